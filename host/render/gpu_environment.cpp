#include "render/gpu_environment.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace whitted {

namespace {

// A CDF of `count` bins with values f[0..count) into cdf[0..count]: the
// running sums over the total, or the uniform steps when the total is 0.
// Returns the total (times the bin width 1 / count: the integral).
double buildCdf(const double* f, size_t count, float* cdf) {
    double sum = 0.0;
    cdf[0] = 0.0f;
    std::vector<double> running(count + 1, 0.0);
    for (size_t i = 0; i < count; ++i) running[i + 1] = sum += f[i];
    for (size_t i = 1; i <= count; ++i)
        cdf[i] = sum > 0.0 ? float(running[i] / sum) : float(double(i) / double(count));
    cdf[count] = 1.0f;
    return sum / double(count);
}

}  // namespace

std::vector<float> environmentDistribution(int width, int height, const std::vector<float>& luminance) {
    size_t w = size_t(width), h = size_t(height);
    std::vector<float> out((h + 1) + h * (w + 1));
    std::vector<double> row(w), rowIntegrals(h);
    for (size_t y = 0; y < h; ++y) {
        double sinTheta = std::sin(std::numbers::pi * (double(y) + 0.5) / double(h));
        for (size_t x = 0; x < w; ++x) {
            float m = 0.0f;
            for (size_t dy = y == 0 ? 0 : y - 1; dy <= std::min(h - 1, y + 1); ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    m = std::max(m, luminance[dy * w + (x + size_t(int(w) + dx)) % w]);
            row[x] = double(m) * sinTheta;
        }
        rowIntegrals[y] = buildCdf(row.data(), w, &out[(h + 1) + y * (w + 1)]);
    }
    buildCdf(rowIntegrals.data(), h, out.data());
    return out;
}

GpuEnvironment packEnvironment(const Scene& scene, std::vector<std::shared_ptr<const TextureData>>& textures) {
    GpuEnvironment g;
    if (!scene.environment) return g;
    const Environment& env = *scene.environment;
    gpu::EnvironmentParams& p = g.params;
    p.intensity = float(env.intensity);
    p.rotation = float(env.rotationDegrees * std::numbers::pi / 180.0);
    p.visible = env.visible ? 1u : 0u;
    p.shadowSamples = uint32_t(env.shadowSamples);
    switch (env.kind) {
        case Environment::Kind::Color:
            p.kind = gpu::kEnvironmentColor;
            p.color = glm::vec3(env.color * env.intensity);
            return g;
        case Environment::Kind::Gradient:
            p.kind = gpu::kEnvironmentGradient;
            p.color = glm::vec3(env.zenith * env.intensity);
            p.horizon = glm::vec3(env.horizon * env.intensity);
            p.ground = glm::vec3(env.ground * env.intensity);
            return g;
        case Environment::Kind::Image: break;
    }
    if (!env.image || env.image->levels.empty()) throw std::runtime_error("the environment has no image");
    if (textures.size() == gpu::kMaxTextures)
        throw std::runtime_error("the scene uses more than " + std::to_string(gpu::kMaxTextures) +
                                 " texture files, the most a render binds");
    p.kind = gpu::kEnvironmentImage;
    p.image = uint32_t(textures.size());
    textures.push_back(env.image);
    const TextureLevel& level = env.image->levels[0];
    p.imageSize = glm::uvec2(uint32_t(level.width), uint32_t(level.height));
    std::vector<float> luminance(size_t(level.width) * size_t(level.height));
    for (size_t i = 0; i < luminance.size(); ++i)
        luminance[i] = 0.2126f * glm::unpackHalf1x16(level.rgba[i * 4]) +
                       0.7152f * glm::unpackHalf1x16(level.rgba[i * 4 + 1]) +
                       0.0722f * glm::unpackHalf1x16(level.rgba[i * 4 + 2]);
    g.distribution = environmentDistribution(level.width, level.height, luminance);
    return g;
}

}  // namespace whitted

#include "io/aov_output.h"

#include "io/image_io.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace whitted {
namespace {

enum class AovKind { Color, Scalar, Depth, Normal };

struct AovSpec {
    AovInfo info;
    AovKind kind;
    uint32_t layer;
    int channel;      // for Scalar
    float pngScale;   // for Scalar: 8-bit value = value * pngScale
};

const std::vector<AovSpec>& aovSpecs() {
    using enum AovKind;
    static const std::vector<AovSpec> specs = {
        {{"ambient", "ambient colour component ka Cd A"}, Color, gpu::kAovAmbient, 0, 1},
        {{"diffuse", "diffuse colour component, all lights"}, Color, gpu::kAovDiffuse, 0, 1},
        {{"specular", "Phong specular colour component, all lights"}, Color, gpu::kAovSpecular, 0, 1},
        {{"reflection", "light arriving by the reflected ray, weighted"}, Color, gpu::kAovReflection, 0, 1},
        {{"transmission", "light arriving by the refracted ray, weighted"}, Color, gpu::kAovTransmission, 0, 1},
        {{"ambient_coef", "ka of the visible surface"}, Scalar, gpu::kAovCoefs0, 0, 1},
        {{"diffuse_coef", "kd of the visible surface"}, Scalar, gpu::kAovCoefs0, 1, 1},
        {{"specular_coef", "ks of the visible surface"}, Scalar, gpu::kAovCoefs0, 2, 1},
        {{"reflection_coef", "kr of the visible surface (black and white)"}, Scalar, gpu::kAovCoefs1, 0, 1},
        {{"transmission_coef", "kt of the visible surface (black and white)"}, Scalar, gpu::kAovCoefs1, 1, 1},
        {{"ior", "index of refraction of the visible surface (8-bit: ior / 3)"}, Scalar, gpu::kAovCoefs1, 2, 1.0f / 3.0f},
        {{"depth", "distance from the eye to the visible surface"}, Depth, gpu::kAovCoefs0, 3, 1},
        {{"normal", "shading normal of the visible surface (8-bit: n / 2 + 0.5)"}, Normal, gpu::kAovNormal, 0, 1},
    };
    return specs;
}

const AovSpec& findSpec(const std::string& name) {
    for (const AovSpec& s : aovSpecs())
        if (name == s.info.name) return s;
    throw std::invalid_argument("unknown auxiliary image '" + name + "'");
}

// The seed's tone mapping: min-max normalisation over all channels, then a
// gamma of 0.667.
void seedTonemap(std::vector<float>& pixels) {
    auto [lo, hi] = std::minmax_element(pixels.begin(), pixels.end());
    float minimum = *lo, range = *hi - *lo;
    for (float& v : pixels) v = range > 0 ? std::pow((v - minimum) / range, 0.667f) : 0.0f;
}

std::vector<float> rgbOf(const std::vector<float>& rgba) {
    std::vector<float> rgb(rgba.size() / 4 * 3);
    for (size_t i = 0, n = rgba.size() / 4; i < n; ++i)
        for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = rgba[i * 4 + c];
    return rgb;
}

void writeColor(const std::filesystem::path& path, const RenderResult& r, const std::vector<float>& rgba, Tonemap tonemap) {
    std::vector<float> rgb = rgbOf(rgba);
    PixelEncoding encoding = PixelEncoding::Srgb8;
    if (!isFloatFormat(path) && tonemap == Tonemap::Seed) {
        seedTonemap(rgb);
        encoding = PixelEncoding::Linear8;
    }
    writeImage(path, r.width, r.height, 3, rgb, encoding);
}

void writeAov(const std::filesystem::path& path, const RenderResult& r, const AovSpec& spec, Tonemap tonemap) {
    const std::vector<float>& layer = r.layers[spec.layer];
    const std::vector<float>& hits = r.layers[gpu::kAovCoefs1];  // w: fraction of samples that hit
    bool isFloat = isFloatFormat(path);
    size_t n = size_t(r.width) * r.height;
    switch (spec.kind) {
        case AovKind::Color:
            writeColor(path, r, layer, tonemap);
            return;
        case AovKind::Scalar: {
            std::vector<float> v(n);
            for (size_t i = 0; i < n; ++i) v[i] = layer[i * 4 + spec.channel] * (isFloat ? 1.0f : spec.pngScale);
            writeImage(path, r.width, r.height, 1, v, PixelEncoding::Linear8);
            return;
        }
        case AovKind::Depth: {
            // Mean distance over the samples that hit; 0 where nothing was
            // hit. 8-bit files map distance d to m / (m + d), m the median
            // distance, so that near is bright and an infinite plane's
            // horizon does not wash the rest out.
            std::vector<float> v(n, 0.0f), distances;
            for (size_t i = 0; i < n; ++i)
                if (hits[i * 4 + 3] > 0) distances.push_back(v[i] = layer[i * 4 + 3] / hits[i * 4 + 3]);
            if (!isFloat && !distances.empty()) {
                std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
                float median = distances[distances.size() / 2];
                for (size_t i = 0; i < n; ++i)
                    if (hits[i * 4 + 3] > 0) v[i] = median / (median + v[i]);
            }
            writeImage(path, r.width, r.height, 1, v, PixelEncoding::Linear8);
            return;
        }
        case AovKind::Normal: {
            std::vector<float> v(n * 3, 0.0f);
            for (size_t i = 0; i < n; ++i) {
                float w = layer[i * 4 + 3];
                if (w <= 0) continue;
                for (int c = 0; c < 3; ++c) {
                    float x = layer[i * 4 + c] / w;
                    v[i * 3 + c] = isFloat ? x : x * 0.5f + 0.5f;
                }
            }
            writeImage(path, r.width, r.height, 3, v, PixelEncoding::Linear8);
            return;
        }
    }
}

}  // namespace

const std::vector<AovInfo>& allAovs() {
    static const std::vector<AovInfo> infos = [] {
        std::vector<AovInfo> v;
        for (const AovSpec& s : aovSpecs()) v.push_back(s.info);
        return v;
    }();
    return infos;
}

std::vector<std::string> parseAovList(const std::string& list) {
    std::vector<std::string> names;
    if (list == "none" || list.empty()) return names;
    if (list == "all") {
        for (const AovInfo& a : allAovs()) names.push_back(a.name);
        return names;
    }
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) {
        findSpec(item);  // throws for an unknown name
        if (std::find(names.begin(), names.end(), item) == names.end()) names.push_back(item);
    }
    return names;
}

std::filesystem::path aovPath(const std::filesystem::path& mainImage, const std::string& aov) {
    return mainImage.parent_path() / (mainImage.stem().string() + "." + aov + mainImage.extension().string());
}

std::vector<std::filesystem::path> writeRenderImages(const RenderResult& result, const std::filesystem::path& mainImage,
                                                     const std::vector<std::string>& aovs, Tonemap tonemap) {
    std::vector<std::filesystem::path> written;
    writeColor(mainImage, result, result.layers[gpu::kAovColor], tonemap);
    written.push_back(mainImage);
    if (!aovs.empty() && !result.hasAuxiliary)
        throw std::logic_error("auxiliary images requested from a render without auxiliary layers");
    for (const std::string& name : aovs) {
        std::filesystem::path path = aovPath(mainImage, name);
        writeAov(path, result, findSpec(name), tonemap);
        written.push_back(path);
    }
    return written;
}

}  // namespace whitted

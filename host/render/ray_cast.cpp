#include "render/ray_cast.h"

#include "ray_cast_types.h"
#include "render/device_policy.h"

#include "cast_rays_comp.h"            // kCastRaysCompSpv, generated from shaders/cast_rays.comp
#include "cast_rays_comp_ray_query.h"  // kCastRaysCompRayQuerySpv: the same with -DWHITTED_RAY_QUERY

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace whitted {
namespace {

static_assert(sizeof(gpu::CastRay) == 32 && offsetof(gpu::CastRay, tMax) == 12 &&
              offsetof(gpu::CastRay, direction) == 16);
static_assert(sizeof(gpu::CastHit) == 32 && offsetof(gpu::CastHit, t) == 12 && offsetof(gpu::CastHit, uv) == 16 &&
              offsetof(gpu::CastHit, object) == 24 && offsetof(gpu::CastHit, primitive) == 28);
static_assert(sizeof(gpu::CastParams) == 32 && offsetof(gpu::CastParams, hitAddress) == 8 &&
              offsetof(gpu::CastParams, count) == 16);

// The farthest distance handed to the shader: kRayInfinity of
// shaders/intersect.glsl, what the tracer's own rays use for "no limit".
constexpr double kFarthest = 3.0e38;

std::string rowText(std::span<const double> values, size_t row) {
    std::ostringstream text;
    text << "(" << values[3 * row] << ", " << values[3 * row + 1] << ", " << values[3 * row + 2] << ")";
    return text.str();
}

glm::dvec3 rowAt(std::span<const double> values, size_t row) {
    return {values[3 * row], values[3 * row + 1], values[3 * row + 2]};
}

glm::uvec2 addressWords(vk::DeviceAddress a) { return {uint32_t(a), uint32_t(a >> 32)}; }

}  // namespace

CameraRay generateCameraRay(const gpu::FrameParams& camera, glm::dvec2 pixel, glm::dvec2 imageSize) {
    glm::dvec2 ndc(2.0 * pixel.x / imageSize.x - 1.0, 1.0 - 2.0 * pixel.y / imageSize.y);
    glm::dvec3 eye(camera.eye), forward(camera.forward), right(camera.right), up(camera.up);
    if (camera.projection == gpu::kProjectionOrthographic) return {eye + ndc.x * right + ndc.y * up, forward};
    return {eye, glm::normalize(forward + ndc.x * right + ndc.y * up)};
}

void checkCastRays(const CastRays& rays) {
    auto bad = [](const std::string& what) { throw std::invalid_argument(what); };
    if (rays.origins.size() % 3 != 0) bad("origins: must hold 3 numbers a ray");
    size_t n = rays.origins.size() / 3;
    if (rays.directions.size() != rays.origins.size())
        bad("directions: " + std::to_string(rays.directions.size() / 3) + " rays, but origins has " +
            std::to_string(n));
    if (rays.tMax.size() != 1 && rays.tMax.size() != n)
        bad("t_max: must be one number or one per ray (" + std::to_string(n) + "), got " +
            std::to_string(rays.tMax.size()));
    // The device computes in float: a number beyond float's range is refused
    // like infinity.
    constexpr double kFloatMax = std::numeric_limits<float>::max();
    for (size_t i = 0; i < n; ++i) {
        glm::dvec3 o = rowAt(rays.origins, i), d = rowAt(rays.directions, i);
        if (!glm::all(glm::lessThanEqual(glm::abs(o), glm::dvec3(kFloatMax))))
            bad("origins: row " + std::to_string(i) + " " + rowText(rays.origins, i) + " is not finite");
        if (!glm::all(glm::lessThanEqual(glm::abs(d), glm::dvec3(kFloatMax))))
            bad("directions: row " + std::to_string(i) + " " + rowText(rays.directions, i) + " is not finite");
        if (d == glm::dvec3(0.0)) bad("directions: row " + std::to_string(i) + " has length 0");
    }
    for (size_t i = 0; i < rays.tMax.size(); ++i)
        if (!(rays.tMax[i] > 0))  // NaN too
            bad("t_max: must be > 0 (inf allowed), got " + std::to_string(rays.tMax[i]) +
                (rays.tMax.size() > 1 ? " for ray " + std::to_string(i) : ""));
}

CastResult RayCaster::cast(const Renderer& renderer, const CastRays& rays) {
    checkCastRays(rays);
    size_t n = rays.origins.size() / 3;
    CastResult result;
    result.t.resize(n);
    result.object.resize(n);
    result.primitive.resize(n);
    result.normal.resize(3 * n);
    result.uv.resize(2 * n);
    if (n == 0) return result;

    // The cast build with the renderer's path and specialization, on a set
    // layout made as the renderer's, so that its descriptor set binds here.
    std::pair<TracePath, Specialization> key{renderer.trace(), renderer.specialization()};
    if (builtFor_ != key) {
        std::span<const uint32_t> spirv = key.first == TracePath::RayQuery
                                              ? std::span<const uint32_t>(kCastRaysCompRayQuerySpv)
                                              : std::span<const uint32_t>(kCastRaysCompSpv);
        pipeline_ = createTracerPipeline(ctx_, spirv, key.first, key.second, sizeof(gpu::CastParams));
        builtFor_ = key;
    }
    size_t bandRays = std::min<size_t>(n, kCastBandRays);
    DeviceActivity activity(*ctx_.events, "casting " + std::to_string(n) + " rays");
    if (rays_.size() < bandRays * sizeof(gpu::CastRay)) {
        rays_ = {};
        hits_ = {};
        constexpr vk::BufferUsageFlags usage =
            vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress;
        rays_ = MirroredBuffer(ctx_, bandRays * sizeof(gpu::CastRay), usage);
        hits_ = MirroredBuffer(ctx_, bandRays * sizeof(gpu::CastHit), usage);
    }

    auto* in = static_cast<gpu::CastRay*>(rays_.host());
    const auto* out = static_cast<const gpu::CastHit*>(hits_.host());
    std::span<const uint32_t> inObject = renderer.primitiveInObject();
    for (size_t first = 0; first < n; first += kCastBandRays) {
        uint32_t count = uint32_t(std::min<size_t>(n - first, kCastBandRays));
        // The shader takes unit directions (as the tracer's rays) and
        // distances along them; the lengths convert tMax and t.
        for (uint32_t k = 0; k < count; ++k) {
            size_t i = first + k;
            glm::dvec3 d = rowAt(rays.directions, i);
            double length = glm::length(d);
            double tMax = rays.tMax[rays.tMax.size() == 1 ? 0 : i];
            in[k] = {.origin = glm::vec3(rowAt(rays.origins, i)),
                     .tMax = float(std::min(tMax * length, kFarthest)),
                     .direction = glm::vec3(d / length)};
        }
        gpu::CastParams params{.rayAddress = addressWords(rays_.device().address),
                               .hitAddress = addressWords(hits_.device().address),
                               .count = count};
        ctx_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
            rays_.recordUpload(cmd, count * sizeof(gpu::CastRay));
            cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_.pipeline);
            cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline_.layout, 0, renderer.descriptorSet(),
                                   nullptr);
            cmd.pushConstants<gpu::CastParams>(*pipeline_.layout, vk::ShaderStageFlagBits::eCompute, 0, params);
            cmd.dispatch((count + gpu::kCastGroupSize - 1) / gpu::kCastGroupSize, 1, 1);
            hits_.recordDownload(cmd, count * sizeof(gpu::CastHit));
            vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eShaderWrite,
                                     .dstAccessMask = vk::AccessFlagBits::eHostRead};
            cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eHost, {},
                                toHost, nullptr, nullptr);
        });
        for (uint32_t k = 0; k < count; ++k) {
            size_t i = first + k;
            const gpu::CastHit& h = out[k];
            // t in units of the direction as given: past float's range for a
            // direction short enough, and then a miss, since infinity means one.
            const float t = float(double(h.t) / glm::length(rowAt(rays.directions, i)));
            if (h.primitive == gpu::kNoObject || std::isinf(t)) {
                result.t[i] = std::numeric_limits<float>::infinity();
                result.object[i] = result.primitive[i] = gpu::kNoObject;
                continue;  // normal and uv stay 0
            }
            result.t[i] = t;
            result.object[i] = h.object;
            result.primitive[i] = inObject[h.primitive];
            for (int c = 0; c < 3; ++c) result.normal[3 * i + c] = h.normal[c];
            result.uv[2 * i] = h.uv.x;
            result.uv[2 * i + 1] = h.uv.y;
        }
    }
    return result;
}

}  // namespace whitted

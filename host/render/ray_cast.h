// Ray casting on the device (Renderer.cast_rays in Python,
// host/python/README.md "Ray casting"): what each of a list of rays hits
// first in a Renderer's uploaded scene, found by the tracer's own
// closest-hit query (shaders/cast_rays.comp calls traceClosest of
// shaders/intersect.glsl: our BVH walk or the device's ray queries, as the
// renderer traces), through the renderer's descriptor set. Rays go to the
// device in bands of at most kCastBandRays, through two buffers kept
// between calls.
#pragma once

#include "device_types.h"
#include "render/renderer.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"
#include "vk/context.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace whitted {

// N rays. A direction need not be unit: t and tMax are in units of the
// direction as given (the point hit is origin + t * direction).
struct CastRays {
    std::span<const double> origins;     // 3N: x, y, z of each ray
    std::span<const double> directions;  // 3N, each of nonzero length
    std::span<const double> tMax;        // 1 (every ray) or N; > 0, infinity allowed
};

// What each ray hits first (the index of a miss: kNoObject, t infinity, the
// rest 0). A hit whose t (in units of the direction) overflows float is a miss.
struct CastResult {
    std::vector<float> t;              // N: the hit at origin + t * direction
    std::vector<uint32_t> object;      // N: the object's index in the scene, the object_id mask's
    std::vector<uint32_t> primitive;   // N: its index among its object's (GpuScene::primitiveInObject)
    std::vector<float> normal;         // 3N: the unit geometric normal, outward (a triangle's: by its winding)
    std::vector<float> uv;             // 2N: the texture coordinates the shader computes there
};

inline constexpr uint32_t kCastBandRays = 1u << 20;

// The tracer's camera ray through the point `pixel` of an image of
// `imageSize`, in its pixel units: origin at the image's top-left corner, x
// right, y down, so pixel (i, j)'s centre is (i + 0.5, j + 0.5), the point
// the object_id mask's ray goes through. `camera`: the fields packCamera
// (render/gpu_scene.h) sets for that size. The C++ twin of
// generateCameraRay (shaders/camera.glsl), in double; the direction is unit.
struct CameraRay {
    glm::dvec3 origin;
    glm::dvec3 direction;
};
CameraRay generateCameraRay(const gpu::FrameParams& camera, glm::dvec2 pixel, glm::dvec2 imageSize);

// Throws std::invalid_argument naming the argument and the ray ("directions:
// row 3 has length 0") unless every number is finite (tMax may be
// infinity), every direction is nonzero, every tMax > 0 and the sizes agree.
void checkCastRays(const CastRays& rays);

class RayCaster {
public:
    explicit RayCaster(VulkanContext& ctx) : ctx_(ctx) {}
    // The rays against `renderer`'s current scene (checkCastRays first).
    CastResult cast(const Renderer& renderer, const CastRays& rays);

private:
    VulkanContext& ctx_;
    MirroredBuffer rays_, hits_;  // one band each, made on first use
    ComputePipeline pipeline_;
    std::optional<std::pair<TracePath, Specialization>> builtFor_;
};

}  // namespace whitted

// Packs the CPU scene into the std430 arrays and uniforms of device_types.h.
#pragma once

#include "accel/bvh.h"
#include "device_types.h"
#include "render/render_settings.h"
#include "scene/scene.h"

#include <vector>

namespace whitted {

struct GpuScene {
    std::vector<gpu::Primitive> primitives;
    std::vector<gpu::Material> materials;
    std::vector<gpu::Light> lights;
    std::vector<gpu::BvhNode> bvhNodes;  // empty: brute force over all primitives
    BvhStats bvhStats;
    gpu::FrameParams params{};
    int width = 0;
    int height = 0;
};

GpuScene packScene(const Scene& scene, const RenderSettings& settings);

}  // namespace whitted

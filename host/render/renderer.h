// Uploads a scene, dispatches the Whitted compute shader tile by tile and
// reads the image and its auxiliary layers back.
#pragma once

#include "device_types.h"
#include "render/gpu_scene.h"
#include "render/render_settings.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"

#include <array>
#include <functional>
#include <vector>

namespace whitted {

struct RayStats {
    uint64_t primary = 0;
    uint64_t shadow = 0;
    uint64_t secondary = 0;
    uint64_t total() const { return primary + shadow + secondary; }
};

// Linear float RGBA layers, averaged over samples, row-major from the top.
struct RenderResult {
    int width = 0;
    int height = 0;
    int samplesPerPixel = 0;
    bool hasAuxiliary = false;
    std::array<std::vector<float>, gpu::kAovCount> layers;  // only kAovColor without auxiliary
    RayStats rays;
    BvhStats bvh;
    double uploadSeconds = 0;  // buffer uploads (the BVH build is bvh.buildSeconds)
    double pipelineSeconds = 0;  // shader compilation by the driver
    double renderSeconds = 0;
    uint64_t deviceBytes = 0;  // every buffer the render allocated on the device
    // Camera samples the driver cut short (a shader run over lavapipe's loop
    // iteration cap, see renderer.cpp): 0 unless the image is incomplete.
    uint64_t lostSamples = 0;
};

// Fraction of the work done so far, in [0, 1].
using ProgressCallback = std::function<void(double)>;

class Renderer {
public:
    Renderer(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings);
    RenderResult render(const ProgressCallback& progress = {});

private:
    struct WorkItem {
        gpu::TileParams tile;
        uint64_t samples;  // pixels x samples, for progress
    };
    std::vector<WorkItem> planWork() const;

    VulkanContext& ctx_;
    RenderSettings settings_;
    GpuScene scene_;
    ComputePipeline pipeline_;
    uint32_t layerCount_;
    Buffer params_, primitives_, materials_, lights_, output_, counters_, bvhNodes_;
    vk::raii::DescriptorPool descriptorPool_{nullptr};
    vk::raii::DescriptorSet descriptorSet_{nullptr};
    double uploadSeconds_ = 0;
    double pipelineSeconds_ = 0;
    uint64_t deviceBytes_ = 0;
};

}  // namespace whitted

// Uploads a scene, dispatches the Whitted compute shader tile by tile and
// reads the image and its auxiliary layers back.
#pragma once

#include "accel/acceleration_structure.h"
#include "device_types.h"
#include "render/adaptive.h"
#include "render/band_sink.h"
#include "render/gpu_scene.h"
#include "render/render_result.h"
#include "render/render_settings.h"
#include "render/texture_set.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"

#include <algorithm>
#include <array>
#include <functional>
#include <vector>

namespace whitted {


// What one scene array may take on the device: its maxBufferSize (Vulkan 1.3
// or VK_KHR_maintenance4) and maxMemoryAllocationSize. The Renderer refuses
// a scene whose arrays exceed them (sceneArraysTooLarge) before packing it.
BufferLimits sceneBufferLimits(const VulkanContext& ctx);

// Fraction of the work done so far, in [0, 1].
using ProgressCallback = std::function<void(double)>;

// The descriptor set asks for more than Vulkan guarantees every device (4
// storage buffers and 16 samplers per stage; desktop GPUs and lavapipe
// offer far more): what a device with these limits lacks, in words ("offers
// 4 storage buffers per shader stage; whitted needs 9"), or "" when it has
// enough. A Renderer refuses such a device before building its pipeline.
std::string descriptorLimitShortfall(const vk::PhysicalDeviceLimits& limits);

class Renderer {
public:
    Renderer(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings);
    // Renders the region band by band into `sink` (rows top to bottom); the
    // result carries the statistics, not the pixels.
    // With bandStep > 1 only bands firstBand, firstBand + bandStep, ... (the
    // share of one of several devices, render/multi_device.h); progress then
    // counts this renderer's share.
    RenderResult renderTo(BandSink& sink, const ProgressCallback& progress = {}, uint32_t firstBand = 0,
                          uint32_t bandStep = 1);
    // The same, with every band kept in the result's layers.
    RenderResult render(const ProgressCallback& progress = {});
    const ImageLayout& layout() const { return layout_; }
    // Rows of the region per band; lowering it (never raising) lets several
    // renderers share one band layout.
    uint32_t bandRows() const { return bandRows_; }
    void limitBandRows(uint32_t rows) { bandRows_ = std::clamp<uint32_t>(rows, 1, bandRows_); }

    // Progressive use (`whitted view`): the output buffer keeps its sums
    // between calls and the caller records the dispatches into its own
    // command buffers. The device must be idle when the scene is replaced.
    // Re-pack and re-upload the scene; the pipeline is rebuilt when the new
    // scene needs shapes or transparency the old one compiled out.
    void setScene(const Scene& scene);
    void setCamera(const Camera& camera);  // rewrites the camera in the uniform block only
    void recordClear(const vk::raii::CommandBuffer& cmd) const;  // zero the sums
    // One dispatch over `tile` (pixels x0, y0, width, height) with samples
    // [first, first + count) of samplesPerPixel, added to the sums of the
    // whole image, after a barrier on earlier ones (split into dispatches of
    // at most 4 samples: lavapipe's loop cap). Needs bandBytes = 0.
    void recordTile(const vk::raii::CommandBuffer& cmd, const gpu::TileParams& tile) const;
    // Reads the sums back as means, each pixel divided by its own sample
    // count (the w of the colour layer), so a partly finished pass reads right.
    RenderResult readMeans() const;
    const Buffer& outputBuffer() const { return output_; }
    gpu::RayCounters& counters() const { return *static_cast<gpu::RayCounters*>(counters_.mapped); }
    int width() const { return scene_.width; }
    int height() const { return scene_.height; }
    uint32_t layerCount() const { return layerCount_; }
    const RenderSettings& settings() const { return settings_; }
    TracePath trace() const { return trace_; }  // Bvh or RayQuery

private:
    class Batch;
    void recordDispatch(const vk::raii::CommandBuffer& cmd, const gpu::TileParams& params, uint32_t groupsX,
                        uint32_t groupsY) const;
    void renderBandUniform(Batch& batch, const PixelRect& band);
    void renderBandAdaptive(Batch& batch, const PixelRect& band);
    void buildPipeline();
    void uploadScene();

    VulkanContext& ctx_;
    RenderSettings settings_;
    GpuScene scene_;  // primitives and bvhNodes emptied once uploaded
    TracePath trace_ = TracePath::Bvh;  // settings_.trace resolved for the device
    SceneAccelerationStructures accelerationStructures_;  // ray queries only
    ComputePipeline pipeline_;
    std::array<uint32_t, 4> specialization_{};  // what pipeline_ was specialised for; [3]: the storage-buffer variant
    uint32_t layerCount_;
    ImageLayout layout_;
    uint32_t bandRows_ = 0;  // rows of the region per band
    Buffer params_, primitives_, materials_, lights_, output_, counters_, bvhNodes_;
    Buffer csgNodes_;  // the csg objects' programs (FrameParams.csgNodeAddress)
    Buffer attributes_;     // gpu::SurfaceAttributes per primitive, when a textured mesh needs them
    TextureSet textures_;   // the kBindingTextures array
    // Adaptive anti-aliasing: pixel list, first-pass guide, sample
    // statistics (host-visible: the host reads and writes them between
    // passes); and the band's read-back staging buffer.
    Buffer pixelList_, guide_, sampleStats_, readback_;
    vk::raii::DescriptorPool descriptorPool_{nullptr};
    vk::raii::DescriptorSet descriptorSet_{nullptr};
    double uploadSeconds_ = 0;
    double pipelineSeconds_ = 0;
    uint64_t deviceBytes_ = 0;
};

}  // namespace whitted

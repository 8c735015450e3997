// Uploads a scene, dispatches the Whitted compute shader tile by tile and
// reads the image and its auxiliary layers back. What depends on the device
// (which tracer build, its specialization, the limits) is decided in
// render/device_policy.h; the band loop of renderTo is render/bands.h.
#pragma once

#include "accel/acceleration_structure.h"
#include "device_types.h"
#include "tracer_types.h"
#include "render/adaptive.h"
#include "render/band_sink.h"
#include "render/bands.h"
#include "render/device_policy.h"
#include "render/gpu_scene.h"
#include "render/render_result.h"
#include "render/render_settings.h"
#include "render/texture_set.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>

namespace whitted {

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
    // scene needs shapes or transparency the old one compiled out. Large
    // meshes get BVH parts of their own, kept for the next setScene: an
    // edit rebuilds the trees of what it changed, the others are reused
    // (render/gpu_scene.h BvhPartCache; RenderResult::bvh says how many).
    void setScene(const Scene& scene);
    // Whether the last upload (the first, or setScene's) sent the textures:
    // setScene keeps those on the device when the new scene uses the same
    // ones (the same TextureData, in the same slots), as after an object moved.
    bool texturesUploaded() const { return texturesUploaded_; }
    void setCamera(const Camera& camera);  // rewrites the camera in the uniform block only
    // Re-uploads the materials only (no BVH, no primitives) when `scene`
    // has the shapes of the uploaded one; false when a new texture or a
    // material count needs setScene. The pipeline is rebuilt when
    // transparency comes or goes.
    bool setMaterials(const Scene& scene);
    // Re-uploads the lights and the ambient light only; the device must be idle.
    void setLights(const Scene& scene);
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
    // The ray counters as the host sees them: zeroed on both sides by
    // recordCountersZero, and brought to the host by recordCountersDownload
    // once the submission is done (vk/buffer.h MirroredBuffer).
    gpu::RayCounters& counters() const { return *static_cast<gpu::RayCounters*>(counters_.host()); }
    void recordCountersZero(const vk::raii::CommandBuffer& cmd) const { counters_.recordZero(cmd); }
    void recordCountersDownload(const vk::raii::CommandBuffer& cmd) const {
        counters_.recordDownload(cmd, sizeof(gpu::RayCounters));
    }
    int width() const { return scene_.width; }
    int height() const { return scene_.height; }
    uint32_t layerCount() const { return layerCount_; }
    const RenderSettings& settings() const { return settings_; }
    TracePath trace() const { return trace_; }  // Bvh or RayQuery
    // What the ray-tree recorder (render/ray_tree.h) runs its build of the
    // tracer with: this renderer's descriptor set and specialization.
    vk::DescriptorSet descriptorSet() const { return *descriptorSet_; }
    const Specialization& specialization() const { return specialization_; }
    // Each uploaded primitive's index among its object's (GpuScene::primitiveInObject).
    std::span<const uint32_t> primitiveInObject() const { return scene_.primitiveInObject; }

private:
    // Specialised for scene_, or with `constants` (and the tracer build kept)
    // when its arrays are already on the device (setMaterials).
    void buildPipeline(std::optional<Specialization> constants = std::nullopt);
    // The pipeline rebuilt (descriptor set unwritten) when an edit of the
    // materials, lights or camera changed the constants that follow them
    // (withShading); whether it was.
    bool respecialize();
    void uploadScene();
    void writeDescriptors();

    VulkanContext& ctx_;
    RenderSettings settings_;
    GpuScene scene_;  // primitives and bvhNodes emptied once uploaded
    BvhPartCache bvhParts_;  // setScene's (the BVH path's only)
    TracePath trace_ = TracePath::Bvh;  // settings_.trace resolved for the device
    SceneAccelerationStructures accelerationStructures_;  // ray queries only
    ComputePipeline pipeline_;
    ShaderVariant shaderVariant_ = ShaderVariant::Addresses;  // the tracer build pipeline_ runs
    Specialization specialization_{};  // the specialization constants pipeline_ was built with
    uint32_t layerCount_;
    ImageLayout layout_;
    uint32_t bandRows_ = 0;  // rows of the region per band
    Buffer params_, primitives_, materials_, lights_, output_, bvhNodes_;
    MirroredBuffer counters_;  // gpu::RayCounters
    Buffer csgNodes_;  // the csg objects' programs (FrameParams.csgNodeAddress)
    Buffer environmentDistribution_;  // an image environment's (FrameParams.environment.distributionAddress)
    Buffer instances_;      // gpu::InstanceRecord per instance (FrameParams.instanceAddress), when the scene has any
    Buffer attributes_;     // gpu::SurfaceAttributes per primitive, when a textured mesh needs them
    TextureSet textures_;   // the kBindingTextures array
    // What textures_ holds (kept alive, so a pointer compares as the texture),
    // whether it was made at all, and whether the last upload made it.
    std::vector<std::shared_ptr<const TextureData>> uploadedTextures_;
    bool texturesMade_ = false, texturesUploaded_ = false;
    // Adaptive anti-aliasing: pixel list, first-pass guide, sample
    // statistics (the host reads and writes them between passes); and the
    // band's read-back staging buffer.
    MirroredBuffer pixelList_, guide_, sampleStats_;
    Buffer readback_;
    vk::raii::DescriptorPool descriptorPool_{nullptr};
    vk::raii::DescriptorSet descriptorSet_{nullptr};
    double uploadSeconds_ = 0;
    double pipelineSeconds_ = 0;
    uint64_t deviceBytes_ = 0;
};

}  // namespace whitted

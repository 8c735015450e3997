// The band loop of a render (Renderer::renderTo): each band of whole rows of
// the region traced tile by tile, or pass by pass with adaptive
// anti-aliasing, its sums read back as means and handed to a BandSink.
#pragma once

#include "tracer_types.h"
#include "render/band_sink.h"
#include "render/render_result.h"
#include "render/render_settings.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"
#include "vk/context.h"

#include <cstdint>
#include <functional>

namespace whitted {

// Fraction of the work done so far, in [0, 1].
using ProgressCallback = std::function<void(double)>;

// At most this many samples of a pixel in one dispatch. llvmpipe (lavapipe)
// caps the loop iterations of one shader run at 65535, counted over ALL its
// loops together (LP_MAX_TGSI_LOOP_ITERATIONS in Mesa's gallivm), then ends
// every loop silently: 16 samples of a pixel seen through a lattice of
// 10,000 spheres overran it and lost whole samples. Fewer samples per
// dispatch keep each run far below the cap; the band loop checks the count
// of camera rays and reports any that are still cut off.
inline constexpr uint32_t kMaxSamplesPerInvocation = 4;

// One dispatch of the tracer with `params` as its push constants, after a
// barrier on the shader, transfer and host writes before it (dispatches
// accumulate into the same sums). The pipeline and its descriptor set must
// be bound.
void recordDispatch(const vk::raii::CommandBuffer& cmd, const ComputePipeline& pipeline, const gpu::TileParams& params,
                    uint32_t groupsX, uint32_t groupsY);

// What the band loop uses of a Renderer, borrowed for one render.
struct BandResources {
    const VulkanContext& ctx;
    const RenderSettings& settings;
    const ComputePipeline& pipeline;
    vk::DescriptorSet descriptorSet;
    int imageWidth = 0;  // the full image: the adaptive passes' borders stop at its edges
    int imageHeight = 0;
    const ImageLayout& layout;
    uint32_t bandRows = 0;  // rows of the region per band
    const Buffer& output;    // one band's sums, every layer (device-local)
    const Buffer& readback;  // host-visible, as large as output
    // What the shader writes or reads at every sample and the host reads or
    // writes between submissions (device-local, vk/buffer.h MirroredBuffer):
    // gpu::RayCounters; adaptive anti-aliasing's pixel list, first-pass
    // guide, sample statistics.
    const MirroredBuffer& counters;
    const MirroredBuffer& pixelList;
    const MirroredBuffer& guide;
    const MirroredBuffer& sampleStats;
};

// Renders bands firstBand, firstBand + bandStep, ... of the region into
// `sink`, top to bottom; progress gets the fraction of these bands done
// after every submission to the queue (it may throw to stop the render
// there). The result has the image's size and layout, the samples and rays
// counted and the bands written; no pixels and no timings.
RenderResult renderBands(const BandResources& parts, BandSink& sink, const ProgressCallback& progress,
                         uint32_t firstBand, uint32_t bandStep);

// Keeps every band in a RenderResult's layers and sample counts, sized for
// result.layout when made.
class MemorySink final : public BandSink {
public:
    explicit MemorySink(RenderResult& result);
    void writeBand(const BandView& band) override;

private:
    RenderResult& result_;
};

}  // namespace whitted

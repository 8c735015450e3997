#include "render/bands.h"

#include "render/adaptive.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace whitted {
namespace {

constexpr uint32_t kTileSize = 128;

// Dispatches recorded into one command buffer and submission, at most.
constexpr size_t kDispatchesPerSubmit = 4;
// A submission that runs longer than this halves the dispatches of the next
// ones (one far shorter doubles them again, up to kDispatchesPerSubmit), so
// that progress (and with it Ctrl+C in Python) comes several times
// a second even where one sample costs much.
constexpr std::chrono::milliseconds kSubmitTarget{250};

// The fraction of this render's bands done, reported after every
// submission (not only after every band), so that a progress bar moves and
// a callback that stops the render (Python's Ctrl+C) runs within one
// submission's time. A band is worked through in stages whose camera
// samples are known when they start: the uniform band is one stage; the
// adaptive band a first pass and one stage per refinement level.
class Progress {
public:
    Progress(const ProgressCallback& callback, uint32_t bands) : callback_(callback), bands_(std::max(bands, 1u)) {}

    // The next `samples` camera samples take the band from `from` to `to`.
    void stage(double from, double to, uint64_t samples) {
        from_ = from;
        to_ = to;
        stageSamples_ = std::max<uint64_t>(samples, 1);
        stageDone_ = 0;
    }

    // After a submission that traced `samples` camera samples. The band's
    // end is reported by bandDone, after its pixels reached the sink.
    void submitted(uint64_t samples) {
        if (samples == 0) return;
        stageDone_ += samples;
        double inBand = from_ + (to_ - from_) * std::min(1.0, double(stageDone_) / double(stageSamples_));
        if (inBand < 1.0) report(inBand);
    }

    void bandDone() {
        ++bandsDone_;
        report(0.0);
    }

private:
    void report(double inBand) const {
        if (callback_) callback_(std::min(1.0, (double(bandsDone_) + inBand) / double(bands_)));
    }

    const ProgressCallback& callback_;
    uint32_t bands_;
    uint32_t bandsDone_ = 0;
    double from_ = 0.0, to_ = 1.0;
    uint64_t stageSamples_ = 1, stageDone_ = 0;
};

// Dispatches go to the queue in batches of kDispatchesPerSubmit, each after
// a barrier (later dispatches may accumulate into the same pixels); the ray
// counters are read, and the camera rays checked, once per batch, and the
// progress is reported after it. Buffers the host shares with the shader
// (render/bands.h) travel by the copies MirroredBuffer records, where the
// device does not work in host memory.
class Batch {
public:
    // A buffer of the host's to read after the next submission.
    struct Download {
        const MirroredBuffer& buffer;
        vk::DeviceSize bytes;
    };

    Batch(const BandResources& parts, RenderResult& result, Progress& progress)
        : parts_(parts), result_(result), progress_(progress),
          commandPool_(parts.ctx.device, vk::CommandPoolCreateInfo{.flags = vk::CommandPoolCreateFlagBits::eTransient,
                                                                   .queueFamilyIndex = parts.ctx.queueFamily}),
          commandBuffers_(parts.ctx.device, {.commandPool = *commandPool_,
                                             .level = vk::CommandBufferLevel::ePrimary, .commandBufferCount = 1}),
          fence_(parts.ctx.device, vk::FenceCreateInfo{}) {}

    // The host's first `bytes` of `buffer` to the device before the next dispatch.
    void upload(const MirroredBuffer& buffer, vk::DeviceSize bytes) {
        begin();
        buffer.recordUpload(commandBuffers_.front(), bytes);
    }

    // One dispatch; `cameraSamples` = pixels x samples it traces.
    void add(const gpu::TileParams& params, uint32_t groupsX, uint32_t groupsY, uint64_t cameraSamples) {
        vk::raii::CommandBuffer& cmd = commandBuffers_.front();
        begin();
        if (recorded_ == 0) {
            cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *parts_.pipeline.pipeline);
            cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *parts_.pipeline.layout, 0, parts_.descriptorSet,
                                   nullptr);
        }
        recordDispatch(cmd, parts_.pipeline, params, groupsX, groupsY);
        expected_ += cameraSamples;
        if (++recorded_ == dispatchesPerSubmit_) flush();
    }

    // Submits what is recorded, with `copyBand` bytes of the output buffer
    // copied to the read-back buffer and `downloads` to the host after it,
    // and waits.
    void flush(vk::DeviceSize copyBand = 0, std::initializer_list<Download> downloads = {}) {
        vk::raii::CommandBuffer& cmd = commandBuffers_.front();
        if (!open_ && copyBand == 0 && downloads.size() == 0) return;
        begin();
        if (copyBand > 0) {
            vk::MemoryBarrier toCopy{.srcAccessMask = vk::AccessFlagBits::eShaderWrite,
                                     .dstAccessMask = vk::AccessFlagBits::eTransferRead};
            cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eTransfer, {},
                                toCopy, nullptr, nullptr);
            cmd.copyBuffer(*parts_.output.buffer, *parts_.readback.buffer, vk::BufferCopy{0, 0, copyBand});
        }
        parts_.counters.recordDownload(cmd, sizeof(gpu::RayCounters));
        for (const Download& d : downloads) d.buffer.recordDownload(cmd, d.bytes);
        vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eHostRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                            vk::PipelineStageFlagBits::eHost, {}, toHost, nullptr, nullptr);
        cmd.end();
        open_ = false;
        vk::CommandBuffer raw = *cmd;
        auto submitted = std::chrono::steady_clock::now();
        parts_.ctx.submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &raw}, *fence_);
        parts_.ctx.waitForFence(*fence_);
        parts_.ctx.device.resetFences(*fence_);
        // Fewer dispatches after a long submission, more again after short
        // ones: lavapipe compiles the pipeline during the first submission.
        auto took = std::chrono::steady_clock::now() - submitted;
        if (took > kSubmitTarget && recorded_ > 1)
            dispatchesPerSubmit_ = std::max<size_t>(1, recorded_ / 2);
        else if (took < kSubmitTarget / 4 && recorded_ == dispatchesPerSubmit_)
            dispatchesPerSubmit_ = std::min(kDispatchesPerSubmit, 2 * dispatchesPerSubmit_);

        // One camera ray per sample: fewer means the driver cut a run short.
        const auto* counters = static_cast<const gpu::RayCounters*>(parts_.counters.host());
        if (counters->primary < expected_) result_.lostSamples += expected_ - counters->primary;
        result_.rays.primary += counters->primary;
        result_.rays.shadow += counters->shadow;
        result_.rays.secondary += counters->secondary;
        result_.samplesTaken += expected_;
        uint64_t traced = expected_;
        recorded_ = 0;
        expected_ = 0;
        progress_.submitted(traced);  // last: it may throw to stop the render
    }

private:
    // A fresh command buffer, unless one is open, and ray counters zeroed for it.
    void begin() {
        if (open_) return;
        vk::raii::CommandBuffer& cmd = commandBuffers_.front();
        commandPool_.reset();  // the whole pool: cheaper than one buffer's reset on some drivers
        cmd.begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
        parts_.counters.recordZero(cmd);
        open_ = true;
    }

    const BandResources& parts_;
    RenderResult& result_;
    Progress& progress_;
    vk::raii::CommandPool commandPool_;  // the batch's own, reset whole before each submission
    vk::raii::CommandBuffers commandBuffers_;
    vk::raii::Fence fence_;
    bool open_ = false;
    size_t recorded_ = 0;
    size_t dispatchesPerSubmit_ = kDispatchesPerSubmit;
    uint64_t expected_ = 0;
};

// Tiles of at most kTileSize^2 pixels covering `rect`.
template <typename F>
void forEachTile(const PixelRect& rect, F&& f) {
    for (uint32_t y = 0; y < rect.height; y += kTileSize)
        for (uint32_t x = 0; x < rect.width; x += kTileSize)
            f(PixelRect{rect.x0 + x, rect.y0 + y, std::min(kTileSize, rect.width - x), std::min(kTileSize, rect.height - y)});
}

glm::uvec2 originOf(const PixelRect& r) { return {r.x0, r.y0}; }
glm::uvec2 sizeOf(const PixelRect& r) { return {r.width, r.height}; }

uint32_t groupsFor(uint32_t n) { return (n + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize; }

// Every pixel of the band takes samples [0, spp) of the spp pattern, in
// dispatches of at most samplesPerDispatch camera samples and
// kMaxSamplesPerInvocation samples a pixel; the first replaces the band
// buffer's old sums. Sample indices are global, so the split changes only
// the grouping, never which samples are traced or the order they are added.
void renderBandUniform(const BandResources& parts, Batch& batch, Progress& progress, const PixelRect& band) {
    const RenderSettings& settings = parts.settings;
    uint32_t spp = uint32_t(settings.samplesPerPixel);
    progress.stage(0.0, 1.0, uint64_t(band.width) * band.height * spp);
    forEachTile(band, [&](const PixelRect& tile) {
        uint64_t pixels = uint64_t(tile.width) * tile.height;
        uint32_t chunk = uint32_t(std::clamp<uint64_t>(std::max<uint64_t>(settings.samplesPerDispatch, 1) / pixels, 1, spp));
        chunk = std::min(chunk, kMaxSamplesPerInvocation);
        for (uint32_t s = 0; s < spp; s += chunk) {
            uint32_t n = std::min(chunk, spp - s);
            gpu::TileParams params{.tileOrigin = originOf(tile),
                                   .tileSize = sizeOf(tile),
                                   .firstSample = s,
                                   .sampleCount = n,
                                   .patternSize = spp,
                                   .flags = s == 0 ? gpu::kTileOverwrite : 0u,
                                   .outputOrigin = originOf(band),
                                   .outputSize = sizeOf(band)};
            batch.add(params, groupsFor(tile.width), groupsFor(tile.height), pixels * n);
        }
    });
}

// Adaptive anti-aliasing (render/adaptive.h): the centre sample of every
// pixel of the band and of its one-pixel border (the border only feeds the
// guide), then refinement passes over the pixels that need them.
void renderBandAdaptive(const BandResources& parts, Batch& batch, Progress& progress, const PixelRect& band) {
    const RenderSettings& settings = parts.settings;
    // Level k's pixels are decided on the band grown by L - k + 1 pixels
    // (L levels), from level k - 1's samples one pixel further out: each
    // level is traced in a border one pixel narrower, down to the band.
    std::vector<uint32_t> levels = refinementLevels(uint32_t(settings.samplesPerPixel));
    uint32_t border = uint32_t(levels.size());
    uint32_t width = uint32_t(parts.imageWidth), height = uint32_t(parts.imageHeight);
    PixelRect guideRect = grow(band, border, width, height);
    double stages = double(levels.size() + 1);
    progress.stage(0.0, 1.0 / stages, uint64_t(guideRect.width) * guideRect.height);
    forEachTile(guideRect, [&](const PixelRect& tile) {
        gpu::TileParams params{.tileOrigin = originOf(tile),
                               .tileSize = sizeOf(tile),
                               .firstSample = 0,
                               .sampleCount = 1,
                               .patternSize = 1,
                               .flags = gpu::kTileOverwrite | gpu::kTileGuide,
                               .outputOrigin = originOf(band),
                               .outputSize = sizeOf(band),
                               .guideOrigin = originOf(guideRect),
                               .guideSize = sizeOf(guideRect)};
        batch.add(params, groupsFor(tile.width), groupsFor(tile.height), uint64_t(tile.width) * tile.height);
    });
    size_t guidePixels = size_t(guideRect.width) * guideRect.height;
    if (levels.empty()) {
        batch.flush();
        return;
    }
    batch.flush(0, {{parts.guide, guidePixels * sizeof(glm::uvec4)}});
    std::vector<uint32_t> list = pixelsToRefine(
        std::span(static_cast<const glm::uvec4*>(parts.guide.host()), guidePixels),
        guideRect, grow(band, border - 1, width, height), settings.aaThreshold);

    for (size_t level = 0; level < levels.size() && !list.empty(); ++level) {
        uint32_t n = levels[level];
        progress.stage(double(level + 1) / stages, double(level + 2) / stages, uint64_t(list.size()) * n);
        std::memcpy(parts.pixelList.host(), list.data(), list.size() * sizeof(uint32_t));
        batch.upload(parts.pixelList, list.size() * sizeof(uint32_t));
        // Slices of the list small enough for samplesPerDispatch.
        uint32_t chunk = std::min(n, kMaxSamplesPerInvocation);
        uint32_t slice = uint32_t(std::max<uint64_t>(settings.samplesPerDispatch / chunk, gpu::kListGroupSize));
        for (uint32_t first = 0; first < list.size(); first += slice) {
            uint32_t count = std::min<uint32_t>(slice, uint32_t(list.size()) - first);
            for (uint32_t s = 0; s < n; s += chunk) {
                uint32_t k = std::min(chunk, n - s);
                uint32_t flags = gpu::kTileList | gpu::kTileStats | (s == 0 ? gpu::kTileOverwrite : 0u);
                gpu::TileParams params{.firstSample = s,
                                       .sampleCount = k,
                                       .patternSize = n,
                                       .flags = flags,
                                       .outputOrigin = originOf(band),
                                       .outputSize = sizeOf(band),
                                       .listFirst = first,
                                       .listCount = count};
                batch.add(params, (count + gpu::kListGroupSize - 1) / gpu::kListGroupSize, 1, uint64_t(count) * k);
            }
        }
        if (level + 1 == levels.size()) {
            batch.flush();
            break;
        }
        batch.flush(0, {{parts.sampleStats, 2 * list.size() * sizeof(glm::uvec4)}});
        list = pixelsStillVarying(list,
                                  std::span(static_cast<const glm::uvec4*>(parts.sampleStats.host()), 2 * list.size()),
                                  settings.aaThreshold, grow(band, border - 2 - uint32_t(level), width, height));
    }
}

}  // namespace

void recordDispatch(const vk::raii::CommandBuffer& cmd, const ComputePipeline& pipeline, const gpu::TileParams& params,
                    uint32_t groupsX, uint32_t groupsY) {
    vk::MemoryBarrier accumulate{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite |
                                                  vk::AccessFlagBits::eHostWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer |
                            vk::PipelineStageFlagBits::eHost,
                        vk::PipelineStageFlagBits::eComputeShader, {}, accumulate, nullptr, nullptr);
    cmd.pushConstants<gpu::TileParams>(*pipeline.layout, vk::ShaderStageFlagBits::eCompute, 0, params);
    cmd.dispatch(groupsX, groupsY, 1);
}

RenderResult renderBands(const BandResources& parts, BandSink& sink, const ProgressCallback& progress,
                         uint32_t firstBand, uint32_t bandStep) {
    const ImageLayout& layout = parts.layout;
    RenderResult result;
    result.width = layout.region.width();
    result.height = layout.region.height();
    result.samplesPerPixel = parts.settings.samplesPerPixel;
    result.hasAuxiliary = parts.settings.auxiliary;
    result.layout = layout;

    const PixelRegion& region = layout.region;
    uint32_t bandRows = parts.bandRows, layerCount = layout.layerCount;
    std::vector<float> counts;
    uint32_t bandCount = (uint32_t(region.height()) + bandRows - 1) / bandRows;
    uint32_t mine = firstBand < bandCount ? (bandCount - firstBand + bandStep - 1) / bandStep : 0;
    Progress done(progress, mine);
    Batch batch(parts, result, done);
    for (uint32_t index = firstBand; index < bandCount; index += bandStep) {
        int y = region.y0 + int(index * bandRows);
        PixelRect band{uint32_t(region.x0), uint32_t(y), uint32_t(region.width()),
                       uint32_t(std::min<int>(int(bandRows), region.y1 - y))};
        DeviceActivity activity(*parts.ctx.events,
                                "rendering band " + std::to_string(index + 1) + " of " + std::to_string(bandCount));
        if (parts.settings.antiAliasing == AntiAliasing::Adaptive)
            renderBandAdaptive(parts, batch, done, band);
        else
            renderBandUniform(parts, batch, done, band);
        size_t pixels = size_t(band.width) * band.height;
        batch.flush(vk::DeviceSize(layerCount) * pixels * sizeof(glm::vec4));

        // Sums to means: every layer of a pixel over the samples it took
        // (w of its colour layer); the hit-mask layers average the same way,
        // the id layer's uint bits stay as they are.
        // In place, in the mapped read-back buffer: no host copy of the band.
        float* raw = static_cast<float*>(parts.readback.mapped);
        counts.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) counts[i] = raw[i * 4 + 3];
        for (uint32_t layer = 0; layer < std::min(layerCount, layout.idLayer()); ++layer)
            for (size_t i = 0; i < pixels; ++i) {
                float inverse = counts[i] > 0 ? 1.0f / counts[i] : 0.0f;
                for (int c = 0; c < 4; ++c) raw[(layer * pixels + i) * 4 + c] *= inverse;
            }
        std::span<const float> means(raw, size_t(layerCount) * pixels * 4);
        sink.writeBand({.index = int(index), .y0 = y, .rows = int(band.height), .width = int(band.width), .layers = means,
                        .sampleCounts = counts});
        ++result.bands;
        done.bandDone();
    }
    return result;
}

MemorySink::MemorySink(RenderResult& result) : result_(result) {
    size_t pixels = size_t(result.layout.region.width()) * result.layout.region.height();
    result_.layers.resize(std::max(gpu::kAovCount, result.layout.layerCount));
    for (uint32_t l = 0; l < result.layout.layerCount; ++l) result_.layers[l].resize(pixels * 4);
    result_.sampleCounts.resize(pixels);
}

void MemorySink::writeBand(const BandView& band) {
    size_t offset = size_t(band.y0 - result_.layout.region.y0) * band.width;
    for (uint32_t l = 0; l < result_.layout.layerCount; ++l) {
        std::span<const float> from = band.layer(l);
        std::copy(from.begin(), from.end(), result_.layers[l].begin() + offset * 4);
    }
    std::copy(band.sampleCounts.begin(), band.sampleCounts.end(), result_.sampleCounts.begin() + offset);
}

}  // namespace whitted

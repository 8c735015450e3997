// What a render gives back: its layers and its statistics, in plain values
// (no Vulkan), so that the output writers and the command layer need not
// include the renderer.
#pragma once

#include "accel/bvh.h"
#include "device_types.h"
#include "render/band_sink.h"
#include "render/render_settings.h"

#include <cstdint>
#include <vector>

namespace whitted {

struct RayStats {
    uint64_t primary = 0;
    uint64_t shadow = 0;
    uint64_t secondary = 0;
    uint64_t total() const { return primary + shadow + secondary; }
};

// Linear float RGBA layers, averaged over samples, row-major from the top.
// width x height is the region rendered (the whole image unless
// RenderSettings::region says otherwise).
struct RenderResult {
    int width = 0;
    int height = 0;
    int samplesPerPixel = 0;  // uniform: every pixel's count; adaptive: the maximum
    bool hasAuxiliary = false;
    // Filled by Renderer::render; empty after renderTo (the sink had them).
    // At least gpu::kAovCount entries (the ones not rendered empty); more
    // with split reflection/transmission layers (RenderSettings::aovBounces).
    // Only kAovColor is filled without auxiliary layers.
    std::vector<std::vector<float>> layers = std::vector<std::vector<float>>(gpu::kAovCount);
    std::vector<float> sampleCounts;  // samples each pixel took
    ImageLayout layout;
    uint64_t samplesTaken = 0;  // camera samples over all pixels
    int bands = 0;              // bands of rows the region was rendered in
    RayStats rays;
    BvhStats bvh;
    TracePath trace = TracePath::Bvh;  // the path taken (never Auto)
    double accelerationStructureSeconds = 0;  // ray queries: building the device's structures (within upload)
    double uploadSeconds = 0;  // buffer uploads (the BVH build is bvh.buildSeconds)
    double pipelineSeconds = 0;  // shader compilation by the driver
    double renderSeconds = 0;
    uint64_t deviceBytes = 0;  // every buffer the render allocated on the device
    // Camera samples the driver cut short (a shader run over lavapipe's loop
    // iteration cap, render/bands.h): 0 unless the image is incomplete.
    uint64_t lostSamples = 0;
};

}  // namespace whitted

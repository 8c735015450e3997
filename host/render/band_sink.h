// Where a render's pixels go: the renderer hands over one band of whole rows
// of the region at a time, top to bottom, as soon as it is done, so neither
// device nor host memory grows with the image (output/aov_output.h streams
// bands into files; Renderer::render keeps them in memory).
#pragma once

#include "device_types.h"
#include "render/render_settings.h"

#include <cstdint>
#include <span>

namespace whitted {

// The image a render produces: a region of a full image, and its layers.
struct ImageLayout {
    int fullWidth = 0;
    int fullHeight = 0;
    PixelRegion region;       // the pixels rendered, within the full image
    uint32_t layerCount = 1;  // gpu::kAovCount (+ 2 per split bounce, + 1 with ids) with auxiliary layers, else 1
    bool ids = false;         // the last layer is the id layer (gpu::kOptionWriteIds): uint bits, not means
    // The scene has an environment: a pixel whose samples all left the scene sees it at an infinite
    // distance (depth infinity in float files; without one, depth 0 there).
    bool environment = false;
    // The id layer's index, or layerCount (none).
    uint32_t idLayer() const { return ids ? layerCount - 1 : layerCount; }
};

// One band: rows [y0, y0 + rows) of the region, every column of it.
struct BandView {
    int index = 0;  // bands are numbered from 0, top to bottom
    int y0 = 0;     // image row of the band's first row
    int rows = 0;
    int width = 0;  // the region's width
    // Means over each pixel's samples, [layer][row][column][rgba]; the
    // colour layers' w is 1 where the pixel took samples. The id layer
    // (ImageLayout::idLayer) holds uint bits instead.
    std::span<const float> layers;
    // Samples each pixel took, [row][column].
    std::span<const float> sampleCounts;

    std::span<const float> layer(uint32_t l) const {
        size_t n = size_t(rows) * width * 4;
        return layers.subspan(l * n, n);
    }
};

class BandSink {
public:
    virtual ~BandSink() = default;
    virtual void writeBand(const BandView& band) = 0;
};

}  // namespace whitted

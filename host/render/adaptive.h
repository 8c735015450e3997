// Adaptive anti-aliasing after Whitted (1980): every pixel first takes one
// sample through its centre; a pixel whose colour differs from a neighbour's
// by more than a threshold, or that sees another object, is refined with a
// stratified pattern of 4 samples, then 16, 64, ... (each level's pattern
// replaces the one before) for as long as its own samples still disagree,
// up to the maximum. POV-Ray's +AM2 is the same idea on a sub-pixel grid.
//
// A refined pixel goes on while its own samples disagree, or while a
// neighbour's do (an edge that cuts only a corner of a pixel can leave all
// 4 of its samples on one side; its neighbour across the edge sees both).
// Every decision depends on samples within a few pixels, which a band, a
// region or a farm tile traces in a border around itself (outputs dropped),
// so each decides exactly as a full render does.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace whitted {

// Pattern sizes after the centre sample: 4, 16, 64, ... below maxSamples,
// then maxSamples itself. maxSamples 1 gives none.
std::vector<uint32_t> refinementLevels(uint32_t maxSamples);

// A rectangle of pixels in image coordinates.
struct PixelRect {
    uint32_t x0 = 0, y0 = 0, width = 0, height = 0;
};

// Pixels of `output` to refine after the first pass. `guide` holds, for
// every pixel of `guideRect` (which must contain `output` and each of its
// pixels' neighbours that lie in the image), the centre sample's display
// colour bits and object id (gpu::kBindingGuide). Returned as x | y << 16,
// row by row.
std::vector<uint32_t> pixelsToRefine(std::span<const glm::uvec4> guide, const PixelRect& guideRect,
                                     const PixelRect& output, float threshold);

// The entries of `list` inside `next` that go on to the next level: those
// whose samples (gpu::kBindingSampleStats, two per entry) still disagree, or
// one of whose 8 neighbours' do.
std::vector<uint32_t> pixelsStillVarying(std::span<const uint32_t> list, std::span<const glm::uvec4> stats,
                                         float threshold, const PixelRect& next);

// `rect` grown by `border` pixels on every side, within a width x height image.
PixelRect grow(const PixelRect& rect, uint32_t border, uint32_t width, uint32_t height);

}  // namespace whitted

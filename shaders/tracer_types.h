// GPU data layout of the tracer (shaders/whitted.comp), shared by the C++ host
// and GLSL as device_types.h, whose core it builds on.
#ifndef WHITTED_TRACER_TYPES_H
#define WHITTED_TRACER_TYPES_H
#include "device_types.h"

#ifdef __cplusplus
namespace whitted::gpu {
#endif

// The tracer's bindings, per-dispatch constants and counters (shaders/whitted.comp,
// host/render/renderer.cpp): what a dispatch of tiles or of a pixel list
// reads and writes besides the scene.
WHITTED_CONST uint kBindingOutput = 4;    // vec4[kAovCount * TileParams.outputSize pixels]
WHITTED_CONST uint kBindingCounters = 5;  // RayCounters
// Adaptive anti-aliasing (host/render/adaptive.*): the pixels a refinement
// pass traces, the first pass's per-pixel guide, per-entry sample statistics.
WHITTED_CONST uint kBindingPixelList = 7;   // uint[]: x | y << 16
WHITTED_CONST uint kBindingGuide = 8;       // uvec4[] over TileParams.guideSize: display colour bits, object id
WHITTED_CONST uint kBindingSampleStats = 9; // uvec4[2 * entries]: min colour bits + object, max colour bits + mixed

// The auxiliary outputs a render may ask for (FrameParams.options & (kOptionWriteAovs | kOptionWriteIds)), so that
// a render without them compiles none of their code (shaders/whitted.comp; unset: all of them).
WHITTED_CONST uint kSpecOutputOptions = 3;

// TileParams.flags bits.
WHITTED_CONST uint kTileList = 1u;       // pixels from the pixel list (listFirst, listCount)
WHITTED_CONST uint kTileOverwrite = 2u;  // replace the pixels' sums (and statistics) instead of adding
WHITTED_CONST uint kTileGuide = 4u;      // write the guide (colour, object) of each pixel
WHITTED_CONST uint kTileStats = 8u;      // write the sample statistics of each list entry

// Entries of the pixel list traced by one work group in list mode.
WHITTED_CONST uint kListGroupSize = kWorkgroupSize * kWorkgroupSize;

// Per-dispatch constants (push constants): which pixels, which samples of
// which pattern, and where the output layers and guide sit in the image.
struct TileParams {
    uvec2 tileOrigin WHITTED_ZERO;    // rect mode: the first pixel of the tile
    uvec2 tileSize WHITTED_ZERO;      // rect mode: its width and height
    uint firstSample WHITTED_ZERO;    // index of the first sample
    uint sampleCount WHITTED_ZERO;
    uint patternSize WHITTED_ZERO;    // n of the n x n sample pattern
    uint flags WHITTED_ZERO;          // kTile* bits
    uvec2 outputOrigin WHITTED_ZERO;  // the first pixel of the pixels the output layers hold
    uvec2 outputSize WHITTED_ZERO;    // their width and height
    uvec2 guideOrigin WHITTED_ZERO;   // likewise for the guide
    uvec2 guideSize WHITTED_ZERO;
    uint listFirst WHITTED_ZERO;      // list mode: the first entry of the pixel list and the count
    uint listCount WHITTED_ZERO;
    // The ray-tree build (-DWHITTED_RAY_TREE, shaders/ray_tree.glsl) only:
    // the device address of the RayTreeRecord it fills; unread otherwise.
    uvec2 rayTreeAddress WHITTED_ZERO;
};

// Rays traced, counted by the shader (reset before each dispatch).
struct RayCounters {
    uint primary WHITTED_ZERO;
    uint shadow WHITTED_ZERO;
    uint secondary WHITTED_ZERO;
    uint pad WHITTED_ZERO;
};

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#endif

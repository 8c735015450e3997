// GPU data layout of the live window's display pass (whitted view,
// shaders/display.comp), shared by the C++ host and GLSL as device_types.h.
#ifndef WHITTED_DISPLAY_TYPES_H
#define WHITTED_DISPLAY_TYPES_H
#include "device_types.h"

#ifdef __cplusplus
namespace whitted::gpu {
#endif

// Bindings of the display pass: the renderer's output sums in, packed RGBA8 out.
WHITTED_CONST uint kBindingDisplayInput = 0;   // vec4[] sums, as kBindingOutput
WHITTED_CONST uint kBindingDisplayOutput = 1;  // uint[width * height], RGBA8

// What the display pass shows (DisplayParams.kind), like output/aov_output.
WHITTED_CONST uint kDisplayColor = 0;   // a colour layer: mean, clamp, sRGB
WHITTED_CONST uint kDisplayScalar = 1;  // one channel's mean times scalarScale
WHITTED_CONST uint kDisplayDepth = 2;   // m / (m + d), m = depthMedian
WHITTED_CONST uint kDisplayNormal = 3;  // n / 2 + 0.5
WHITTED_CONST uint kDisplayId = 4;      // the id in channel `channel` of the id layer, as idColorRgb8

// Push constants of the display pass.
struct DisplayParams {
    uint kind WHITTED_ZERO;     // kDisplay*
    uint layer WHITTED_ZERO;    // the output layer shown (kAov*)
    uint channel WHITTED_ZERO;  // kDisplayScalar: its channel
    uint pad0 WHITTED_ZERO;
    uint width WHITTED_ZERO;
    uint height WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
    uint pad2 WHITTED_ZERO;
    float scalarScale WHITTED_ZERO;
    float depthMedian WHITTED_ZERO;
    float exposure WHITTED_ZERO;  // kDisplayColor: the mean is scaled by 2^exposure before encoding (--exposure)
    float pad4 WHITTED_ZERO;
};

// The colour of a mask id in 8-bit files and the window: a fixed hash of the
// id (hashPcg), each channel in 64..255 so that no object is as black as the
// background (kNoObject). Packed r | g << 8 | b << 16.
WHITTED_FUNCTION uint idColorRgb8(uint id) {
    if (id == kNoObject) return 0u;
    return (hashPcg(id) & 0xbfbfbfu) + 0x404040u;
}

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#endif

#version 460
// The live window's display pass: turns the renderer's per-pixel sums into
// the 8-bit image shown, one invocation per pixel. Every pixel is divided by
// its own sample count (the w of the colour layer), so a pass that is only
// partly done shows right. Colour layers are clamped and sRGB-encoded
// (color.glsl) exactly as io/image_io.cpp writes PNG files; the data
// layers follow output/aov_output.cpp.
#extension GL_GOOGLE_include_directive : require

#include "display_types.h"
#include "color.glsl"

layout(local_size_x = kWorkgroupSize, local_size_y = kWorkgroupSize, local_size_z = 1) in;

layout(std430, binding = kBindingDisplayInput) readonly buffer Sums { vec4 sums[]; };
layout(std430, binding = kBindingDisplayOutput) writeonly buffer Pixels { uint pixels[]; };
layout(push_constant) uniform Push { DisplayParams display; };

uint packRgba8(vec3 v) {
    uvec3 b = uvec3(round(clamp(v, 0.0, 1.0) * 255.0));
    return b.r | (b.g << 8) | (b.b << 16) | (255u << 24);
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uint width = display.width, height = display.height;
    if (pixel.x >= width || pixel.y >= height) return;
    uint index = pixel.y * width + pixel.x;
    uint count = width * height;
    float samples = sums[kAovColor * count + index].w;
    vec4 s = sums[display.layer * count + index];
    vec3 shown = vec3(0.0);
    if (display.kind == kDisplayId) {  // uint bits, written once (not sums)
        uint rgb = samples > 0.0 ? idColorRgb8(floatBitsToUint(s[display.channel])) : 0u;
        pixels[index] = rgb | (255u << 24);
        return;
    }
    if (samples > 0.0) {
        if (display.kind == kDisplayColor) {
            vec3 mean = s.rgb / samples * exp2(display.exposure);
            shown = linearToSrgb(mean);
        } else if (display.kind == kDisplayScalar) {
            shown = vec3(s[display.channel] / samples * display.scalarScale);
        } else if (display.kind == kDisplayDepth) {
            float hits = sums[kAovCoefs1 * count + index].w;
            if (hits > 0.0) {
                float d = s.w / hits;
                shown = vec3(display.depthMedian / (display.depthMedian + d));
            }
        } else if (s.w > 0.0) {
            shown = s.xyz / s.w * 0.5 + 0.5;
        }
    }
    pixels[index] = packRgba8(shown);
}

// The sRGB transfer curve (IEC 61966-2-1), both ways: decoding, an
// sRGB-encoded value in [0, 1] to linear light (what texture files and a
// model file's raw embedded texels are decoded with); encoding, linear
// light clamped to [0, 1] to its sRGB value (what 8-bit images are written
// with).
#pragma once

#include <algorithm>
#include <cmath>

namespace whitted {

inline float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

inline float linearToSrgb(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace whitted

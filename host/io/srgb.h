// The sRGB transfer curve (IEC 61966-2-1), decoding: an sRGB-encoded value
// in [0, 1] to linear light. What texture files and a model file's raw
// embedded texels are decoded with.
#pragma once

#include <cmath>

namespace whitted {

inline float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace whitted

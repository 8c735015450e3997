// Packing the scene's environment (scene/environment.h) for the tracer:
// EnvironmentParams, its image's slot among the textures, and the image's
// importance-sampling distribution (shaders/environment.glsl).
#pragma once

#include "device_types.h"
#include "io/texture.h"
#include "scene/scene.h"

#include <memory>
#include <vector>

namespace whitted {

struct GpuEnvironment {
    gpu::EnvironmentParams params{};  // kind kEnvironmentNone without an environment
    // An image environment's distribution (EnvironmentParams's layout),
    // empty for the other kinds.
    std::vector<float> distribution;
};

// `textures` gets the image, when there is one, as its next slot.
GpuEnvironment packEnvironment(const Scene& scene, std::vector<std::shared_ptr<const TextureData>>& textures);

// The importance-sampling distribution of a width x height image whose
// texel (x, y) (rows from the top) has luminance luminance[y * width + x]:
// pbrt-v4's PiecewiseConstant2D (Pharr, Jakob and Humphreys, "Physically
// Based Rendering", 4th ed., 12.5.3 and A.5) over f = luminance x sin theta,
// theta the polar angle of the row's centre, so that directions are drawn in
// proportion to the light they bring per solid angle. Each texel's f takes
// the largest luminance of the texel and its eight neighbours (wrapping
// across the left and right edges), because the device filters the image
// bilinearly: wherever a lookup is not zero the density is not either, and
// the estimate stays unbiased. An image that is black everywhere gets the
// uniform distribution. Layout: the marginal CDF over the rows (height + 1
// values, from 0 to 1), then each row's conditional CDF over its columns
// (width + 1 values a row).
std::vector<float> environmentDistribution(int width, int height, const std::vector<float>& luminance);

}  // namespace whitted

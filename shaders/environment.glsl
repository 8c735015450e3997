// The world around the scene (scenes/README.md "Environment"): what a ray that leaves the scene sees, and the
// directions its light is sampled along. Compiled in only for a scene with an <environment>
// (kHasEnvironment, kHasEnvironmentLight: material.glsl).
#ifndef WHITTED_ENVIRONMENT_GLSL
#define WHITTED_ENVIRONMENT_GLSL
#include "sampling.glsl"
#include "texture.glsl"

const float kEnvironmentPi = 3.14159265358979;

// dir turned by `angle` radians about +y, counter-clockwise seen from above (+z towards +x), as
// host/scene/environment.cpp turnedAboutUp.
vec3 turnedAboutUp(vec3 dir, float angle) {
    float c = cos(angle), s = sin(angle);
    return vec3(c * dir.x + s * dir.z, dir.y, -s * dir.x + c * dir.z);
}

// The equirectangular image's coordinates of world direction dir (unit): u across from the left edge, t down
// from the top row; the image's centre looks along -z, u = 0.75 along +x, the top row along +y, before the
// rotation turns it (host/scene/environment.h environmentUv).
vec2 environmentUv(vec3 dir) {
    vec3 d = turnedAboutUp(dir, -params.environment.rotation);
    float u = 0.5 + atan(d.x, -d.z) * (0.5 / kEnvironmentPi);
    float t = acos(clamp(d.y, -1.0, 1.0)) * (1.0 / kEnvironmentPi);
    return vec2(u, t);
}

// Its inverse: the world direction of image coordinates (u, t) (environmentDirection on the host).
vec3 environmentDirection(vec2 uv) {
    float theta = uv.y * kEnvironmentPi, phi = (uv.x - 0.5) * 2.0 * kEnvironmentPi;
    float sinTheta = sin(theta);
    return turnedAboutUp(vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi)), params.environment.rotation);
}

// The radiance arriving along -dir from direction dir (unit). A gradient is linear in dir.y: the horizon's
// colour at 0, the zenith's at +1, the ground's at -1. An image is read bilinearly at its full resolution
// (u wraps around; t is clamped to the centres of the first and last rows, so the poles do not blend with
// the opposite edge).
vec3 environmentRadiance(vec3 dir) {
    uint kind = params.environment.kind;
    if (kind == kEnvironmentColor) return params.environment.color;
    if (kind == kEnvironmentGradient) {
        return dir.y >= 0.0 ? mix(params.environment.horizon, params.environment.color, dir.y)
                            : mix(params.environment.horizon, params.environment.ground, -dir.y);
    }
#ifndef WHITTED_NO_TEXTURES  // an image environment is a texture: never the build without them
    vec2 uv = environmentUv(dir);
    float halfRow = 0.5 / float(params.environment.imageSize.y);
    uv.y = clamp(uv.y, halfRow, 1.0 - halfRow);
    uint slot = params.environment.image;
    return textureLod(textures[nonuniformEXT(slot)], uv, 0.0).rgb * params.environment.intensity;
#else
    return vec3(0.0);
#endif
}

// The image's distribution (device_types.h EnvironmentParams): the marginal CDF over the rows, then each
// row's conditional CDF over its columns.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer EnvironmentCdfArray { float v[]; };
#define environmentCdf (EnvironmentCdfArray(params.environment.distributionAddress).v)

// A draw from the piecewise-constant 1D distribution whose CDF is environmentCdf[base .. base + n] (n bins):
// the bin i with cdf[i] <= x < cdf[i + 1] (binary search, pbrt-v4's FindInterval), the position in [0, 1)
// and the density there (the bin's probability times n). pbrt-v4 PiecewiseConstant1D::Sample.
float sampleEnvironmentCdf(uint base, uint n, float x, out float density, out uint bin) {
    uint first = 1u, size = n - 1u;  // search cdf[1 .. n - 1] for the last entry <= x
    while (size > 0u) {
        uint halfSize = size >> 1, middle = first + halfSize;
        if (environmentCdf[base + middle] <= x) {
            first = middle + 1u;
            size -= halfSize + 1u;
        } else {
            size = halfSize;
        }
    }
    bin = min(first - 1u, n - 1u);
    float lo = environmentCdf[base + bin], hi = environmentCdf[base + bin + 1u];
    density = (hi - lo) * float(n);
    float within = hi > lo ? (x - lo) / (hi - lo) : 0.5;
    return (float(bin) + clamp(within, 0.0, 0.99999994)) / float(n);
}

// A direction l for the environment's light at a point of shading normal n, from u uniform in [0, 1)^2, and
// what it brings there per unit of the Phong formula's N.L: radiance(l) / (pi pdf(l)), so that the sum over
// samples of that times (kd Cd N.L + ks Cs (R.V)^e) estimates (1 / pi) times the integral over directions of
// radiance times (kd Cd N.L + ks Cs (R.V)^e): the formula of a point light, each solid angle dw of the
// environment a point light of colour radiance dw / pi (scenes/README.md "Environment light"). An image is
// importance-sampled by its distribution (pbrt-v4's ImageInfiniteLight: luminance x sin theta; the density
// per solid angle is the image's p(u, t) / (2 pi^2 sin theta), Pharr, Jakob and Humphreys 4th ed. 12.5.3);
// a colour or a gradient by the cosine about n (pdf N.L / pi). False when the draw has no density.
bool sampleEnvironmentLight(vec3 n, vec2 u, out vec3 l, out vec3 weight) {
    weight = vec3(0.0);
    if (params.environment.kind != kEnvironmentImage) {
        l = samplePhongLobe(n, 1.0, u);
        float cosine = dot(l, n);
        if (cosine <= 0.0) return false;
        weight = environmentRadiance(l) / cosine;
        return true;
    }
    uint width = params.environment.imageSize.x, height = params.environment.imageSize.y;
    float rowDensity, columnDensity;
    uint row, column;
    float t = sampleEnvironmentCdf(0u, height, u.y, rowDensity, row);
    float s = sampleEnvironmentCdf(height + 1u + row * (width + 1u), width, u.x, columnDensity, column);
    l = environmentDirection(vec2(s, t));
    float sinTheta = sin(t * kEnvironmentPi);
    float pdf = rowDensity * columnDensity / (2.0 * kEnvironmentPi * kEnvironmentPi * max(sinTheta, 1e-7));
    if (!(pdf > 0.0)) return false;
    weight = environmentRadiance(l) / (kEnvironmentPi * pdf);
    return true;
}

#endif

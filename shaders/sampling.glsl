// Stratified sample positions inside a pixel.
#ifndef WHITTED_SAMPLING_GLSL
#define WHITTED_SAMPLING_GLSL

#include "device_types.h"  // hashPcg, which turns a pixel index into a pattern seed

// Hash-based permutation of [0, l) and uniform float from "Correlated
// Multi-Jittered Sampling", Kensler, Pixar Technical Memo 13-01 (2013).
uint cmjPermute(uint i, uint l, uint p) {
    uint w = l - 1u;
    w |= w >> 1; w |= w >> 2; w |= w >> 4; w |= w >> 8; w |= w >> 16;
    do {
        i ^= p; i *= 0xe170893du; i ^= p >> 16; i ^= (i & w) >> 4;
        i ^= p >> 8; i *= 0x0929eb3fu; i ^= p >> 23; i ^= (i & w) >> 1;
        i *= 1u | p >> 27; i *= 0x6935fa69u; i ^= (i & w) >> 11;
        i *= 0x74dcb303u; i ^= (i & w) >> 2; i *= 0x9e501cc3u;
        i ^= (i & w) >> 2; i *= 0xc860a3dfu; i &= w; i ^= i >> 5;
    } while (i >= l);
    return (i + p) % l;
}

float cmjRandFloat(uint i, uint p) {
    i ^= p; i ^= i >> 17; i ^= i >> 10; i *= 0xb36534e5u; i ^= i >> 12;
    i ^= i >> 21; i *= 0x93fc4795u; i ^= 0xdf6e307fu; i ^= i >> 17;
    i *= 1u | p >> 18;
    return float(i) * (1.0 / 4294967808.0);
}

// Sample s of n in the unit square, jittered within an m x ceil(n/m) grid
// and correlated so that both 1D projections are stratified too (Kensler
// 2013, listing 5). p decorrelates pixels.
vec2 cmjSample(uint s, uint n, uint p) {
    uint m = uint(sqrt(float(n)));
    uint rows = (n + m - 1u) / m;
    s = cmjPermute(s, n, p * 0x51633e2du);
    uint sx = cmjPermute(s % m, m, p * 0x68bc21ebu);
    uint sy = cmjPermute(s / m, rows, p * 0x02e5be93u);
    float jx = cmjRandFloat(s, p * 0x967a889bu);
    float jy = cmjRandFloat(s, p * 0x368cc8b7u);
    return vec2((float(sx) + (float(sy) + jx) / float(rows)) / float(m), (float(s) + jy) / float(n));
}

// Dimension `dimension` (>= 1) of sample s of n: an independent correlated multi-jittered pattern per dimension
// (Kensler 2013), so lens, light and lobe samples are stratified with the pixel's samples and adaptive
// refinement refines them too. Dimension 0 is the pixel position (pixelSampleOffset).
vec2 sampleDimension(uint s, uint n, uint pixelSeed, uint dimension) {
    return cmjSample(s, n, hashPcg(pixelSeed ^ (dimension * 0x9e3779b9u)));
}

// The dimensions of sampleDimension: the lens; the lobe of a glossy bounce at ray depth d, kDimLobeBase + d
// (d < 14); light i's shadow samples, kDimLightBase + i (with <shadow_samples> N > 1, sample k of N of camera
// sample s is cmjSample(s * N + k, n * N, hashPcg(pixelSeed ^ ((kDimLightBase + i) * 0x9e3779b9u)))).
const uint kDimLens = 1u;
const uint kDimLobeBase = 2u;
const uint kDimLightBase = 16u;

// The distribution effects the scene has (device_types.h kSpecDistribution): a scene without a lens, gloss or
// area lights compiles none of their sampling (host/render/device_policy.cpp specializationFor).
layout(constant_id = kSpecDistribution) const uint kDistribution =
    kDistributionLens | kDistributionGloss | kDistributionAreaLights;
const bool kHasLens = (kDistribution & kDistributionLens) != 0u;
const bool kHasGloss = (kDistribution & kDistributionGloss) != 0u;
const bool kHasAreaLights = (kDistribution & kDistributionAreaLights) != 0u;

// Pixel-space offset of sample s; a single sample goes through the centre so
// that spp 1 matches a classic one-ray-per-pixel render.
vec2 pixelSampleOffset(uint s, uint n, uint pixelSeed) {
    if (n == 1u) return vec2(0.5);
    return cmjSample(s, n, pixelSeed);
}

// A point of the unit disc from u in [0, 1)^2 by the concentric mapping
// (Shirley and Chiu 1997, "A low distortion map between disk and square";
// pbrt-v4 SampleUniformDiskConcentric): squares map to rings, so the
// pattern's strata stay compact on the disc.
vec2 sampleDiskConcentric(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    const float kPiOver4 = 0.78539816339744831;
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = kPiOver4 * (o.y / o.x);
    } else {
        r = o.y;
        theta = 2.0 * kPiOver4 - kPiOver4 * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

// A direction about the unit axis w with density proportional to
// cos^e of its angle to w (the Phong lobe, sampled as Lafortune and Willems
// 1994: cos theta = u.x^(1 / (e + 1)), phi = 2 pi u.y), in the orthonormal
// basis of Duff et al. 2017 ("Building an orthonormal basis, revisited").
vec3 samplePhongLobe(vec3 w, float e, vec2 u) {
    float cosTheta = pow(u.x, 1.0 / (e + 1.0));
    float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
    float phi = 6.28318530717958648 * u.y;
    float sign = w.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign + w.z);
    float b = w.x * w.y * a;
    vec3 t = vec3(1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x);
    vec3 bt = vec3(b, sign + w.y * w.y * a, -w.y);
    return normalize(sinTheta * (cos(phi) * t + sin(phi) * bt) + cosTheta * w);
}

#endif

// Material properties that vary over a surface.
#ifndef WHITTED_MATERIAL_GLSL
#define WHITTED_MATERIAL_GLSL

// The shading features the scene has (device_types.h kSpecFeatures): what a scene lacks compiles out, as the
// shapes it lacks do (host/render/device_policy.cpp specializationFor).
layout(constant_id = kSpecFeatures) const uint kFeatures = kFeatureAll;
const bool kHasFresnel = (kFeatures & kFeatureFresnel) != 0u;
const bool kHasAbsorption = (kFeatures & kFeatureAbsorption) != 0u;
const bool kHasChecker = (kFeatures & kFeatureChecker) != 0u;
const bool kHasSmoothTriangles = (kFeatures & kFeatureSmoothTriangles) != 0u;
const bool kHasSpotLights = (kFeatures & kFeatureSpotLights) != 0u;
const bool kHasDirectionalLights = (kFeatures & kFeatureDirectionalLights) != 0u;
const bool kHasFalloff = (kFeatures & kFeatureFalloff) != 0u;
const bool kHasEnvironment = (kFeatures & kFeatureEnvironment) != 0u;
const bool kHasEnvironmentLight = (kFeatures & kFeatureEnvironmentLight) != 0u;

// The colour Cd at surface point p: the diffuse colour, or with a solid
// checker (cell size S > 0) the checker colour in the cells
// whose coordinates floor((p - origin) / S + 0.001) have an odd sum. This
// is POV-Ray's checker pattern scaled by S, its tolerance included, so a
// face lying on a cell boundary (a box's min-corner faces) falls wholly in
// the cells above it instead of speckling.
vec3 pigment(vec3 diffuse, vec3 checkerColor, float checkerSize, vec3 origin, vec3 p) {
    if (!kHasChecker || checkerSize <= 0.0) return diffuse;
    vec3 cell = floor((p - origin) / checkerSize + 0.001);
    bool odd = fract((cell.x + cell.y + cell.z) * 0.5) > 0.25;
    return odd ? checkerColor : diffuse;
}

#endif

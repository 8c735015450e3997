// Local Phong shading at a hit point (scenes/scenes/README.md, "Shading model").
#ifndef WHITTED_SHADING_GLSL
#define WHITTED_SHADING_GLSL
#include "environment.glsl"
#include "intersect.glsl"
#include "sampling.glsl"

struct LocalShading {
    vec3 ambient;
    vec3 diffuse;
    vec3 specular;
    uint shadowRays;
};

#ifdef WHITTED_RAY_TREE  // the ray-tree recorder's build (shaders/ray_tree.glsl)
#include "ray_tree.glsl"
#endif

// A point on area light `light` (an index into lights) for the shaded point
// p, from u uniform in [0, 1)^2. A rectangle: uniform over its area
// (position + (u.x - 1/2) u + (u.y - 1/2) v). A sphere: pbrt-v4's
// Sphere::Sample (Pharr, Jakob and Humphreys, 4th ed., 6.2.4): the direction
// uniform in the cone of directions the sphere fills as seen from p (small
// cones through the Taylor expansion of sin^2 theta there), and the point
// where it meets the sphere's near side; from inside the sphere, uniform
// over its surface.
vec3 sampleLightPoint(uint light, vec3 p, vec2 u) {
    vec3 centre = lights[light].position;
    if (lights[light].type == kLightRect)
        return centre + (u.x - 0.5) * lights[light].u + (u.y - 0.5) * lights[light].v;
    const float kTwoPi = 6.28318530718;
    float phi = kTwoPi * u.y;
    vec3 toCentre = centre - p;
    float r = lights[light].radius, dist2 = dot(toCentre, toCentre);
    if (dist2 <= r * r) {
        float z = 1.0 - 2.0 * u.x, rho = sqrt(max(0.0, 1.0 - z * z));
        return centre + r * vec3(rho * cos(phi), rho * sin(phi), z);
    }
    float sinThetaMax = r / sqrt(dist2), sin2ThetaMax = sinThetaMax * sinThetaMax;
    float cosThetaMax = sqrt(max(0.0, 1.0 - sin2ThetaMax));
    float cosTheta = (cosThetaMax - 1.0) * u.x + 1.0;
    float sin2Theta = 1.0 - cosTheta * cosTheta;
    if (sin2ThetaMax < 0.00068523) {  // sin^2(1.5 degrees)
        sin2Theta = sin2ThetaMax * u.x;
        cosTheta = sqrt(1.0 - sin2Theta);
    }
    // The angle alpha at the centre between -wc and the point (law of sines).
    float cosAlpha = sin2Theta / sinThetaMax + cosTheta * sqrt(max(0.0, 1.0 - sin2Theta / sin2ThetaMax));
    float sinAlpha = sqrt(max(0.0, 1.0 - cosAlpha * cosAlpha));
    // An orthonormal frame about wc (Duff et al., "Building an Orthonormal
    // Basis, Revisited", JCGT 2017).
    vec3 wc = toCentre / sqrt(dist2);
    float sign = wc.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign + wc.z), b = wc.x * wc.y * a;
    vec3 x = vec3(1.0 + sign * wc.x * wc.x * a, sign * b, -sign * wc.x);
    vec3 y = vec3(b, sign + wc.y * wc.y * a, -wc.y);
    vec3 normal = -(sinAlpha * cos(phi) * x + sinAlpha * sin(phi) * y + cosAlpha * wc);
    return centre + r * normal;
}

// Ambient ka Ca A (Ca the material's ambient colour, Cd without one) plus,
// per light, its visibility (shadow ray) times its arriving light E times
// kd Cd max(N.L, 0) + ks Cs max(R.V, 0)^shininess. E is the light's colour
// (times intensity), over d^2 with inverse-square falloff, times a spot's
// cone factor saturate((cos theta - cos outer) / (cos inner - cos outer))^2
// (the KHR_lights_punctual formula); a directional light comes from -its
// direction, its shadow ray running to infinity. n is the shading normal,
// ng the geometric one; both face the viewer and p is already offset to the
// viewer's side of the surface. A light behind the geometric surface gives
// nothing even where the shading normal leans towards it.
// An area light (a sphere of radius > 0, a rectangle; Cook, Porter and
// Carpenter 1984, "Distributed ray tracing") is N = shadowSamples point
// lights of E / N at points sampled on it (sampleLightPoint), E's falloff and
// cone measured from its centre; L, N.L and R.V are each sample's. Sample k
// of camera sample `sampleIndex` of n is sampleDimension(sampleIndex N + k, n N,
// pixelSeed, kDimLightBase + i), so adaptive refinement refines penumbras.
// A rect light gives nothing to points behind its face (u x v) unless it is
// two-sided.
//
// The sum over lights and their samples is a walk: nextShadowRay hands out
// the next sample's shadow ray, traceSamples (whitted.comp) traces it
// through the same call of traceQuery as the ray that hit, and
// addShadowedLight adds what it lets through, so the BVH walk is compiled
// once.

// Where the walk over a hit's light samples stands.
struct LightWalk {
    uint light;      // the light whose samples are walked
    uint taken;      // its samples handed out so far; 0: the light is set up first
    uint count;      // its number of samples
    bool area;       // an area light: each sample draws a point on it
    vec3 l;          // a point or directional light: the unit direction to it
    float dist;      // and the shadow ray's length
    vec3 radiance;   // what each sample brings unshadowed
};

// A shadow ray handed out by nextShadowRay and the terms its light adds,
// times its visibility.
struct ShadowQuery {
    Ray ray;
    float dist;
    uint light;
    vec3 radiance;
    float nDotL;
    float highlight;  // max(R.V, 0)^shininess (0 when ks is 0)
};

LocalShading startShading(Material m, out LightWalk walk) {
    LocalShading s;
    vec3 ambientColor = (m.flags & kMaterialAmbientColor) != 0u ? m.ambientColor : m.diffuse;
    s.ambient = m.ka * ambientColor * params.ambientLight;
    s.diffuse = vec3(0.0);
    s.specular = vec3(0.0);
    s.shadowRays = 0u;
    walk.light = 0u;
    walk.taken = 0u;
    walk.count = 0u;
    walk.area = false;
    walk.l = vec3(0.0);
    walk.dist = 0.0;
    walk.radiance = vec3(0.0);
    return s;
}

// Adds the light of shadow ray q, which lets `visibility` through, to s.
void addShadowedLight(inout LocalShading s, Material m, ShadowQuery q, vec3 visibility) {
    if (all(equal(visibility, vec3(0.0)))) return;
    vec3 light = visibility * q.radiance;
    s.diffuse += light * m.kd * m.diffuse * q.nDotL;
    if (m.ks > 0.0) s.specular += light * m.ks * m.specular * q.highlight;
}

// The environment's light, after the scene's lights (walk.light == lightCount): its shadow_samples N
// directions of camera sample `sampleIndex` of n are samples sampleIndex N + k of a pattern of n N of
// dimension kDimLightBase + lightCount (as a light of that index would be), drawn by
// sampleEnvironmentLight; each brings radiance(l) / (pi pdf(l) N) per unit of the Phong formula, and its
// shadow ray runs to infinity. False when its samples are done.
bool nextEnvironmentRay(inout LocalShading s, inout LightWalk w, Material m, vec3 p, vec3 n, vec3 ng, vec3 viewDir,
                        uint sampleIndex, uint patternSize, uint pixelSeed, out ShadowQuery q) {
    uint count = params.environment.shadowSamples;
    while (w.taken < count) {
        uint k = w.taken++;
        vec2 u = sampleDimension(sampleIndex * count + k, patternSize * count, pixelSeed,
                                 kDimLightBase + params.lightCount);
        vec3 l, weight;
        if (!sampleEnvironmentLight(n, u, l, weight)) continue;
        float nDotL = dot(n, l);
        if (nDotL <= 0.0 || dot(ng, l) <= 0.0 || all(equal(weight, vec3(0.0)))) continue;
        s.shadowRays += 1u;
        q.ray = Ray(p, l);
        q.dist = kRayInfinity;
        q.light = params.lightCount;
        q.radiance = weight / float(count);
        q.nDotL = nDotL;
        q.highlight = m.ks > 0.0 ? pow(max(dot(reflect(-l, n), viewDir), 0.0), m.shininess) : 0.0;
        return true;
    }
    return false;
}

// The next light sample of the walk that needs a shadow ray (one in front
// of both normals), as q; false when the walk is done. Counts the shadow
// rays in s.
bool nextShadowRay(inout LocalShading s, inout LightWalk w, Material m, vec3 p, vec3 n, vec3 ng, vec3 viewDir,
                   uint sampleIndex, uint patternSize, uint pixelSeed, out ShadowQuery q) {
    uint lightCount = params.lightCount;
#ifdef WHITTED_PROFILE_NO_LIGHTS  // tools/profile_shader.sh: ambient only, no light loop
    lightCount = 0u;
#endif
    bool lit = m.kd > 0.0 || m.ks > 0.0;
    if (!lit) lightCount = 0u;
    while (w.light < lightCount) {
        uint i = w.light;
        if (w.taken == 0u) {
            uint type = lights[i].type;
            vec3 l;
            float dist;
            float attenuation = 1.0;
            if (kHasDirectionalLights && type == kLightDirectional) {
                l = -lights[i].direction;
                dist = kRayInfinity;
            } else {
                vec3 toLight = lights[i].position - p;
                dist = length(toLight);
                l = toLight / dist;
                if (kHasFalloff && lights[i].falloff == kFalloffInverseSquare) attenuation = 1.0 / (dist * dist);
                if (kHasSpotLights && type == kLightSpot) {
                    float cosOuter = lights[i].cosOuter;
                    float cone = clamp((dot(-l, lights[i].direction) - cosOuter) / (lights[i].cosInner - cosOuter),
                                       0.0, 1.0);
                    attenuation *= cone * cone;
                }
            }
            bool behindRect = kHasAreaLights && type == kLightRect && lights[i].twoSided == 0u &&
                              dot(l, cross(lights[i].u, lights[i].v)) >= 0.0;
            if (attenuation <= 0.0 || behindRect) {
                ++w.light;
                continue;
            }
            // A point or directional light keeps l and dist and draws no sample.
            w.area = kHasAreaLights && (type == kLightRect || lights[i].radius > 0.0);
            w.count = w.area ? lights[i].shadowSamples : 1u;
            w.radiance = lights[i].color * (w.area ? attenuation / float(w.count) : attenuation);
            w.l = l;
            w.dist = dist;
        }
        uint k = w.taken;
        if (++w.taken >= w.count) {
            ++w.light;
            w.taken = 0u;
        }
        if (k >= w.count) continue;  // a light of no samples
        vec3 l = w.l;
        float dist = w.dist;
        if (w.area) {
            vec2 u = sampleDimension(sampleIndex * w.count + k, patternSize * w.count, pixelSeed, kDimLightBase + i);
            vec3 toPoint = sampleLightPoint(i, p, u) - p;
            dist = length(toPoint);
            l = toPoint / dist;
        }
        float nDotL = dot(n, l);
        if (nDotL <= 0.0 || dot(ng, l) <= 0.0) continue;
        s.shadowRays += 1u;
        q.ray = Ray(p, l);
        q.dist = dist;
        q.light = i;
        q.radiance = w.radiance;
        q.nDotL = nDotL;
        q.highlight = m.ks > 0.0 ? pow(max(dot(reflect(-l, n), viewDir), 0.0), m.shininess) : 0.0;
#ifdef WHITTED_PROFILE_NO_SHADOWS  // tools/profile_shader.sh: what shadow rays cost
        addShadowedLight(s, m, q, vec3(1.0));
        continue;
#endif
        return true;
    }
    if (kHasEnvironmentLight && lit)
        return nextEnvironmentRay(s, w, m, p, n, ng, viewDir, sampleIndex, patternSize, pixelSeed, q);
    return false;
}

// The direction of a glossy reflected or refracted ray: drawn from the Phong lobe of exponent e about the ideal
// direction (Lafortune and Willems 1994, sampling.glsl samplePhongLobe). A draw that falls on the wrong side of
// the surface (whose normal towards the side the ray must leave on is `side`) is mirrored about the surface
// plane back into it: the lobe is folded, not cut, so its weight stays the ideal ray's and no light is lost or
// gained.
vec3 glossyDirection(vec3 ideal, vec3 side, float e, vec2 u) {
    vec3 d = samplePhongLobe(ideal, e, u);
    float below = dot(d, side);
    return below < 0.0 ? d - 2.0 * below * side : d;
}

#endif

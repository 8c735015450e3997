// Scene intersection: nearest hit for camera and secondary rays, and the
// filtered transmittance of shadow rays. Brute force over all primitives.
#ifndef WHITTED_INTERSECT_GLSL
#define WHITTED_INTERSECT_GLSL
#include "scene.glsl"
#include "shapes/primitive.glsl"

// Nearest hit in (0, tMax).
bool traceClosest(Ray ray, float tMax, out Hit hit) {
    hit.t = tMax;
    hit.normal = vec3(0.0);
    hit.primitive = 0xffffffffu;
    uint count = params.sizes.z;
    for (uint i = 0u; i < count; ++i) {
        vec3 n;
        if (intersectPrimitive(primitives[i], ray, 0.0, hit.t, n)) {
            hit.normal = n;
            hit.primitive = i;
        }
    }
    return hit.primitive != 0xffffffffu;
}

// Light that reaches the end of a shadow ray of length tMax. An opaque
// surface blocks it; every crossing of a transparent surface (kt > 0)
// filters it by kt * mix(white, Cd, kd), so shadows take the colour of glass
// as in the seed. Each surface crossing counts, so a glass sphere filters
// twice (in and out), the same as a closed glass mesh.
vec3 shadowTransmittance(Ray ray, float tMax) {
    vec3 transmittance = vec3(1.0);
    uint count = params.sizes.z;
    for (uint i = 0u; i < count; ++i) {
        Primitive prim = primitives[i];
        float tFrom = 0.0;
        // A primitive is convex or flat: at most two crossings.
        for (int crossing = 0; crossing < 2; ++crossing) {
            float t = tMax;
            vec3 n;
            if (!intersectPrimitive(prim, ray, tFrom, t, n)) break;
            Material m = materials[prim.info.y];
            float kt = m.coefs1.y;
            if (kt <= 0.0) return vec3(0.0);
            transmittance *= kt * mix(vec3(1.0), m.diffuse.rgb, m.coefs0.y);
            tFrom = t;
        }
    }
    return transmittance;
}

#endif

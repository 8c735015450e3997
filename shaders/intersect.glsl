// Scene intersection: nearest hit for camera and secondary rays, and the
// filtered transmittance of shadow rays. Brute force over all primitives.
#ifndef WHITTED_INTERSECT_GLSL
#define WHITTED_INTERSECT_GLSL
#include "scene.glsl"
#include "shapes/sphere.glsl"
#include "shapes/cylinder.glsl"
#include "shapes/plane.glsl"
#include "shapes/triangle.glsl"
#include "shapes/box.glsl"

// Dispatches to the shape's own intersection function.
bool intersectPrimitive(Primitive prim, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    switch (prim.info.x) {
        case kShapeSphere: return intersectSphere(prim.a.xyz, prim.a.w, ray, tMin, tHit, normal);
        case kShapeCylinder: return intersectCylinder(prim.a.xyz, prim.b.xyz, prim.a.w, prim.b.w, ray, tMin, tHit, normal);
        case kShapePlane: return intersectPlane(prim.a.xyz, prim.b.xyz, ray, tMin, tHit, normal);
        case kShapeTriangle: return intersectTriangle(prim.a.xyz, prim.b.xyz, prim.c.xyz, ray, tMin, tHit, normal);
        case kShapeBox: return intersectBox(prim.a.xyz, prim.b.xyz, ray, tMin, tHit, normal);
    }
    normal = vec3(0.0);
    return false;
}

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

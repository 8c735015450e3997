#version 460
// Runs the renderer's own intersectPrimitive() and offsetRay() on a batch of
// rays against one primitive, so tests can compare them with a
// double-precision CPU evaluation (tests/intersect_test.cpp).
#extension GL_GOOGLE_include_directive : require
#include "shapes/primitive.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer PrimitiveBlock { Primitive primitive; };
layout(std430, binding = 1) readonly buffer RayBlock { vec4 rays[]; };   // origin, dir pairs
layout(std430, binding = 2) writeonly buffer ResultBlock { vec4 results[]; };  // (normal, t), (self-hit, 0, 0, 0)
layout(push_constant) uniform Count { uint rayCount; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= rayCount) return;
    Ray ray = Ray(rays[2 * i].xyz, rays[2 * i + 1].xyz);
    float t = 3.0e38;
    vec3 n;
    bool hit = intersectPrimitive(primitive, ray, 0.0, t, n);
    results[2 * i] = hit ? vec4(n, t) : vec4(0.0, 0.0, 0.0, -1.0);

    // Self-intersection: a ray leaving the hit point (offset to the side it
    // leaves into) in the mirror direction must not hit the surface again
    // right there (pbrt-v4 shapes_test's re-intersection check).
    float selfHit = 0.0;
    if (hit) {
        vec3 facing = dot(ray.dir, n) < 0.0 ? n : -n;
        vec3 p = offsetRay(ray.origin + t * ray.dir, facing);
        float t2 = 3.0e38;
        vec3 n2;
        if (intersectPrimitive(primitive, Ray(p, reflect(ray.dir, facing)), 0.0, t2, n2) && t2 < 1e-3 * max(t, 1.0))
            selfHit = t2;
    }
    results[2 * i + 1] = vec4(selfHit, 0.0, 0.0, 0.0);
}

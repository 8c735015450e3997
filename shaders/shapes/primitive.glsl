// Any primitive: dispatches on the shape tag to the shape's own function.
#ifndef WHITTED_PRIMITIVE_GLSL
#define WHITTED_PRIMITIVE_GLSL
#include "../device_types.h"
#include "sphere.glsl"
#include "cylinder.glsl"
#include "plane.glsl"
#include "triangle.glsl"
#include "box.glsl"

// The shapes in the scene's BVH, one bit per shape tag: a specialization
// constant set by the renderer (all shapes by default). On a SIMD CPU
// driver such as lavapipe a branch is not skipped, its lanes are masked off,
// so every shape function in this dispatch costs on every primitive test
// unless the shapes the scene lacks are compiled out.
layout(constant_id = kSpecShapeMask) const uint kShapeMask = 0x1fu;

bool shapeEnabled(uint tag, uint actual) { return (kShapeMask & (1u << tag)) != 0u && actual == tag; }

bool intersectPrimitive(Primitive prim, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    normal = vec3(0.0);
    uint tag = prim.info.x;
    if (shapeEnabled(kShapeSphere, tag)) return intersectSphere(prim.a.xyz, prim.a.w, ray, tMin, tHit, normal);
    if (shapeEnabled(kShapeCylinder, tag))
        return intersectCylinder(prim.a.xyz, prim.b.xyz, prim.a.w, prim.b.w, ray, tMin, tHit, normal);
    if (shapeEnabled(kShapePlane, tag)) return intersectPlane(prim.a.xyz, prim.b.xyz, ray, tMin, tHit, normal);
    if (shapeEnabled(kShapeTriangle, tag))
        return intersectTriangle(prim.a.xyz, prim.b.xyz, prim.c.xyz, ray, tMin, tHit, normal);
    if (shapeEnabled(kShapeBox, tag)) return intersectBox(prim.a.xyz, prim.b.xyz, ray, tMin, tHit, normal);
    return false;
}

// The normal that shading uses at point p of a primitive hit from the side n
// faces (n: the geometric normal turned towards the incoming ray). It is n
// itself except on smooth mesh triangles, where it is the interpolated vertex
// normal, turned to n's side (a file's normals may disagree with the
// winding) and, where it would face away from the viewer (silhouettes of a
// coarse mesh), bent towards viewDir until their cosine is kMinCosine, so
// shading never looks at a surface from behind.
vec3 shadingNormal(Primitive prim, vec3 p, vec3 n, vec3 viewDir) {
    if (prim.info.x != kShapeTriangle || prim.info.z != kTriangleSmooth) return n;
    const float kMinCosine = 1e-3;
    uvec3 packedNormals = uvec3(floatBitsToUint(prim.a.w), floatBitsToUint(prim.b.w), floatBitsToUint(prim.c.w));
    vec3 s = shadingNormalTriangle(prim.a.xyz, prim.b.xyz, prim.c.xyz, packedNormals, p);
    if (dot(s, n) < 0.0) s = -s;
    float facing = dot(s, viewDir);
    if (facing < kMinCosine) s = normalize(s + (kMinCosine - facing) * viewDir);
    return s;
}

#endif

// Any primitive: dispatches on the shape tag to the shape's own function.
#ifndef WHITTED_PRIMITIVE_GLSL
#define WHITTED_PRIMITIVE_GLSL
#include "../device_types.h"
#include "sphere.glsl"
#include "cylinder.glsl"
#include "plane.glsl"
#include "triangle.glsl"
#include "box.glsl"

// One primitive held in registers. The renderer's traversal uses
// intersectPrimitiveAt (intersect.glsl), which reads from the primitive
// buffer only the words the shape needs; this form serves callers that have
// the whole struct (tests/shaders/intersect_test.comp). Both call the same
// shape functions.
bool intersectPrimitive(Primitive prim, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    switch (prim.shape) {
        case kShapeSphere: return intersectSphere(sphereCenter(prim), sphereRadius(prim), ray, tMin, tHit, normal);
        case kShapeCylinder:
            return intersectCylinder(cylinderBase(prim), cylinderAxis(prim), cylinderRadius(prim), cylinderHeight(prim),
                                     ray, tMin, tHit, normal);
        case kShapePlane: return intersectPlane(planePoint(prim), planeUnitNormal(prim), ray, tMin, tHit, normal);
        case kShapeTriangle:
            return intersectTriangle(triangleV0(prim), triangleV1(prim), triangleV2(prim), ray, tMin, tHit, normal);
        case kShapeBox: return intersectBox(boxMin(prim), boxMax(prim), ray, tMin, tHit, normal);
    }
    normal = vec3(0.0);
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
    if (prim.shape != kShapeTriangle || !triangleSmooth(prim)) return n;
    const float kMinCosine = 1e-3;
    vec3 s = shadingNormalTriangle(triangleV0(prim), triangleV1(prim), triangleV2(prim), triangleNormals(prim), p);
    if (dot(s, n) < 0.0) s = -s;
    float facing = dot(s, viewDir);
    if (facing < kMinCosine) s = normalize(s + (kMinCosine - facing) * viewDir);
    return s;
}

#endif

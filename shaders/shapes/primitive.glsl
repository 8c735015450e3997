// Any primitive: dispatches on the shape tag to the shape's own function.
#ifndef WHITTED_PRIMITIVE_GLSL
#define WHITTED_PRIMITIVE_GLSL
#include "../device_types.h"
#include "sphere.glsl"
#include "cylinder.glsl"
#include "plane.glsl"
#include "triangle.glsl"
#include "box.glsl"

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

#endif

#ifndef WHITTED_PLANE_GLSL
#define WHITTED_PLANE_GLSL
#include "../ray.glsl"

// Ray/infinite plane through `point` with unit `planeNormal`.
bool intersectPlane(vec3 point, vec3 planeNormal, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    float denom = dot(planeNormal, ray.dir);
    if (abs(denom) < 1e-12) return false;
    float t = dot(point - ray.origin, planeNormal) / denom;
    if (!(t > tMin && t < tHit)) return false;
    tHit = t;
    normal = planeNormal;
    return true;
}

#endif

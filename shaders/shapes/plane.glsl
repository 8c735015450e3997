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

// Planar mapping: u along planarTangent(normal), v along
// normal x planarTangent(normal) (for a floor facing +y: u along +x, v along
// -z), from the plane's point, one repeat per `scale` world units.
SurfaceUv planeUv(vec3 point, vec3 planeNormal, float scale, vec3 p) {
    vec3 e1 = planarTangent(planeNormal);
    vec3 e2 = cross(planeNormal, e1);
    SurfaceUv s;
    s.tangent = vec3(0.0);
    s.uv = vec2(dot(p - point, e1), dot(p - point, e2)) / scale;
    s.dpdu = scale * e1;
    s.dpdv = scale * e2;
    return s;
}

#endif

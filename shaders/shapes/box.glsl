#ifndef WHITTED_BOX_GLSL
#define WHITTED_BOX_GLSL
#include "../ray.glsl"

// Ray/axis-aligned box by slabs ("An Efficient and Robust Ray-Box
// Intersection Algorithm", Williams et al., JGT 2005). The entry distance is
// used when it is in range, else the exit distance (ray starting inside);
// the normal is the axis of the slab that produced that distance.
bool intersectBox(vec3 lo, vec3 hi, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    vec3 d = mix(ray.dir, vec3(1e-30), lessThan(abs(ray.dir), vec3(1e-30)));
    vec3 invDir = 1.0 / d;
    vec3 t0 = (lo - ray.origin) * invDir;
    vec3 t1 = (hi - ray.origin) * invDir;
    vec3 tNear3 = min(t0, t1);
    vec3 tFar3 = max(t0, t1);
    float tNear = max(max(tNear3.x, tNear3.y), tNear3.z);
    float tFar = min(min(tFar3.x, tFar3.y), tFar3.z);
    if (tNear > tFar) return false;

    float t;
    int axis;
    float sgn;
    if (tNear > tMin) {
        t = tNear;
        axis = tNear == tNear3.x ? 0 : (tNear == tNear3.y ? 1 : 2);
        sgn = d[axis] > 0.0 ? -1.0 : 1.0;
    } else {
        t = tFar;
        axis = tFar == tFar3.x ? 0 : (tFar == tFar3.y ? 1 : 2);
        sgn = d[axis] > 0.0 ? 1.0 : -1.0;
    }
    if (!(t > tMin && t < tHit)) return false;
    tHit = t;
    normal = vec3(0.0);
    normal[axis] = sgn;
    return true;
}

#endif

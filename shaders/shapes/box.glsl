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

// Each face holds the whole texture, read unmirrored from outside: v up
// (+y) on the four side faces, u to the right as seen from outside; on the
// top face u along +x and v along -z, on the bottom face u along +x and v
// along +z. The face is the one the geometric normal n names.
SurfaceUv boxUv(vec3 lo, vec3 hi, vec3 n, vec3 p) {
    vec3 size = hi - lo;
    vec3 t = (p - lo) / size;  // [0, 1]^3 over the box
    vec3 an = abs(n);
    SurfaceUv s;
    s.tangent = vec3(0.0);
    if (an.y >= an.x && an.y >= an.z) {
        float vz = n.y > 0.0 ? -1.0 : 1.0;
        s.uv = vec2(t.x, n.y > 0.0 ? 1.0 - t.z : t.z);
        s.dpdu = vec3(size.x, 0.0, 0.0);
        s.dpdv = vec3(0.0, 0.0, vz * size.z);
    } else if (an.x >= an.z) {
        float uz = n.x > 0.0 ? -1.0 : 1.0;
        s.uv = vec2(n.x > 0.0 ? 1.0 - t.z : t.z, t.y);
        s.dpdu = vec3(0.0, 0.0, uz * size.z);
        s.dpdv = vec3(0.0, size.y, 0.0);
    } else {
        float ux = n.z > 0.0 ? 1.0 : -1.0;
        s.uv = vec2(n.z > 0.0 ? t.x : 1.0 - t.x, t.y);
        s.dpdu = vec3(ux * size.x, 0.0, 0.0);
        s.dpdv = vec3(0.0, size.y, 0.0);
    }
    return s;
}

#endif

// Scene intersection: nearest hit for camera and secondary rays, and the
// filtered transmittance of shadow rays. Bounded primitives are found
// through the BVH, unbounded ones (planes) are tested one by one.
//
// Traversal follows the stack-based scheme of Aila and Laine ("Understanding
// the Efficiency of Ray Traversal on GPUs", HPG 2009): test both children's
// boxes, descend into the nearer, push the farther; closest-hit rays shrink
// their interval as hits are found, shadow rays stop at the first opaque hit.
#ifndef WHITTED_INTERSECT_GLSL
#define WHITTED_INTERSECT_GLSL
#include "scene.glsl"
#include "shapes/primitive.glsl"

// Entry distance of the ray into a node's box within [0, tMax], or -1.
float intersectNodeBounds(BvhNode node, vec3 origin, vec3 invDir, float tMax) {
    vec3 t0 = (node.lo.xyz - origin) * invDir;
    vec3 t1 = (node.hi.xyz - origin) * invDir;
    vec3 tNear = min(t0, t1), tFar = max(t0, t1);
    float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
    float exit = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
    return enter <= exit ? enter : -1.0;
}

vec3 safeInverse(vec3 d) {
    return 1.0 / mix(d, vec3(1e-30) * sign(d + vec3(1e-37)), lessThan(abs(d), vec3(1e-30)));
}

// Nearest hit in (0, tMax).
bool traceClosest(Ray ray, float tMax, out Hit hit) {
    hit.t = tMax;
    hit.normal = vec3(0.0);
    hit.primitive = 0xffffffffu;
    vec3 n;

    if (params.accel.x > 0u) {
        vec3 invDir = safeInverse(ray.dir);
        uint stack[kBvhStackSize];
        int top = 0;
        uint node = 0u;
        bool traversing = intersectNodeBounds(bvhNodes[0], ray.origin, invDir, hit.t) >= 0.0;
        while (traversing) {
            BvhNode current = bvhNodes[node];
            uint count = floatBitsToUint(current.hi.w);
            uint first = floatBitsToUint(current.lo.w);
            if (count > 0u) {
                for (uint i = first; i < first + count; ++i)
                    if (intersectPrimitive(primitives[i], ray, 0.0, hit.t, n)) {
                        hit.normal = n;
                        hit.primitive = i;
                    }
            } else {
                float tLeft = intersectNodeBounds(bvhNodes[first], ray.origin, invDir, hit.t);
                float tRight = intersectNodeBounds(bvhNodes[first + 1u], ray.origin, invDir, hit.t);
                if (tLeft >= 0.0 && tRight >= 0.0) {
                    bool leftFirst = tLeft <= tRight;
                    stack[top++] = leftFirst ? first + 1u : first;
                    node = leftFirst ? first : first + 1u;
                    continue;
                }
                if (tLeft >= 0.0) { node = first; continue; }
                if (tRight >= 0.0) { node = first + 1u; continue; }
            }
            traversing = top > 0;
            if (traversing) node = stack[--top];
        }
    }

    uint end = params.accel.y + params.accel.z;
    for (uint i = params.accel.y; i < end; ++i)
        if (intersectPrimitive(primitives[i], ray, 0.0, hit.t, n)) {
            hit.normal = n;
            hit.primitive = i;
        }
    return hit.primitive != 0xffffffffu;
}

// Filters `transmittance` by every crossing of primitive i's surface in
// (0, tMax); returns false once an opaque surface blocks the ray.
bool filterThrough(uint i, Ray ray, float tMax, inout vec3 transmittance) {
    Primitive prim = primitives[i];
    float tFrom = 0.0;
    // A primitive is convex or flat: at most two crossings.
    for (int crossing = 0; crossing < 2; ++crossing) {
        float t = tMax;
        vec3 n;
        if (!intersectPrimitive(prim, ray, tFrom, t, n)) break;
        Material m = materials[prim.info.y];
        float kt = m.coefs1.y;
        if (kt <= 0.0) return false;
        transmittance *= kt * mix(vec3(1.0), m.diffuse.rgb, m.coefs0.y);
        tFrom = t;
    }
    return true;
}

// Light that reaches the end of a shadow ray of length tMax. An opaque
// surface blocks it; every crossing of a transparent surface (kt > 0)
// filters it by kt * mix(white, Cd, kd), so shadows take the colour of glass
// as in the seed. Each surface crossing counts, so a glass sphere filters
// twice (in and out), the same as a closed glass mesh. The product does not
// depend on the order, so the BVH is walked without sorting and the walk
// ends at the first opaque hit.
vec3 shadowTransmittance(Ray ray, float tMax) {
    vec3 transmittance = vec3(1.0);
    if (params.accel.x > 0u) {
        vec3 invDir = safeInverse(ray.dir);
        uint stack[kBvhStackSize];
        int top = 0;
        if (intersectNodeBounds(bvhNodes[0], ray.origin, invDir, tMax) >= 0.0) stack[top++] = 0u;
        while (top > 0) {
            BvhNode current = bvhNodes[stack[--top]];
            uint count = floatBitsToUint(current.hi.w);
            uint first = floatBitsToUint(current.lo.w);
            if (count > 0u) {
                for (uint i = first; i < first + count; ++i)
                    if (!filterThrough(i, ray, tMax, transmittance)) return vec3(0.0);
            } else {
                if (intersectNodeBounds(bvhNodes[first], ray.origin, invDir, tMax) >= 0.0) stack[top++] = first;
                if (intersectNodeBounds(bvhNodes[first + 1u], ray.origin, invDir, tMax) >= 0.0) stack[top++] = first + 1u;
            }
        }
    }
    uint end = params.accel.y + params.accel.z;
    for (uint i = params.accel.y; i < end; ++i)
        if (!filterThrough(i, ray, tMax, transmittance)) return vec3(0.0);
    return transmittance;
}

#endif

// The BVH walk: bounded primitives found by the shader's own traversal of
// the host's BVH, included by intersect.glsl in place of the device's
// ray queries (its twin, shaders/ray_query.glsl, in the variant compiled
// with -DWHITTED_RAY_QUERY). The unbounded primitives (traverseList) and
// the primitive tests (testPrimitive) are intersect.glsl's.
//
// Traversal follows the stack-based scheme of Aila and Laine ("Understanding
// the Efficiency of Ray Traversal on GPUs", HPG 2009) on a 4-wide tree: the
// host's binary SAH tree collapsed to two to four children a node
// (host/accel/bvh.h, collapseToWide; the wide traversal of Ylitie, Karras
// and Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed
// Wide BVHs", HPG 2017, without their compression). A step tests the
// child boxes, descends into the nearest (a sorting network orders them),
// pushes the others farthest first; closest-hit rays shrink their interval
// as hits are found, shadow rays stop at the first opaque hit and take the
// children in slot order. On lavapipe a step gathers four nodes instead of
// two, but a walk takes about half the steps (measured: see
// tools/benchmark_results/README.md).
// Stacked entries keep their entry distance, and a closest-hit ray drops a
// popped entry that lies behind its nearest hit so far, as Embree's
// traversal does (Wald et al., "Embree: A Kernel Framework for Efficient CPU
// Ray Tracing", SIGGRAPH 2014).
#ifndef WHITTED_BVH_GLSL
#define WHITTED_BVH_GLSL
#include "scene.glsl"  // bvhNodes, bvhNodeBuffer

// Entry distance of the ray into a node's box within [0, tMax], or -1.
float intersectNodeBounds(BvhNode node, vec3 origin, vec3 invDir, float tMax) {
    vec3 t0 = (node.lo - origin) * invDir;
    vec3 t1 = (node.hi - origin) * invDir;
    vec3 tNear = min(t0, t1), tFar = max(t0, t1);
    float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
    float exit = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
    return enter <= exit ? enter : -1.0;
}

vec3 safeInverse(vec3 d) {
    return 1.0 / mix(d, vec3(1e-30) * sign(d + vec3(1e-37)), lessThan(abs(d), vec3(1e-30)));
}

// Where the walk reads its nodes: through their device address, or in the
// variant compiled with -DWHITTED_SCENE_STORAGE_BUFFERS (chosen by the
// renderer for lavapipe before Mesa 25) through the storage buffer of the same
// nodes (the primitives likewise: shaders/scene.glsl).
// Lavapipe runs either as a load per lane: Mesa 25.0 gathers a device
// address in one vector instruction and loops over the lanes for a storage
// buffer (bounds-checked each); Mesa 22.3 loops over the lanes for both,
// once per 32-bit word of a device address, and walks faster through
// the storage buffer (measured: see tools/benchmark_results/README.md). A
// variant, so that the default shader is the one measured on Mesa 25.
#ifdef WHITTED_SCENE_STORAGE_BUFFERS
#define bvhWalkNodes bvhNodeBuffer
#else
#define bvhWalkNodes bvhNodes
#endif

// One routine serves both queries (`shadow` is a constant at each call, so
// the other query's code folds away). The unbounded primitives come first,
// one by one: a near plane then culls the BVH for closest hits. The BVH
// loop is flat ("if-if" in Aila and Laine's terms): every iteration first
// takes one traversal step if the lane has no leaf primitive left to test,
// then tests at most one primitive. A SIMD CPU driver (lavapipe) runs both
// halves for all lanes under masks anyway, so an iteration costs one node
// step plus one primitive test and the iteration count is the most work any
// lane has, where nested loops pay each inner loop's body at least once per
// outer iteration. Stack entries are an inner node's `first` (its first child
// slot and child count, whose boxes are tested next) or kLeafEntry | the
// leaf's index.
// Returns false when a shadow ray is blocked.
const uint kLeafEntry = 0x80000000u;
const uint kNoEntry = 0xffffffffu;

uint entryOf(BvhNode node, uint index) {
    return node.primitiveCount > 0u ? (kLeafEntry | index) : node.first;
}

bool traverseScene(Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
                   inout vec3 opticalDepth) {
    if (!traverseList(ray, tMax, shadow, hit, transmittance, opticalDepth)) return false;
    if (kShapeMask == 0u || params.bvhNodeCount == 0u) return true;
    float tFrom = 0.0;  // shadow rays: a second crossing of the same primitive starts here
    bool blocked = false;

    vec3 invDir = safeInverse(ray.dir);
    uint stack[kBvhWideStackSize];
    float stackT[kBvhWideStackSize];  // entry distance of each stacked node (closest hit)
    int top = 0;
    uint children = kNoEntry;  // `first` of the inner node to expand next: first child slot, child count
    uint prim = 0u, primEnd = 0u;
    if (intersectNodeBounds(bvhWalkNodes[0], ray.origin, invDir, shadow ? tMax : hit.t) >= 0.0) {
        stackT[top] = 0.0;
        stack[top++] = entryOf(bvhWalkNodes[0], 0u);
    }

    bool running = true;
    while (running) {
        if (prim >= primEnd) {
            // Traversal step: test the four child boxes of the inner node,
            // go on with the nearest hit one (closest hit; shadow rays: the
            // first in slot order) and push the others, farthest first, or
            // pop.
            float tLimit = shadow ? tMax : hit.t;
            uint entry = kNoEntry;
            if (children != kNoEntry) {
                const float kMiss = 3.4e38;  // beyond any tLimit: sorts last
                // Two to four children (the count is in the entry); a slot
                // past the last is not read: slot 0 is read again, its
                // distance ignored.
                uint first = children & kBvhChildIndexMask, count = (children >> kBvhChildCountShift) + 2u;
                uint s2 = count > 2u ? first + 2u : first, s3 = count > 3u ? first + 3u : first;
                BvhNode c0 = bvhWalkNodes[first], c1 = bvhWalkNodes[first + 1u];
                BvhNode c2 = bvhWalkNodes[s2], c3 = bvhWalkNodes[s3];
                float t0 = intersectNodeBounds(c0, ray.origin, invDir, tLimit);
                float t1 = intersectNodeBounds(c1, ray.origin, invDir, tLimit);
                float t2 = count > 2u ? intersectNodeBounds(c2, ray.origin, invDir, tLimit) : -1.0;
                float t3 = count > 3u ? intersectNodeBounds(c3, ray.origin, invDir, tLimit) : -1.0;
                t0 = t0 >= 0.0 ? t0 : kMiss;
                t1 = t1 >= 0.0 ? t1 : kMiss;
                t2 = t2 >= 0.0 ? t2 : kMiss;
                t3 = t3 >= 0.0 ? t3 : kMiss;
                uint e0 = entryOf(c0, first), e1 = entryOf(c1, first + 1u);
                uint e2 = entryOf(c2, s2), e3 = entryOf(c3, s3);
                if (!shadow) {
                    // Sorting network on the entry distances (stable: ties
                    // keep slot order).
#define WHITTED_SORT2(ta, ea, tb, eb) { bool swap = tb < ta; float tt = ta; uint et = ea; \
                    ta = swap ? tb : ta; ea = swap ? eb : ea; tb = swap ? tt : tb; eb = swap ? et : eb; }
                    WHITTED_SORT2(t0, e0, t1, e1)
                    WHITTED_SORT2(t2, e2, t3, e3)
                    WHITTED_SORT2(t0, e0, t2, e2)
                    WHITTED_SORT2(t1, e1, t3, e3)
                    WHITTED_SORT2(t1, e1, t2, e2)
#undef WHITTED_SORT2
                } else {
                    // Any hit child first: the first one in slot order.
                    bool swap = t0 == kMiss;
                    float tt = t0; uint et = e0;
                    t0 = swap ? t1 : t0; e0 = swap ? e1 : e0; t1 = swap ? tt : t1; e1 = swap ? et : e1;
                }
                if (t3 < kMiss) { stackT[top] = t3; stack[top++] = e3; }
                if (t2 < kMiss) { stackT[top] = t2; stack[top++] = e2; }
                if (t1 < kMiss) { stackT[top] = t1; stack[top++] = e1; }
                entry = t0 < kMiss ? e0 : kNoEntry;
            }
            bool culled = false;
            if (entry == kNoEntry && top > 0) {
                entry = stack[--top];
                // Closest hit: a hit found since the push, nearer than the
                // entry's box, culls it here rather than after a step (an
                // inner node) or a test of each primitive (a leaf).
                culled = !shadow && stackT[top] > tLimit;
            }
            children = kNoEntry;
            if (entry == kNoEntry) {
                running = false;
            } else if (culled) {
                // this step is spent; the next one pops again
            } else if ((entry & kLeafEntry) != 0u) {
                // Only the two words needed: a whole node would be a
                // gather of eight per lane.
                uint leaf = entry & ~kLeafEntry;
                prim = bvhWalkNodes[leaf].first;
                primEnd = prim + bvhWalkNodes[leaf].primitiveCount;
            } else {
                children = entry;
            }
        }
        if (prim < primEnd) {
            if (testPrimitive(prim, kShapeMask, ray, tMax, shadow, hit, transmittance, opticalDepth, tFrom,
                              blocked)) ++prim;
            if (blocked) return false;
            running = true;
        }
    }
    return true;
}

#endif

// The BVH walk: bounded primitives found by the shader's own traversal of
// the host's BVH, included by intersect.glsl in place of the device's
// ray queries (its twin, shaders/ray_query.glsl, in the variant compiled
// with -DWHITTED_RAY_QUERY). The unbounded primitives (traverseList) and
// the primitive tests (testPrimitive) are intersect.glsl's.
//
// Traversal follows the stack-based scheme of Aila and Laine ("Understanding
// the Efficiency of Ray Traversal on GPUs", HPG 2009) on the compressed
// 8-wide tree of Ylitie, Karras and Laine ("Efficient Incoherent Ray
// Traversal on GPUs Through Compressed Wide BVHs", HPG 2017): the host's
// binary SAH tree collapsed to up to eight children a node, their boxes
// quantised to 8 bits a bound on the node's power-of-two grid (gpu::BvhNode,
// host/accel/bvh.h). A step loads one 80-byte node, decodes and tests its
// eight child boxes, descends into the nearest (a sorting network orders
// them), pushes the others farthest first; closest-hit rays shrink their
// interval as hits are found, shadow rays stop at the first opaque hit and
// take the children in slot order. Unlike Ylitie et al., the stack holds
// one entry per child (with its entry distance, below), not a node and a
// mask of hit children ordered by the ray's octant. A step gathers one node,
// five 16-byte words, where a 4-wide tree of 32-byte child nodes gathers
// eight: lavapipe gathers a loaded word lane by lane, so the words a step
// loads bound its cost (measurements: tools/benchmark_results/notes-shader.md).
// Stacked entries keep their entry distance, and a closest-hit ray drops a
// popped entry that lies behind its nearest hit so far, as Embree's
// traversal does (Wald et al., "Embree: A Kernel Framework for Efficient CPU
// Ray Tracing", SIGGRAPH 2014).
#ifndef WHITTED_BVH_GLSL
#define WHITTED_BVH_GLSL
#include "scene.glsl"  // bvhNodes, bvhNodeBuffer

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
// once per 32-bit word of a device address, so there the storage buffer is
// the cheaper of the two (tools/benchmark_results/notes-shader.md). A
// variant, so that the default shader reads addresses, the cheaper on Mesa 25.
#ifdef WHITTED_SCENE_STORAGE_BUFFERS
#define bvhWalkNodes bvhNodeBuffer
#else
#define bvhWalkNodes bvhNodes
#endif

// One routine serves both queries: `shadow` is a constant where
// traceClosest calls it (shaders/cast_rays.comp), so the other query's code
// folds away, and chosen per ray by traceSamples' one call (traceQuery). The unbounded primitives come first,
// one by one: a near plane then culls the BVH for closest hits. The BVH
// loop is flat ("if-if" in Aila and Laine's terms): every iteration first
// takes one traversal step if the lane has no leaf primitive left to test,
// then tests at most one primitive. A SIMD CPU driver (lavapipe) runs both
// halves for all lanes under masks anyway, so an iteration costs one node
// step plus one primitive test and the iteration count is the most work any
// lane has, where nested loops pay each inner loop's body at least once per
// outer iteration. Stack entries are a wide node's index (its children's
// boxes are tested next) or a leaf's primitive range (kBvhLeafEntry,
// device_types.h).
// Returns false when a shadow ray is blocked (the recorder's build walks on
// to the end: kShadowWalksAll, intersect.glsl).
const uint kNoEntry = 0xffffffffu;

// Child k's entry distance (or kMiss) and stack entry, from the node's
// words: the child's bytes of the quantised bounds (lo and hi on x, y, z),
// its info byte and the node's inclusive prefix sum of leaf counts
// (leafEnd: the end of child k's primitives, relative to primitiveBase).
//
// The test is conservative: a ray that meets child k's true box is never
// said to miss it (pbrt-v4's robust ray-bounds test: Pharr, Jakob and
// Humphreys, "Physically Based Rendering", 4th ed., 6.8 "Managing
// Rounding Error"). Two parts:
//  - The decoded box contains the child's box. A bound is
//    origin + q * scale; q * scale is exact (an 8-bit integer times a power
//    of two), so the sum rounds once whether or not the compiler fuses it,
//    and gives exactly the host's decode() (host/accel/bvh.cpp), whose
//    quantisation steps each q outward until decode(q) <= min, resp.
//    >= max (checked by Bvh.QuantisedBoxesContainTheirChildren).
//  - The slab distances t = (bound - ray origin) * invDir carry three
//    roundings (the difference, the reciprocal, the product), so a
//    computed t is within a factor (1 +- gamma(n)) of the exact one,
//    gamma(n) = n u / (1 - n u), u = 2^-24, and n = 7 rather than pbrt's
//    3 because Vulkan allows 1.0 / x an error of 2.5 ULP (5 u; lavapipe
//    divides exactly). Growing each exit distance by (1 + 2 gamma(7))
//    makes it at least any computed entry distance of an exactly
//    overlapping interval, so a ray grazing a box face (a triangle lying
//    on a node's grid plane) still enters it. A bound is therefore not
//    computed as fma(q, scale, origin - ray origin): origin - ray origin
//    would round with an error relative to the ray's distance to the node's
//    origin, not to the bound's, which no relative widening of t covers
//    (tools/benchmark_results/notes-shader.md).
// 2 gamma(7) = 14 u / (1 - 7 u) is a hair above 7 * 2^-23; the factor is
// 1 + 8 * 2^-23, the next float up, which also covers the rounding of the
// growth's own product. `precise` keeps the compiler from reassociating
// origin + q * scale - ray origin (which would undo the first part).
const float kBoxExitGrowth = 1.00000095367431640625;  // 1 + 8 * 2^-23
#define WHITTED_CHILD(k, lw, hw, infoWord, endWord, t, e) { \
    uint sh = 8u * uint((k) & 3); \
    vec3 qlo = vec3(uvec3(n.quantX.lw, n.quantY.lw, n.quantZ.lw) >> sh & 0xffu); \
    vec3 qhi = vec3(uvec3(n.quantX.hw, n.quantY.hw, n.quantZ.hw) >> sh & 0xffu); \
    precise vec3 tA = (qlo * scale + n.origin - ray.origin) * invDir; \
    precise vec3 tB = (qhi * scale + n.origin - ray.origin) * invDir; \
    vec3 tNear = min(tA, tB), tFar = max(tA, tB) * kBoxExitGrowth; \
    float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0)); \
    float exit = min(min(tFar.x, tFar.y), min(tFar.z, tLimit)); \
    uint info = (infoWord) >> sh & 0xffu; \
    t = info != 0u && enter <= exit ? enter : kMiss; \
    uint leafFirst = n.primitiveBase + ((endWord) >> sh & 0xffu) - info; \
    e = info >= kBvhChildInner ? n.childBase + (info & 7u) \
                               : kBvhLeafEntry | ((info - 1u) << kBvhLeafCountShift) | leafFirst; }

bool traverseScene(Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
                   inout vec3 opticalDepth) {
    bool blocked = !traverseList(ray, tMax, shadow, hit, transmittance, opticalDepth);
    if (blocked && !kShadowWalksAll) return false;
    if (kShapeMask == 0u || params.bvhNodeCount == 0u) return !blocked;
    Ray worldRay = ray;  // in a prototype's tree (instance.glsl); the entries below instanceTop are the world's
    int instanceTop = 0;
    float tFrom = 0.0;  // shadow rays: a second crossing of the same primitive starts here

    vec3 invDir = safeInverse(ray.dir);
    uint stack[kBvhWideStackSize];
    float stackT[kBvhWideStackSize];  // entry distance of each stacked node (closest hit)
    int top = 0;
    uint children = 0u;  // the wide node whose children are tested next: the root first
    uint prim = 0u, primEnd = 0u;

    bool running = true;
    while (running) {
        if (prim >= primEnd) {
            // Traversal step: test the eight child boxes of the wide node,
            // go on with the nearest hit one (closest hit; shadow rays: the
            // first in slot order) and push the others, farthest first, or
            // pop.
            float tLimit = shadow ? tMax : hit.t;
            uint entry = kNoEntry;
            if (children != kNoEntry) {
                const float kMiss = 3.4e38;  // beyond any tLimit: sorts last
                // Member by member (why: shaders/scene.glsl, loadMaterial).
                BvhNode n = BvhNode(bvhWalkNodes[children].origin, bvhWalkNodes[children].exponents,
                                    bvhWalkNodes[children].childBase, bvhWalkNodes[children].primitiveBase,
                                    bvhWalkNodes[children].childInfo0, bvhWalkNodes[children].childInfo1,
                                    bvhWalkNodes[children].quantX, bvhWalkNodes[children].quantY,
                                    bvhWalkNodes[children].quantZ);
                vec3 scale = uintBitsToFloat(uvec3(n.exponents, n.exponents >> 8u, n.exponents >> 16u) << 23u & 0x7f800000u);
                // Leaf children's primitive ranges: byte k of the prefix sum
                // of the leaf counts (inner children's bytes masked to 0) is
                // the end of child k's range.
                uvec2 info = uvec2(n.childInfo0, n.childInfo1);
                uvec2 innerBytes = ((info >> 7u) & 0x01010101u) * 0xffu;
                uvec2 leafEnd = (info & ~innerBytes) * 0x01010101u;
                leafEnd.y += (leafEnd.x >> 24u) * 0x01010101u;
                float t0, t1, t2, t3, t4, t5, t6, t7;
                uint e0, e1, e2, e3, e4, e5, e6, e7;
                WHITTED_CHILD(0, x, z, info.x, leafEnd.x, t0, e0)
                WHITTED_CHILD(1, x, z, info.x, leafEnd.x, t1, e1)
                WHITTED_CHILD(2, x, z, info.x, leafEnd.x, t2, e2)
                WHITTED_CHILD(3, x, z, info.x, leafEnd.x, t3, e3)
                WHITTED_CHILD(4, y, w, info.y, leafEnd.y, t4, e4)
                WHITTED_CHILD(5, y, w, info.y, leafEnd.y, t5, e5)
                WHITTED_CHILD(6, y, w, info.y, leafEnd.y, t6, e6)
                WHITTED_CHILD(7, y, w, info.y, leafEnd.y, t7, e7)
                if (!shadow) {
                    // A sorting network of 19 comparators on the entry
                    // distances (Knuth, TAOCP vol. 3, 5.3.4).
#define WHITTED_SORT2(ta, ea, tb, eb) { bool swap = tb < ta; float tt = ta; uint et = ea; \
                    ta = swap ? tb : ta; ea = swap ? eb : ea; tb = swap ? tt : tb; eb = swap ? et : eb; }
                    WHITTED_SORT2(t0, e0, t2, e2) WHITTED_SORT2(t1, e1, t3, e3)
                    WHITTED_SORT2(t4, e4, t6, e6) WHITTED_SORT2(t5, e5, t7, e7)
                    WHITTED_SORT2(t0, e0, t4, e4) WHITTED_SORT2(t1, e1, t5, e5)
                    WHITTED_SORT2(t2, e2, t6, e6) WHITTED_SORT2(t3, e3, t7, e7)
                    WHITTED_SORT2(t0, e0, t1, e1) WHITTED_SORT2(t2, e2, t3, e3)
                    WHITTED_SORT2(t4, e4, t5, e5) WHITTED_SORT2(t6, e6, t7, e7)
                    WHITTED_SORT2(t2, e2, t4, e4) WHITTED_SORT2(t3, e3, t5, e5)
                    WHITTED_SORT2(t1, e1, t4, e4) WHITTED_SORT2(t3, e3, t6, e6)
                    WHITTED_SORT2(t1, e1, t2, e2) WHITTED_SORT2(t3, e3, t4, e4) WHITTED_SORT2(t5, e5, t6, e6)
#undef WHITTED_SORT2
                }
                // Shadow rays: slot order, the first hit child walked next
                // (popped at once when child 0 is missed). They never cull
                // by entry distance, so they store none: lavapipe writes a
                // private array lane by lane (a scalar store per lane).
                if (t7 < kMiss) { if (!shadow) stackT[top] = t7; stack[top++] = e7; }
                if (t6 < kMiss) { if (!shadow) stackT[top] = t6; stack[top++] = e6; }
                if (t5 < kMiss) { if (!shadow) stackT[top] = t5; stack[top++] = e5; }
                if (t4 < kMiss) { if (!shadow) stackT[top] = t4; stack[top++] = e4; }
                if (t3 < kMiss) { if (!shadow) stackT[top] = t3; stack[top++] = e3; }
                if (t2 < kMiss) { if (!shadow) stackT[top] = t2; stack[top++] = e2; }
                if (t1 < kMiss) { if (!shadow) stackT[top] = t1; stack[top++] = e1; }
                entry = t0 < kMiss ? e0 : kNoEntry;
            }
            bool culled = false;
            if (entry == kNoEntry && top > 0) {
                if (kSceneHasInstances && gWalkInstance != kNoInstance && top == instanceTop) {
                    ray = leaveInstance(worldRay);
                    invDir = safeInverse(ray.dir);
                }
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
            } else if ((entry & kBvhLeafEntry) != 0u) {
                prim = entry & (kBvhMaxPrimitives - 1u);
                primEnd = prim + ((entry >> kBvhLeafCountShift) & 7u) + 1u;
            } else {
                children = entry;
            }
        }
        if (prim < primEnd) {
            if (kSceneHasInstances && primitives[prim].shape == kShapeInstance) {
                children = enterInstance(prim, ray, worldRay);
                invDir = safeInverse(ray.dir);
                instanceTop = top;
                prim = primEnd;
            } else if (testPrimitive(prim, kShapeMask, ray, tMax, shadow, hit, transmittance, opticalDepth, tFrom,
                                     blocked)) {
                ++prim;
            }
            if (blocked && !kShadowWalksAll) return false;
            running = true;
        }
    }
    return !blocked;
}
#undef WHITTED_CHILD

#endif

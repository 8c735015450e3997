// Scene intersection: nearest hit for camera and secondary rays, and the
// filtered transmittance of shadow rays. Bounded primitives are found
// through the BVH, unbounded ones (planes) are tested one by one.
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
// two, but a walk takes about half the steps (README, "Profiling").
// Stacked entries keep their entry distance, and a closest-hit ray drops a
// popped entry that lies behind its nearest hit so far, as Embree's
// traversal does (Wald et al., "Embree: A Kernel Framework for Efficient CPU
// Ray Tracing", SIGGRAPH 2014).
#ifndef WHITTED_INTERSECT_GLSL
#define WHITTED_INTERSECT_GLSL
#include "scene.glsl"
#include "material.glsl"
#include "shapes/primitive.glsl"
#include "shapes/csg.glsl"
#include "texture.glsl"

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

// Whether any material is transparent (kt > 0): a specialization constant
// set by the renderer. Without transparency a shadow ray is an any-hit
// query and the material lookups of testPrimitive compile out.
layout(constant_id = kSpecTransparency) const bool kSceneHasTransparency = true;

// The shapes in the scene's BVH, one bit per shape tag: a specialization
// constant set by the renderer (all shapes by default). On a SIMD CPU
// driver such as lavapipe a branch is not skipped, its lanes are masked off,
// so every shape function in a dispatch costs on every primitive test
// unless the shapes the scene lacks are compiled out.
layout(constant_id = kSpecShapeMask) const uint kShapeMask = 0x3fu;

// The same for the unbounded primitives (planes; every primitive when there
// is no BVH).
layout(constant_id = kSpecListShapeMask) const uint kListShapeMask = 0x3fu;

// intersectPrimitive on primitives[i] for a scene whose shapes are `mask`,
// loading only the words the shape uses (lavapipe gathers each loaded word
// lane by lane: a whole Primitive is sixteen, a sphere four); with one
// shape in the mask not even the tag is read.
bool intersectPrimitiveAt(uint i, const uint mask, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    normal = vec3(0.0);
    bool single = bitCount(mask) == 1;
    uint tag = single ? findLSB(mask) : primitives[i].info.x;
    if ((mask & (1u << kShapeSphere)) != 0u && tag == kShapeSphere) {
        vec4 a = primitives[i].a;
        return intersectSphere(a.xyz, a.w, ray, tMin, tHit, normal);
    }
    if ((mask & (1u << kShapeCylinder)) != 0u && tag == kShapeCylinder) {
        vec4 a = primitives[i].a, b = primitives[i].b;
        return intersectCylinder(a.xyz, b.xyz, a.w, b.w, ray, tMin, tHit, normal);
    }
    if ((mask & (1u << kShapePlane)) != 0u && tag == kShapePlane)
        return intersectPlane(primitives[i].a.xyz, primitives[i].b.xyz, ray, tMin, tHit, normal);
    if ((mask & (1u << kShapeTriangle)) != 0u && tag == kShapeTriangle)
        return intersectTriangle(primitives[i].a.xyz, primitives[i].b.xyz, primitives[i].c.xyz, ray, tMin, tHit,
                                 normal);
    if ((mask & (1u << kShapeBox)) != 0u && tag == kShapeBox)
        return intersectBox(primitives[i].a.xyz, primitives[i].b.xyz, ray, tMin, tHit, normal);
    return false;
}

// A csg object (shaders/shapes/csg.glsl) for either query. A closest hit
// reports the leaf primitive struck. A csg object is not convex, so a
// shadow ray walks every crossing of its surface in (0, tMax) and filters
// the light at each by the material of the leaf struck, as testPrimitive
// does (kt, pigment, signed optical depth by the object's outward normal);
// an opaque crossing blocks.
void testCsg(uint i, Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
             inout vec3 opticalDepth, inout bool blocked) {
    vec3 n;
    uint leaf;
    if (!shadow) {
        if (intersectCsg(i, ray, 0.0, hit.t, n, leaf)) {
            hit.normal = n;
            hit.primitive = leaf;
        }
        return;
    }
    float tFrom = 0.0;
    for (uint crossing = 0u; crossing < 2u * kCsgMaxLeaves; ++crossing) {
        float t = tMax;
        if (!intersectCsg(i, ray, tFrom, t, n, leaf)) return;
        uint k = primitives[leaf].info.y;
        float kt = materials[k].coefs1.y;
        if (!kSceneHasTransparency || kt <= 0.0) {
            blocked = true;
            return;
        }
        vec3 cd = crossingColour(leaf, k, ray.origin + t * ray.dir, n);
        transmittance *= kt * mix(vec3(1.0), cd, materials[k].coefs0.y);
        opticalDepth += (dot(ray.dir, n) > 0.0 ? t : -t) * materials[k].absorption.rgb;
        tFrom = t;
    }
}

// Tests primitive i for either query. Closest hit (shadow = false): updates
// hit. Shadow ray: filters transmittance by a crossing of a transparent
// surface, sets blocked at an opaque one, and adds the crossing's share of
// the optical depth (see shadowTransmittance). A primitive is convex or
// flat, so after a first crossing a shadow ray tests it once more from there
// (tFrom). Returns whether the next primitive is due.
bool testPrimitive(uint i, const uint mask, Ray ray, float tMax, const bool shadow, inout Hit hit,
                   inout vec3 transmittance, inout vec3 opticalDepth, inout float tFrom, inout bool blocked) {
    if ((mask & (1u << kShapeCsg)) != 0u && (bitCount(mask) == 1 || primitives[i].info.x == kShapeCsg)) {
        testCsg(i, ray, tMax, shadow, hit, transmittance, opticalDepth, blocked);
        return true;
    }
    vec3 n;
    if (!shadow) {
        if (intersectPrimitiveAt(i, mask, ray, 0.0, hit.t, n)) {
            hit.normal = n;
            hit.primitive = i;
        }
        return true;
    }
    float t = tMax;
    bool crossed = intersectPrimitiveAt(i, mask, ray, tFrom, t, n);
    if (crossed) {
        if (!kSceneHasTransparency) {
            blocked = true;
            return true;
        }
        uint k = primitives[i].info.y;
        float kt = materials[k].coefs1.y;
        if (kt <= 0.0) {
            blocked = true;
        } else {
            // The pigment at the crossing, as POV-Ray's filter takes it.
            vec3 cd = crossingColour(i, k, ray.origin + t * ray.dir, n);
            transmittance *= kt * mix(vec3(1.0), cd, materials[k].coefs0.y);
            opticalDepth += (dot(ray.dir, n) > 0.0 ? t : -t) * materials[k].absorption.rgb;
        }
    }
    if (crossed && tFrom == 0.0) {
        tFrom = t;
        return false;
    }
    tFrom = 0.0;
    return true;
}

// One routine serves both queries (`shadow` is a constant at each call, so
// the other query's code folds away). The unbounded primitives come first,
// one by one: a near plane then culls the BVH for closest hits. The BVH
// loop is flat ("if-if" in Aila and Laine's terms): every iteration first
// takes one traversal step if the lane has no leaf primitive left to test,
// then tests at most one primitive. A SIMD CPU driver (lavapipe) runs both
// halves for all lanes under masks anyway, so an iteration costs one node
// step plus one primitive test and the iteration count is the most work any
// lane has, where nested loops pay each inner loop's body at least once per
// outer iteration. Stack entries are an inner node's lo.w (its first child
// slot and child count, whose boxes are tested next) or kLeafEntry | the
// leaf's index.
// Returns false when a shadow ray is blocked.
const uint kLeafEntry = 0x80000000u;
const uint kNoEntry = 0xffffffffu;

uint entryOf(BvhNode node, uint index) {
    return floatBitsToUint(node.hi.w) > 0u ? (kLeafEntry | index) : floatBitsToUint(node.lo.w);
}

// The unbounded primitives (planes), one by one; every primitive when
// there is no BVH. Returns false when a shadow ray is blocked.
bool traverseList(Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
                  inout vec3 opticalDepth) {
    float tFrom = 0.0;  // shadow rays: a second crossing of the same primitive starts here
    bool blocked = false;
    if (kListShapeMask != 0u) {
        uint i = params.accel.y, end = params.accel.y + params.accel.z;
        while (i < end) {
            if (testPrimitive(i, kListShapeMask, ray, tMax, shadow, hit, transmittance, opticalDepth, tFrom,
                              blocked)) ++i;
            if (blocked) return false;
        }
    }
    return true;
}

#ifdef WHITTED_RAY_QUERY
#include "ray_query.glsl"
#else
// Where the walk reads its nodes: through their device address, or in the
// variant compiled with -DWHITTED_SCENE_STORAGE_BUFFERS (chosen by the
// renderer for lavapipe before Mesa 25) through the storage buffer of the same
// nodes (the primitives likewise: shaders/scene.glsl).
// Lavapipe runs either as a load per lane: Mesa 25.0 gathers a device
// address in one vector instruction and loops over the lanes for a storage
// buffer (bounds-checked each); Mesa 22.3 loops over the lanes for both,
// once per 32-bit word of a device address, and walks 1.3-2x faster through
// the storage buffer (README, "Profiling and what each change gained"). A
// variant, so that the default shader is the one measured on Mesa 25.
#ifdef WHITTED_SCENE_STORAGE_BUFFERS
#define bvhWalkNodes bvhNodeBuffer
#else
#define bvhWalkNodes bvhNodes
#endif

bool traverseScene(Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
                   inout vec3 opticalDepth) {
    if (!traverseList(ray, tMax, shadow, hit, transmittance, opticalDepth)) return false;
    if (kShapeMask == 0u || params.accel.x == 0u) return true;
    float tFrom = 0.0;  // shadow rays: a second crossing of the same primitive starts here
    bool blocked = false;

    vec3 invDir = safeInverse(ray.dir);
    uint stack[kBvhWideStackSize];
    float stackT[kBvhWideStackSize];  // entry distance of each stacked node (closest hit)
    int top = 0;
    uint children = kNoEntry;  // lo.w of the inner node to expand next: first child slot, child count
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
                prim = floatBitsToUint(bvhWalkNodes[leaf].lo.w);
                primEnd = prim + floatBitsToUint(bvhWalkNodes[leaf].hi.w);
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

// Nearest hit in (0, tMax).
bool traceClosest(Ray ray, float tMax, out Hit hit) {
    hit.t = tMax;
    hit.normal = vec3(0.0);
    hit.primitive = 0xffffffffu;
    vec3 unused = vec3(1.0), unusedDepth = vec3(0.0);
    traverseScene(ray, tMax, false, hit, unused, unusedDepth);
    return hit.primitive != 0xffffffffu;
}

// Light that reaches the end of a shadow ray of length tMax. An opaque
// surface blocks it; every crossing of a transparent surface (kt > 0)
// filters it by kt * mix(white, Cd, kd), so shadows take the colour of glass
// as in the seed. Each surface crossing counts, so a glass sphere filters
// twice (in and out), the same as a closed glass mesh. The product does not
// depend on the order, so the BVH is walked without sorting and the walk
// ends at the first opaque hit.
//
// Absorption (Beer-Lambert) inside objects with sigma > 0 multiplies by
// exp(-sigma * d), d the length inside. The crossings come unordered, so
// each adds to a signed optical depth: sigma * t when leaving (by the
// geometric normal), -sigma * t when entering, which sums to sigma times the
// length between an entry and its exit for any closed surface, meshes
// included, and to sigma * t for a ray that starts inside (a point shaded
// on the inside of glass). A light inside an absorbing object would leave an
// entry unmatched: the clamp at 0 then drops that object's absorption.
vec3 shadowTransmittance(Ray ray, float tMax) {
    Hit unused;
    unused.t = tMax;
    vec3 transmittance = vec3(1.0), opticalDepth = vec3(0.0);
    if (!traverseScene(ray, tMax, true, unused, transmittance, opticalDepth)) return vec3(0.0);
    return transmittance * exp(-max(opticalDepth, vec3(0.0)));
}

#endif

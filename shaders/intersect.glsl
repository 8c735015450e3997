// Scene intersection: nearest hit for camera and secondary rays, and the
// filtered transmittance of shadow rays. Bounded primitives are found by
// the BVH walk (bvh.glsl) or, in the variant compiled with
// -DWHITTED_RAY_QUERY, its twin through the device's ray queries
// (ray_query.glsl); unbounded ones (planes) are tested one by one here.
#ifndef WHITTED_INTERSECT_GLSL
#define WHITTED_INTERSECT_GLSL
#include "scene.glsl"
#include "material.glsl"
#include "shapes/primitive.glsl"
#ifndef WHITTED_NO_CSG  // the build for scenes without csg objects (host/render/device_policy.cpp)
#include "shapes/csg.glsl"
#endif
#include "texture.glsl"

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

#include "instance.glsl"

// intersectPrimitive on primitives[i] for a scene whose shapes are `mask`,
// loading only the words the shape uses (lavapipe gathers each loaded word
// lane by lane: a whole Primitive is sixteen, a sphere four); with one
// shape in the mask not even the tag is read.
bool intersectPrimitiveAt(uint i, const uint mask, Ray ray, float tMin, inout float tHit, out vec3 normal) {
    normal = vec3(0.0);
    bool single = bitCount(mask) == 1;
    uint tag = single ? findLSB(mask) : primitives[i].shape;
    if ((mask & (1u << kShapeSphere)) != 0u && tag == kShapeSphere) {
        Primitive p = primitives[i];
        return intersectSphere(sphereCenter(p), sphereRadius(p), ray, tMin, tHit, normal);
    }
    if ((mask & (1u << kShapeCylinder)) != 0u && tag == kShapeCylinder) {
        Primitive p = primitives[i];
        return intersectCylinder(cylinderBase(p), cylinderAxis(p), cylinderRadius(p), cylinderHeight(p), ray, tMin,
                                 tHit, normal);
    }
    if ((mask & (1u << kShapePlane)) != 0u && tag == kShapePlane) {
        Primitive p = primitives[i];
        return intersectPlane(planePoint(p), planeUnitNormal(p), ray, tMin, tHit, normal);
    }
    if ((mask & (1u << kShapeTriangle)) != 0u && tag == kShapeTriangle) {
        Primitive p = primitives[i];
        return intersectTriangle(triangleV0(p), triangleV1(p), triangleV2(p), ray, tMin, tHit, normal);
    }
    if ((mask & (1u << kShapeBox)) != 0u && tag == kShapeBox) {
        Primitive p = primitives[i];
        return intersectBox(boxMin(p), boxMax(p), ray, tMin, tHit, normal);
    }
    return false;
}

#ifdef WHITTED_RAY_TREE
// The ray-tree recorder's build (shaders/ray_tree.glsl) writes down every
// crossing of a shadow ray as its walk finds it: the walk goes on past an
// opaque crossing (the light is 0 either way) and shadowCrossing hands each
// crossing to rayTreeCrossing. The render's builds stop at the first opaque
// one.
const bool kShadowWalksAll = true;
void rayTreeCrossing(uint primitive, uint material, float t, vec3 filterColour, vec3 opticalDepth, bool opaque);
#else
const bool kShadowWalksAll = false;
#endif

// A shadow ray crosses the surface of primitive i (of a csg object: the leaf
// struck) at distance t, n the geometric normal there: the one step every
// shadow walk takes per crossing (testPrimitive and testCsg in the BVH walk
// and the list, the candidates of ray_query.glsl). A transparent surface
// (kt > 0) filters the light by kt * mix(white, Cd, kd) * Ct, Cd the
// pigment at the crossing as POV-Ray's filter takes it, and adds the
// crossing's share of the signed optical depth (see traceQuery).
// Returns false when the surface is opaque.
bool shadowCrossing(uint i, Ray ray, float t, vec3 n, inout vec3 transmittance, inout vec3 opticalDepth) {
    uint k = instanceMaterial(gWalkInstance, i);
    float kt = kSceneHasTransparency ? materials[k].kt : 0.0;
    bool opaque = kt <= 0.0;
    vec3 filterColour = vec3(0.0), depth = vec3(0.0);
    if (!opaque) {
        vec3 cd = crossingColour(i, k, ray.origin + t * ray.dir, n);
        filterColour = kt * mix(vec3(1.0), cd, materials[k].kd) * materials[k].transmissionColor;
        transmittance *= filterColour;
        if (kHasAbsorption) {
            depth = (dot(ray.dir, n) > 0.0 ? t : -t) * materials[k].absorption;
            opticalDepth += depth;
        }
    }
#ifdef WHITTED_RAY_TREE
    rayTreeCrossing(i, k, t, filterColour, depth, opaque);
#endif
    return !opaque;
}

#ifndef WHITTED_NO_CSG
// A csg object (shaders/shapes/csg.glsl) for either query. A closest hit
// reports the leaf primitive struck. A csg object is not convex, so a
// shadow ray walks every crossing of its surface in (0, tMax), each
// through shadowCrossing with the leaf struck (its material) and the
// object's outward normal; an opaque crossing blocks.
void testCsg(uint i, Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
             inout vec3 opticalDepth, inout bool blocked) {
    vec3 n;
    uint leaf;
    if (!shadow) {
        if (intersectCsg(i, ray, 0.0, hit.t, n, leaf)) {
            hit.normal = n;
            hit.primitive = leaf;
            if (kSceneHasInstances) hit.instance = kNoInstance;
        }
        return;
    }
    float tFrom = 0.0;
    for (uint crossing = 0u; crossing < 2u * kCsgMaxLeaves; ++crossing) {
        float t = tMax;
        if (!intersectCsg(i, ray, tFrom, t, n, leaf)) return;
        if (!shadowCrossing(leaf, ray, t, n, transmittance, opticalDepth)) {
            blocked = true;
            if (!kShadowWalksAll) return;
        }
        tFrom = t;
    }
}
#endif

// Tests primitive i for either query. Closest hit (shadow = false): updates
// hit. Shadow ray: each crossing goes through shadowCrossing, and an opaque
// one sets blocked. A primitive is convex or
// flat, so after a first crossing a shadow ray tests it once more from there
// (tFrom). Returns whether the next primitive is due.
bool testPrimitive(uint i, const uint mask, Ray ray, float tMax, const bool shadow, inout Hit hit,
                   inout vec3 transmittance, inout vec3 opticalDepth, inout float tFrom, inout bool blocked) {
#ifndef WHITTED_NO_CSG
    if ((mask & (1u << kShapeCsg)) != 0u && (bitCount(mask) == 1 || primitives[i].shape == kShapeCsg)) {
        testCsg(i, ray, tMax, shadow, hit, transmittance, opticalDepth, blocked);
        return true;
    }
#endif
    vec3 n;
    if (!shadow) {
        if (intersectPrimitiveAt(i, mask, ray, 0.0, hit.t, n)) {
            hit.normal = n;
            hit.primitive = i;
            if (kSceneHasInstances) hit.instance = gWalkInstance;  // in object space there (instance.glsl)
        }
        return true;
    }
    float t = tMax;
    bool crossed = intersectPrimitiveAt(i, mask, ray, tFrom, t, n);
    if (crossed && !shadowCrossing(i, ray, t, n, transmittance, opticalDepth)) {
        blocked = true;
        if (!kShadowWalksAll) return true;
    }
    if (crossed && tFrom == 0.0) {
        tFrom = t;
        return false;
    }
    tFrom = 0.0;
    return true;
}

// The unbounded primitives (planes), one by one; every primitive when
// there is no BVH. Returns false when a shadow ray is blocked.
bool traverseList(Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
                  inout vec3 opticalDepth) {
    float tFrom = 0.0;  // shadow rays: a second crossing of the same primitive starts here
    bool blocked = false;
    if (kSceneHasInstances) gWalkInstance = kNoInstance;  // the walks after the list start at the world's level
    if (kListShapeMask != 0u) {
        uint i = params.firstListPrimitive, end = params.firstListPrimitive + params.listPrimitiveCount;
        while (i < end) {
            if (testPrimitive(i, kListShapeMask, ray, tMax, shadow, hit, transmittance, opticalDepth, tFrom,
                              blocked)) ++i;
            if (blocked && !kShadowWalksAll) return false;
        }
    }
    return !blocked;
}

#ifdef WHITTED_RAY_QUERY
#include "ray_query.glsl"
#else
#include "bvh.glsl"
#endif

// The length of a shadow ray towards a directional light, "to infinity".
const float kRayInfinity = 3.0e38;

// Nearest hit in (0, tMax).
bool traceClosest(Ray ray, float tMax, out Hit hit) {
    hit.t = tMax;
    hit.normal = vec3(0.0);
    hit.primitive = 0xffffffffu;
    hit.instance = kNoInstance;
    vec3 unused = vec3(1.0), unusedDepth = vec3(0.0);
    traverseScene(ray, tMax, false, hit, unused, unusedDepth);
    if (kSceneHasInstances && hit.instance != kNoInstance) hit.normal = instanceNormal(hit.instance, hit.normal);
    return hit.primitive != 0xffffffffu;
}

// One query, chosen per ray at run time. Closest hit (`shadow` false): the
// nearest hit in (0, tMax) into `hit`; returns whether there is one.
// Shadow ray (`shadow` true): the light that reaches the end of a ray of
// length tMax, into `visibility`; returns false. traceSamples (whitted.comp)
// traces all its rays through one call of this, so the driver compiles one
// copy of the walk.
//
// A shadow ray: an opaque surface blocks it; every crossing of a
// transparent surface (kt > 0) filters it by kt * mix(white, Cd, kd) * Ct
// (Ct the transmission colour, white by default), so shadows take the
// colour of glass as in the seed. Each surface crossing counts, so a glass
// sphere filters twice (in and out), the same as a closed glass mesh. The
// product does not depend on the order, so the BVH is walked without
// sorting and the walk ends at the first opaque hit.
//
// Absorption (Beer-Lambert) inside objects with sigma > 0 multiplies by
// exp(-sigma * d), d the length inside. The crossings come unordered, so
// each adds to a signed optical depth: sigma * t when leaving (by the
// geometric normal), -sigma * t when entering, which sums to sigma times the
// length between an entry and its exit for any closed surface, meshes
// included, and to sigma * t for a ray that starts inside (a point shaded
// on the inside of glass). A light inside an absorbing object would leave an
// entry unmatched: the clamp at 0 then drops that object's absorption.
bool traceQuery(Ray ray, float tMax, bool shadow, out Hit hit, out vec3 visibility) {
    hit.t = tMax;
    hit.normal = vec3(0.0);
    hit.primitive = 0xffffffffu;
    hit.instance = kNoInstance;
    vec3 transmittance = vec3(1.0), opticalDepth = vec3(0.0);
    bool open = traverseScene(ray, tMax, shadow, hit, transmittance, opticalDepth);
    if (kSceneHasInstances && hit.instance != kNoInstance) hit.normal = instanceNormal(hit.instance, hit.normal);
    if (kHasAbsorption) transmittance *= exp(-max(opticalDepth, vec3(0.0)));
    visibility = open ? transmittance : vec3(0.0);
    return !shadow && hit.primitive != 0xffffffffu;
}

#endif

// Traversal through the device's acceleration structures (VK_KHR_ray_query),
// included by intersect.glsl in the shader variant compiled with
// -DWHITTED_RAY_QUERY in place of the BVH walk (its twin, bvh.glsl). The
// renderer builds (host/accel/acceleration_structure.cpp) a TLAS over at
// most two BLASes:
// the bounded triangles as native triangles and the other bounded shapes
// (spheres, cylinders, boxes, csg objects) as AABBs. Both BLASes list every bounded
// primitive in the order of the Primitive array, those of the other kind
// stand-ins no ray hits (a zero-area triangle at another shape's first
// point, a point box at a triangle's first vertex: lavapipe misses every
// primitive of a structure that holds NaN ones, the spec's inactive
// primitives), so a primitive index from the query IS the
// index into primitives[]; shading is unchanged. Planes stay outside, one
// by one.
//
// Closest hits: triangles are opaque geometry, committed by the driver
// (its own watertight test; t may differ from ours in the last bits);
// an AABB candidate is tested with the shape's own function and committed
// with rayQueryGenerateIntersectionEXT when nearer than the committed hit.
// Shadow rays with transparency: every candidate is looked at (ray flag
// NoOpaque, no commits) and filters the light once per crossing
// (shadowCrossing, intersect.glsl); the BLASes
// are built with NO_DUPLICATE_ANY_HIT, so each primitive comes once; the
// first opaque crossing ends the query. Without transparency a shadow ray
// stops at the first hit of any kind.
//
// Instances (shaders/instance.glsl): each prototype is a BLAS of its
// triangles, each instance a TLAS instance of it under its transform, its
// custom index 1 + the instance's (0: the scene's own BLASes). A candidate
// in an instance is primitive firstPrimitive + its index, tested and
// filtered against the ray in the instance's object space, as the BVH walk
// does (the driver's t is the same number in both spaces).
#ifndef WHITTED_RAY_QUERY_GLSL
#define WHITTED_RAY_QUERY_GLSL
#include "scene.glsl"  // sceneTlas

// The instance of a candidate or committed hit from its TLAS instance's
// custom index, or kNoInstance; i moves from the BLAS's index to the
// primitive array's.
uint queryInstance(int custom, inout uint i) {
    if (!kSceneHasInstances || custom == 0) return kNoInstance;
    uint k = uint(custom - 1);
    i += instanceRecords[k].firstPrimitive;
    return k;
}

bool traverseScene(Ray ray, float tMax, const bool shadow, inout Hit hit, inout vec3 transmittance,
                   inout vec3 opticalDepth) {
    bool blocked = !traverseList(ray, tMax, shadow, hit, transmittance, opticalDepth);
    if (blocked && !kShadowWalksAll) return false;
    if (kShapeMask == 0u) return !blocked;
    // The shapes in the AABB BLAS.
    const uint boxMask = kShapeMask & ~((1u << kShapeTriangle) | (1u << kShapeInstance));
    // Shadow rays look at every candidate with transparency, and in the
    // recorder's build, which writes each crossing down (kShadowWalksAll).
    const bool filtering = shadow && (kSceneHasTransparency || kShadowWalksAll);
    const bool mixed = boxMask != 0u && (kShapeMask & (1u << kShapeTriangle)) != 0u;
    uint flags = filtering ? gl_RayFlagsNoOpaqueEXT : (shadow ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT);
    rayQueryEXT query;
    rayQueryInitializeEXT(query, sceneTlas, flags, 0xffu, ray.origin, 0.0, ray.dir, shadow ? tMax : hit.t);
    vec3 boxNormal = vec3(0.0);  // normal of the last AABB hit committed
    uint boxPrimitive = 0u;      // and its primitive: a csg object's leaf struck
    while (rayQueryProceedEXT(query)) {
        uint i = uint(rayQueryGetIntersectionPrimitiveIndexEXT(query, false));
        if (kSceneHasInstances)
            gWalkInstance = queryInstance(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false), i);
        bool box = rayQueryGetIntersectionTypeEXT(query, false) == gl_RayQueryCandidateIntersectionAABBEXT;
        // A triangle's stand-in in the AABB structure (an empty box at a
        // vertex, host/accel/acceleration_structure.cpp) is no candidate.
        if (mixed && box && primitives[i].shape == kShapeTriangle) continue;
        vec3 n;
        // A csg object's AABB: intersectCsg (shaders/shapes/csg.glsl) and,
        // for shadow rays, every crossing of its surface (testCsg).
        bool csg = box && (kShapeMask & (1u << kShapeCsg)) != 0u && primitives[i].shape == kShapeCsg;
        if (filtering) {
            if (csg) {
                testCsg(i, ray, tMax, true, hit, transmittance, opticalDepth, blocked);
            } else if (box && boxMask != 0u) {
                // A convex shape is crossed at most twice: in, then out.
                float t = tMax;
                if (intersectPrimitiveAt(i, boxMask, ray, 0.0, t, n)) {
                    bool opaque = !shadowCrossing(i, ray, t, n, transmittance, opticalDepth);
                    float tOut = tMax;
                    vec3 nOut;
                    if ((!opaque || kShadowWalksAll) && intersectPrimitiveAt(i, boxMask, ray, t, tOut, nOut))
                        opaque = !shadowCrossing(i, ray, tOut, nOut, transmittance, opticalDepth) || opaque;
                    blocked = blocked || opaque;
                }
            } else if (!box) {
                // The winding's normal, as intersectTriangle gives it (in an instance, in object space).
                Ray r = kSceneHasInstances && gWalkInstance != kNoInstance ? objectRay(gWalkInstance, ray) : ray;
                Primitive p = primitives[i];
                vec3 a = triangleV0(p);
                n = cross(triangleV1(p) - a, triangleV2(p) - a);
                blocked = !shadowCrossing(i, r, rayQueryGetIntersectionTEXT(query, false), n, transmittance,
                                          opticalDepth) || blocked;
            }
            if (blocked && !kShadowWalksAll) rayQueryTerminateEXT(query);
        } else if (csg) {
            float tBest = rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT
                              ? rayQueryGetIntersectionTEXT(query, true)
                              : (shadow ? tMax : hit.t);
            uint leaf;
            if (intersectCsg(i, ray, 0.0, tBest, n, leaf)) {
                rayQueryGenerateIntersectionEXT(query, tBest);
                boxNormal = n;
                boxPrimitive = leaf;
            }
        } else if (box && boxMask != 0u) {
            float tBest = rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT
                              ? rayQueryGetIntersectionTEXT(query, true)
                              : (shadow ? tMax : hit.t);
            if (intersectPrimitiveAt(i, boxMask, ray, 0.0, tBest, n)) {
                rayQueryGenerateIntersectionEXT(query, tBest);
                boxNormal = n;
                boxPrimitive = i;
            }
        }
    }
    if (filtering) return !blocked;
    uint committed = rayQueryGetIntersectionTypeEXT(query, true);
    if (committed == gl_RayQueryCommittedIntersectionNoneEXT) return true;
    if (shadow) return false;
    uint i = uint(rayQueryGetIntersectionPrimitiveIndexEXT(query, true));
    hit.t = rayQueryGetIntersectionTEXT(query, true);
    // A prototype's triangle: its normal in object space, turned into the
    // world's by traceQuery (hit.instance).
    if (kSceneHasInstances) hit.instance = queryInstance(rayQueryGetIntersectionInstanceCustomIndexEXT(query, true), i);
    hit.primitive = i;
    if (committed == gl_RayQueryCommittedIntersectionTriangleEXT) {
        Primitive p = primitives[i];
        vec3 v0 = triangleV0(p), v1 = triangleV1(p), v2 = triangleV2(p);
        hit.normal = normalize(cross(v1 - v0, v2 - v0));
    } else {
        hit.normal = boxNormal;
        hit.primitive = boxPrimitive;
    }
    return true;
}

#endif

// The ray-tree recorder: included by shaders/whitted.comp in its build with
// -DWHITTED_RAY_TREE only, whose #ifdef WHITTED_RAY_TREE hooks call these
// functions. The host (host/render/ray_tree.h) dispatches that build over one
// pixel and one sample (its centre), so every ray the tracer traces there is
// written into the RayTreeRecord at TileParams.rayTreeAddress
// (ray_tree_types.h). The values recorded are the tracer's own: its weights,
// its local terms, and its shadow rays, traced by the renderer's own walk
// (traceSamples' one scene query, along the BVH or the ray queries) whose every
// crossing comes here through shadowCrossing's hook (rayTreeCrossing).
#ifndef WHITTED_RAY_TREE_GLSL
#define WHITTED_RAY_TREE_GLSL
#include "intersect.glsl"
#include "ray_tree_types.h"
#include "tracer_buffers.glsl"  // tileParams

layout(buffer_reference, std430, buffer_reference_align = 16) buffer RayTreeBuffer { RayTreeRecord record; };
#define rayTree (RayTreeBuffer(tileParams.rayTreeAddress).record)

// The record's entries are written member by member (why: shaders/scene.glsl, loadMaterial).
void storeRayTreeRay(uint i, RayTreeRay r) {
    rayTree.rays[i].origin = r.origin;
    rayTree.rays[i].kind = r.kind;
    rayTree.rays[i].direction = r.direction;
    rayTree.rays[i].depth = r.depth;
    rayTree.rays[i].point = r.point;
    rayTree.rays[i].t = r.t;
    rayTree.rays[i].normal = r.normal;
    rayTree.rays[i].primitive = r.primitive;
    rayTree.rays[i].weight = r.weight;
    rayTree.rays[i].material = r.material;
    rayTree.rays[i].ambient = r.ambient;
    rayTree.rays[i].shape = r.shape;
    rayTree.rays[i].diffuse = r.diffuse;
    rayTree.rays[i].frontFace = r.frontFace;
    rayTree.rays[i].specular = r.specular;
    rayTree.rays[i].parent = r.parent;
    rayTree.rays[i].emission = r.emission;
    rayTree.rays[i].firstShadowRay = r.firstShadowRay;
    rayTree.rays[i].contribution = r.contribution;
    rayTree.rays[i].shadowRayCount = r.shadowRayCount;
}

void storeRayTreeShadowRay(uint i, RayTreeShadowRay s) {
    rayTree.shadowRays[i].origin = s.origin;
    rayTree.shadowRays[i].ray = s.ray;
    rayTree.shadowRays[i].direction = s.direction;
    rayTree.shadowRays[i].light = s.light;
    rayTree.shadowRays[i].visibility = s.visibility;
    rayTree.shadowRays[i].distance = s.distance;
    rayTree.shadowRays[i].diffuse = s.diffuse;
    rayTree.shadowRays[i].outcome = s.outcome;
    rayTree.shadowRays[i].specular = s.specular;
    rayTree.shadowRays[i].blocker = s.blocker;
    rayTree.shadowRays[i].transmittance = s.transmittance;
    rayTree.shadowRays[i].blockerT = s.blockerT;
    rayTree.shadowRays[i].absorption = s.absorption;
    rayTree.shadowRays[i].firstCrossing = s.firstCrossing;
    rayTree.shadowRays[i].crossingCount = s.crossingCount;
    rayTree.shadowRays[i].blockerMaterial = s.blockerMaterial;
    rayTree.shadowRays[i].droppedCrossings = s.droppedCrossings;
    rayTree.shadowRays[i].pad0 = s.pad0;
}

// The record's index of each pending ray of traceSamples' stack (kNoObject:
// not recorded), the ray being shaded, and whether its reflection carries a
// total internal reflection.
uint gRayTreeStack[kRayStackSize];
uint gRayTreeCurrent = kNoObject;
bool gRayTreeTotalInternal = false;
// What the current ray's diffuse and specular sums held when its last
// shadow ray was recorded: that light's share is what was added since.
vec3 gRayTreeDiffuseBefore = vec3(0.0);
vec3 gRayTreeSpecularBefore = vec3(0.0);

// A ray pushed onto slot `slot` of the stack by the current ray (none for the
// camera ray). Its hit and terms follow when it is shaded (rayTreeShaded).
void rayTreePush(uint slot, uint kind, Ray ray, vec3 weight, uint depth) {
    gRayTreeStack[slot] = kNoObject;
    uint parent = kind == kRayCamera ? kNoObject : gRayTreeCurrent;
    if (kind != kRayCamera && parent == kNoObject) {  // its parent was dropped: so is it, counted
        rayTree.dropped += 1u;
        return;
    }
    uint i = rayTree.rayCount;
    if (i >= kRayTreeMaxRays) {
        rayTree.dropped += 1u;
        return;
    }
    rayTree.rayCount = i + 1u;
    RayTreeRay r;
    r.origin = ray.origin;
    r.kind = kind;
    r.direction = ray.dir;
    r.depth = depth;
    r.point = ray.origin;
    r.t = 0.0;
    r.normal = vec3(0.0);
    r.primitive = kNoObject;
    r.weight = weight;
    r.material = kNoObject;
    r.ambient = vec3(0.0);
    r.shape = 0u;
    r.diffuse = vec3(0.0);
    r.frontFace = 0u;
    r.specular = vec3(0.0);
    r.parent = parent;
    r.emission = vec3(0.0);
    r.firstShadowRay = rayTree.shadowRayCount;
    r.contribution = vec3(0.0);
    r.shadowRayCount = 0u;
    storeRayTreeRay(i, r);
    gRayTreeStack[slot] = i;
}

// The ray popped from slot `slot` is the one traced and shaded next.
void rayTreePop(uint slot) {
    gRayTreeCurrent = gRayTreeStack[slot];
    // Its shadow rays come next (rays pushed after it may be traced before).
    if (gRayTreeCurrent != kNoObject) rayTree.rays[gRayTreeCurrent].firstShadowRay = rayTree.shadowRayCount;
    gRayTreeTotalInternal = false;
    gRayTreeDiffuseBefore = vec3(0.0);
    gRayTreeSpecularBefore = vec3(0.0);
}

// The current ray's reflection also carries the transmitted share.
void rayTreeTotalInternal() { gRayTreeTotalInternal = true; }

// The kind of the reflection ray the current ray spawns.
uint rayTreeReflectionKind() { return gRayTreeTotalInternal ? kRayTotalInternal : kRayReflection; }

// The shadow ray being recorded (gRayTreeShadowOn: it has a place in the
// record) and the signed optical depth of its crossings so far.
bool gRayTreeShadowOn = false;
RayTreeShadowRay gRayTreeShadow;
vec3 gRayTreeOpticalDepth = vec3(0.0);

// The hook of shadowCrossing (intersect.glsl): the walk of the shadow ray
// being recorded crossed `primitive` at t. Writes the crossing down (or
// counts it, the record's crossings being full) and keeps the nearest
// opaque one as the blocker and the product of the filters, found or not.
void rayTreeCrossing(uint primitive, uint material, float t, vec3 filterColour, vec3 opticalDepth, bool opaque) {
    if (!gRayTreeShadowOn) return;
    if (opaque) {
        if (gRayTreeShadow.outcome != kShadowBlocked || t < gRayTreeShadow.blockerT) {
            gRayTreeShadow.blocker = primitive;
            gRayTreeShadow.blockerMaterial = material;
            gRayTreeShadow.blockerT = t;
        }
        gRayTreeShadow.outcome = kShadowBlocked;
    } else {
        gRayTreeShadow.transmittance *= filterColour;
        gRayTreeOpticalDepth += opticalDepth;
        if (gRayTreeShadow.outcome == kShadowLit) gRayTreeShadow.outcome = kShadowFiltered;
    }
    uint c = rayTree.crossingCount;
    if (c >= kRayTreeMaxCrossings) {
        rayTree.dropped += 1u;
        gRayTreeShadow.droppedCrossings += 1u;
    } else {
        rayTree.crossingCount = c + 1u;
        rayTree.crossings[c].filterColour = filterColour;
        rayTree.crossings[c].t = t;
        rayTree.crossings[c].primitive = primitive;
        rayTree.crossings[c].material = material;
        rayTree.crossings[c].pad0 = 0u;
        rayTree.crossings[c].pad1 = 0u;
        gRayTreeShadow.crossingCount += 1u;
    }
}

// The light before the last recorded one gets its share of the current
// ray's diffuse and specular sums: what they gained since its shadow ray.
void rayTreeCloseShadowRay(vec3 diffuse, vec3 specular) {
    if (gRayTreeCurrent == kNoObject) return;
    uint count = rayTree.rays[gRayTreeCurrent].shadowRayCount;
    if (count == 0u) return;
    uint last = rayTree.rays[gRayTreeCurrent].firstShadowRay + count - 1u;
    rayTree.shadowRays[last].diffuse = diffuse - gRayTreeDiffuseBefore;
    rayTree.shadowRays[last].specular = specular - gRayTreeSpecularBefore;
    gRayTreeDiffuseBefore = diffuse;
    gRayTreeSpecularBefore = specular;
}

// A shadow ray of the walk over the current hit's lights (shading.glsl,
// nextShadowRay) towards light `light`, written down in two halves around
// traceSamples' scene query, the renderer's own walk: Begin before it (its
// crossings are written down as the walk finds them, in the walk's order;
// the host sorts them along the ray), End with the visibility it found.
// diffuse and specular are the hit's sums so far (before this sample's
// terms).
void rayTreeShadowRayBegin(uint light, Ray ray, float dist, vec3 diffuse, vec3 specular) {
    gRayTreeShadowOn = false;
    if (gRayTreeCurrent == kNoObject) {  // the ray it belongs to was dropped: so is it, counted
        rayTree.dropped += 1u;
        return;
    }
    rayTreeCloseShadowRay(diffuse, specular);
    if (rayTree.shadowRayCount >= kRayTreeMaxShadowRays) {
        rayTree.dropped += 1u;
        return;
    }
    RayTreeShadowRay s;
    s.origin = ray.origin;
    s.ray = gRayTreeCurrent;
    s.direction = ray.dir;
    s.light = light;
    s.visibility = vec3(0.0);
    s.distance = dist;
    s.diffuse = vec3(0.0);
    s.outcome = kShadowLit;
    s.specular = vec3(0.0);
    s.blocker = kNoObject;
    s.transmittance = vec3(1.0);
    s.blockerT = dist;
    s.absorption = vec3(1.0);
    s.firstCrossing = rayTree.crossingCount;
    s.crossingCount = 0u;
    s.blockerMaterial = kNoObject;
    s.droppedCrossings = 0u;
    s.pad0 = 0u;
    gRayTreeShadow = s;
    gRayTreeOpticalDepth = vec3(0.0);
    gRayTreeShadowOn = true;
}

void rayTreeShadowRayEnd(vec3 visibility) {
    if (!gRayTreeShadowOn) return;
    gRayTreeShadowOn = false;
    RayTreeShadowRay s = gRayTreeShadow;
    s.visibility = visibility;
    s.absorption = exp(-max(gRayTreeOpticalDepth, vec3(0.0)));
    // From what was found, written down or not: a shadow ray whose crossings
    // all overflowed the record is still filtered, never lit.
    s.transmittance = s.outcome == kShadowBlocked ? vec3(0.0) : s.transmittance * s.absorption;
    uint i = rayTree.shadowRayCount;
    rayTree.shadowRayCount = i + 1u;
    storeRayTreeShadowRay(i, s);
    // Shadow rays of one ray are consecutive: they are traced while it is shaded.
    rayTree.rays[gRayTreeCurrent].shadowRayCount += 1u;
}

// The current ray left the scene and sees the environment's `radiance`, times `weight`: recorded as its
// emission, with no local terms (ambient, diffuse, specular 0); its primitive stays kNoObject, t 3e38.
void rayTreeMissed(vec3 weight, vec3 radiance) {
    if (gRayTreeCurrent == kNoObject) return;
    uint i = gRayTreeCurrent;
    rayTree.rays[i].t = 3.0e38;
    rayTree.rays[i].weight = weight;
    rayTree.rays[i].emission = radiance;
    rayTree.rays[i].contribution = weight * radiance;
}

// The current ray hit `hit` and was shaded: its hit, the weight that scaled
// its local terms and its contribution, as traceSamples adds it to the pixel.
void rayTreeShaded(Hit hit, Primitive prim, bool frontFace, vec3 p, vec3 ns, vec3 weight, LocalShading local,
                   vec3 emission) {
    if (gRayTreeCurrent == kNoObject) return;
    rayTreeCloseShadowRay(local.diffuse, local.specular);
    uint i = gRayTreeCurrent;
    rayTree.rays[i].point = p;
    rayTree.rays[i].t = hit.t;
    rayTree.rays[i].normal = ns;
    rayTree.rays[i].primitive = hit.primitive;
    rayTree.rays[i].weight = weight;
    rayTree.rays[i].material = prim.material;
    rayTree.rays[i].shape = prim.shape;
    rayTree.rays[i].frontFace = frontFace ? 1u : 0u;
    rayTree.rays[i].ambient = local.ambient;
    rayTree.rays[i].diffuse = local.diffuse;
    rayTree.rays[i].specular = local.specular;
    // Emission: traceSamples adds it to local.ambient (it counts in the
    // ambient component), so `ambient` includes it and `emission` says how
    // much of it is emission.
    rayTree.rays[i].emission = emission;
    rayTree.rays[i].contribution = weight * (local.ambient + local.diffuse + local.specular);
}

#endif

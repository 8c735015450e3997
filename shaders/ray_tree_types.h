// GPU data layout of the ray-tree inspector (shaders/ray_tree.glsl,
// host/render/ray_tree.h), shared by the C++ host and GLSL as device_types.h.
#ifndef WHITTED_RAY_TREE_TYPES_H
#define WHITTED_RAY_TREE_TYPES_H
#include "device_types.h"

#ifdef __cplusplus
namespace whitted::gpu {
#endif

// The build of shaders/whitted.comp with -DWHITTED_RAY_TREE records every
// ray of one pixel's centre sample into a RayTreeRecord (at
// TileParams.rayTreeAddress): its rays in the order they are traced, the
// shadow rays of each and the surfaces each shadow ray crosses. What does not
// fit is counted in RayTreeRecord.dropped, and so is every ray and shadow ray
// of a dropped ray's subtree (left out); a record with dropped > 0 is not
// fully recorded, and says so.
WHITTED_CONST uint kRayTreeMaxRays = 256;
WHITTED_CONST uint kRayTreeMaxShadowRays = 1024;
WHITTED_CONST uint kRayTreeMaxCrossings = 2048;

// RayTreeRay.kind.
WHITTED_CONST uint kRayCamera = 0;
WHITTED_CONST uint kRayReflection = 1;
WHITTED_CONST uint kRayRefraction = 2;
WHITTED_CONST uint kRayTotalInternal = 3;  // a reflection carrying the transmitted share too

// RayTreeShadowRay.outcome.
WHITTED_CONST uint kShadowLit = 0;       // nothing in the way
WHITTED_CONST uint kShadowBlocked = 1;   // an opaque surface (RayTreeShadowRay.blocker)
WHITTED_CONST uint kShadowFiltered = 2;  // only transparent surfaces, each filtering the light

// One ray. Its contribution to the pixel is weight * (ambient + diffuse +
// specular) as traceSamples adds it; diffuse and specular are the sums over
// its shadow rays' per-light terms. A ray that hits nothing has primitive
// kNoObject and brings nothing back (the background is black).
struct RayTreeRay {
    vec3 origin WHITTED_ZERO;
    uint kind WHITTED_ZERO;           // kRay*
    vec3 direction WHITTED_ZERO;
    uint depth WHITTED_ZERO;          // 0: the camera ray
    vec3 point WHITTED_ZERO;          // the hit point, origin + t * direction
    float t WHITTED_ZERO;
    vec3 normal WHITTED_ZERO;         // shading normal at the hit, facing the ray
    uint primitive WHITTED_ZERO;      // the primitive struck, kNoObject for a miss
    vec3 weight WHITTED_ZERO;         // the throughput that scales its local terms (after absorption)
    uint material WHITTED_ZERO;       // the object's material index (objects come first: the object index)
    vec3 ambient WHITTED_ZERO;
    uint shape WHITTED_ZERO;          // kShape* of the primitive struck
    vec3 diffuse WHITTED_ZERO;
    uint frontFace WHITTED_ZERO;      // 1: the outside of the surface was hit
    vec3 specular WHITTED_ZERO;
    uint parent WHITTED_ZERO;         // index of the ray it was spawned by, kNoObject for the camera ray
    vec3 emission WHITTED_ZERO;       // zero until materials emit (issue 16)
    uint firstShadowRay WHITTED_ZERO; // its shadow rays: RayTreeRecord.shadowRays[first .. first + count)
    vec3 contribution WHITTED_ZERO;   // weight * (ambient + diffuse + specular + emission)
    uint shadowRayCount WHITTED_ZERO;
};

// One shadow ray from a hit point towards a light, traced by the renderer's
// own shadow walk (traceQuery, shaders/intersect.glsl), which goes
// on past an opaque surface in the recorder's build so that every surface in
// (0, distance) is found. visibility is what the walk returned;
// transmittance the product of the filters of the crossings it handed to
// the recorder (crossings[first .. first + count), in order along the ray,
// and those left out), 0 when one is opaque, which tests compare.
struct RayTreeShadowRay {
    vec3 origin WHITTED_ZERO;
    uint ray WHITTED_ZERO;            // the RayTreeRay it belongs to
    vec3 direction WHITTED_ZERO;      // unit, towards the light
    uint light WHITTED_ZERO;          // index into the scene's lights
    vec3 visibility WHITTED_ZERO;
    float distance WHITTED_ZERO;      // to the light
    vec3 diffuse WHITTED_ZERO;        // this light's share of the ray's diffuse term
    uint outcome WHITTED_ZERO;        // kShadow*
    vec3 specular WHITTED_ZERO;       // and of its specular term
    uint blocker WHITTED_ZERO;        // kShadowBlocked: the nearest opaque primitive, else kNoObject
    vec3 transmittance WHITTED_ZERO;  // the product of the crossings' filters times the absorption
    float blockerT WHITTED_ZERO;      // kShadowBlocked: its distance along the ray, else distance
    vec3 absorption WHITTED_ZERO;     // exp(-sigma * length inside), the Beer-Lambert share of transmittance
    uint firstCrossing WHITTED_ZERO;
    uint crossingCount WHITTED_ZERO;
    uint blockerMaterial WHITTED_ZERO;  // the blocker's material (object) index, else kNoObject
    uint droppedCrossings WHITTED_ZERO; // crossings found but not written (the record's crossings were full);
                                        // the outcome and transmittance still count them
    uint pad0 WHITTED_ZERO;
};

// A surface a shadow ray crosses, and the filter kt * mix(white, Cd, kd) * Ct
// it applies there (shadowCrossing, shaders/intersect.glsl). An opaque one
// is recorded too, with filter 0.
struct RayTreeCrossing {
    vec3 filterColour WHITTED_ZERO;
    float t WHITTED_ZERO;
    uint primitive WHITTED_ZERO;
    uint material WHITTED_ZERO;
    uint pad0 WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
};

struct RayTreeRecord {
    uint rayCount WHITTED_ZERO;
    uint shadowRayCount WHITTED_ZERO;
    uint crossingCount WHITTED_ZERO;
    uint dropped WHITTED_ZERO;        // rays, shadow rays or crossings that did not fit, or whose parent did not
    RayTreeRay rays[kRayTreeMaxRays];
    RayTreeShadowRay shadowRays[kRayTreeMaxShadowRays];
    RayTreeCrossing crossings[kRayTreeMaxCrossings];
};

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#endif

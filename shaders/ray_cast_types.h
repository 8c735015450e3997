// GPU data layout of ray casting (Renderer.cast_rays in Python;
// host/render/ray_cast.h, shaders/cast_rays.comp), shared by the C++ host and
// GLSL as device_types.h.
#ifndef WHITTED_RAY_CAST_TYPES_H
#define WHITTED_RAY_CAST_TYPES_H
#include "device_types.h"

#ifdef __cplusplus
namespace whitted::gpu {
#endif

// One invocation a ray, kCastGroupSize a work group, the rays and their hits
// in arrays at the device addresses of CastParams (push constants).
WHITTED_CONST uint kCastGroupSize = 64;

// A ray: its unit direction and the farthest hit distance along it.
struct CastRay {
    vec3 origin WHITTED_ZERO;
    float tMax WHITTED_ZERO;
    vec3 direction WHITTED_ZERO;  // unit length
    float pad0 WHITTED_ZERO;
};

// What a ray hits first: primitive kNoObject for a miss (the rest is then 0).
struct CastHit {
    vec3 normal WHITTED_ZERO;  // the unit geometric normal the intersection gives (outward; a triangle's winding)
    float t WHITTED_ZERO;      // the distance along the unit direction
    vec2 uv WHITTED_ZERO;      // the texture coordinates surfaceUv gives (shaders/texture.glsl)
    uint object WHITTED_ZERO;  // primitiveObject: the object's index, as the object_id mask has it
    uint primitive WHITTED_ZERO;  // the index into the Primitive array (the host maps it to its object's numbering)
};

struct CastParams {
    uvec2 rayAddress WHITTED_ZERO;  // CastRay[count]
    uvec2 hitAddress WHITTED_ZERO;  // CastHit[count]
    uint count WHITTED_ZERO;
    uint pad0 WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
    uint pad2 WHITTED_ZERO;
};

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#endif

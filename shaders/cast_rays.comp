#version 460
// Ray casting (Renderer.cast_rays in Python, host/render/ray_cast.h): one
// invocation a ray, which asks the tracer's own closest-hit query
// (traceClosest, shaders/intersect.glsl: the BVH walk of shaders/bvh.glsl,
// or in the build with -DWHITTED_RAY_QUERY the device's ray queries of
// shaders/ray_query.glsl) on the scene a Renderer uploaded, through that
// renderer's descriptor set and with its specialization constants. It
// writes what it hits as the tracer sees it: the distance, the geometric
// normal, the texture coordinates surfaceUv gives and the object's index of
// the object_id mask (primitiveObject).
#extension GL_GOOGLE_include_directive : require

#include "ray_cast_types.h"
#include "intersect.glsl"

layout(local_size_x = kCastGroupSize, local_size_y = 1, local_size_z = 1) in;
layout(push_constant) uniform CastBlock { CastParams castParams; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer CastRayArray { CastRay v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer CastHitArray { CastHit v[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= castParams.count) return;
    // The ray and its hit member by member (why: shaders/scene.glsl, loadMaterial).
    CastRayArray rays = CastRayArray(castParams.rayAddress);
    Ray ray = Ray(rays.v[i].origin, rays.v[i].direction);
    Hit hit;
    CastHit result = CastHit(vec3(0.0), 0.0, vec2(0.0), kNoObject, kNoObject);
    if (traceClosest(ray, rays.v[i].tMax, hit)) {
        Primitive prim = hitPrimitive(hit);
        vec3 p = ray.origin + hit.t * ray.dir;
        SurfaceUv s = surfaceUv(prim, hit.primitive, hit.normal, p, materials[prim.material].textureScale);
        // Member by member: glslang 12.0.0 (Debian 12) crashes on the constructor CastHit(...) here.
        result.normal = normalize(hit.normal);
        result.t = hit.t;
        result.uv = s.uv;
        result.object = primitiveObject(prim);
        result.primitive = hit.primitive;
    }
    CastHitArray hits = CastHitArray(castParams.hitAddress);
    hits.v[i].normal = result.normal;
    hits.v[i].t = result.t;
    hits.v[i].uv = result.uv;
    hits.v[i].object = result.object;
    hits.v[i].primitive = result.primitive;
}

// Scene buffers, as laid out in device_types.h (the tracer's own: tracer_buffers.glsl).
#ifndef WHITTED_SCENE_GLSL
#define WHITTED_SCENE_GLSL
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#ifdef WHITTED_RAY_QUERY
#extension GL_EXT_ray_query : require
#endif
#include "device_types.h"

layout(std140, set = 0, binding = kBindingParams) uniform FrameParamsBlock { FrameParams params; };
#ifdef WHITTED_RAY_QUERY
// The scene's top-level acceleration structure (shaders/ray_query.glsl).
layout(set = 0, binding = kBindingTlas) uniform accelerationStructureEXT sceneTlas;
#endif

// The scene's arrays are read through buffer device addresses (Vulkan 1.2
// bufferDeviceAddress), not descriptors: a storage buffer descriptor spans
// at most maxStorageBufferRange (128 MiB on lavapipe, 2^21 primitives), an
// address a whole VkBuffer. The driver turns an index into a byte address
// in 64 bits, so no offset overflows past 4 GiB. The macros name the arrays
// as the storage-buffer variant's blocks do. A primitive is read through
// its shape's accessors (device_types.h), and the driver loads only the
// words those use (intersect.glsl). Lavapipe gathers an address load in one
// vector instruction, where it bounds-checks a storage buffer load lane by
// lane (measurements: tools/benchmark_results/notes-shader.md).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer PrimitiveArray { Primitive v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MaterialArray { Material v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer LightArray { Light v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer BvhNodeArray { BvhNode v[]; };
// The same arrays through descriptors (device_types.h,
// kBindingBvhNodeBuffer...), read in the variant built with
// -DWHITTED_SCENE_STORAGE_BUFFERS only: the BVH walk's nodes
// (shaders/bvh.glsl) and every primitive, material and light.
layout(std430, set = 0, binding = kBindingBvhNodeBuffer) readonly buffer BvhNodeBlock { BvhNode bvhNodeBuffer[]; };
layout(std430, set = 0, binding = kBindingPrimitiveBuffer) readonly buffer PrimitiveBlock {
    Primitive primitiveBuffer[];
};
layout(std430, set = 0, binding = kBindingMaterialBuffer) readonly buffer MaterialBlock { Material materialBuffer[]; };
layout(std430, set = 0, binding = kBindingLightBuffer) readonly buffer LightBlock { Light lightBuffer[]; };
#ifdef WHITTED_SCENE_STORAGE_BUFFERS
#define primitives primitiveBuffer
#define materials materialBuffer
#define lights lightBuffer
#else
#define primitives (PrimitiveArray(params.primitiveAddress).v)
#define materials (MaterialArray(params.materialAddress).v)
#define lights (LightArray(params.lightAddress).v)
#endif
#define bvhNodes (BvhNodeArray(params.bvhNodeAddress).v)
// The csg objects' programs (shaders/shapes/csg.glsl).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer CsgNodeArray { CsgNode v[]; };
#define csgNodes (CsgNodeArray(params.csgNodeAddress).v)

// A struct with vec3 members is read and written through a device address
// member by member, never as one struct: loadMaterial here (its padding left
// unread), a node in bvh.glsl, surfaceAttributesAt in texture.glsl, the ray
// tree's records in ray_tree.glsl, the rays and hits of cast_rays.comp; a
// light's members are read where they are used. The driver runs the same
// loads either way, but the Khronos layer's GPU-assisted validation as
// Debian 12 ships it (its SPIRV-Tools predates
// KhronosGroup/SPIRV-Tools#5257) sizes a whole-struct access as if every
// vec3 took 16 bytes, so the access to an array's last element reads as out
// of bounds, and the tier that runs that validation (tests/gpu_readiness.py)
// could not tell a real one from it.
Material loadMaterial(uint k) {
    return Material(materials[k].diffuse, 0.0, materials[k].specular, 0.0, materials[k].ka, materials[k].kd,
                    materials[k].ks, materials[k].shininess, materials[k].kr, materials[k].kt, materials[k].ior,
                    materials[k].flags, materials[k].checkerColor, materials[k].checkerSize,
                    materials[k].checkerOrigin, 0.0, materials[k].absorption, 0.0, materials[k].diffuseTexture,
                    materials[k].normalMap, materials[k].emissionTexture, materials[k].roughnessTexture,
                    materials[k].textureScale, materials[k].normalStrength, materials[k].glossExponent,
                    materials[k].roughness, materials[k].transmissionColor, 0.0, materials[k].emission, 0.0,
                    materials[k].ambientColor, 0.0);
}

#endif

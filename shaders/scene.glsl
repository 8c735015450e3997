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

#endif

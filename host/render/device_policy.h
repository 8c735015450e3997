// What a render decides from the device it runs on: the limits the scene's
// arrays and the descriptor set must fit, the path rays take (our BVH or the
// device's ray queries), which embedded build of the tracer runs, and the
// specialization constants it is compiled with for a scene.
#pragma once

#include "device_types.h"
#include "tracer_types.h"
#include "render/gpu_scene.h"
#include "render/render_settings.h"
#include "vk/compute_pipeline.h"
#include "vk/context.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace whitted {

// The tracer's descriptor set: the uniform block, the outputs, the adaptive
// passes' buffers, the scene's arrays and the textures. Only the
// storage-buffer build (ShaderVariant::StorageBuffers) reads the scene's
// arrays through these bindings; the others read the same buffers through
// their device addresses (shaders/scene.glsl). Ray queries add the top-level
// acceleration structure (gpu::kBindingTlas).
inline constexpr DescriptorBinding kTracerBindings[] = {
    {gpu::kBindingParams, vk::DescriptorType::eUniformBuffer},
    {gpu::kBindingOutput, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingCounters, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingPixelList, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingGuide, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingSampleStats, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingBvhNodeBuffer, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingPrimitiveBuffer, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingMaterialBuffer, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingLightBuffer, vk::DescriptorType::eStorageBuffer},
    {gpu::kBindingTextures, vk::DescriptorType::eCombinedImageSampler, gpu::kMaxTextures}};
inline constexpr uint32_t kTracerStorageBindings =
    uint32_t(std::ranges::count(kTracerBindings, vk::DescriptorType::eStorageBuffer, &DescriptorBinding::type));

// What one scene array may take on the device: its maxBufferSize (Vulkan 1.3
// or VK_KHR_maintenance4) and maxMemoryAllocationSize. The Renderer refuses
// a scene whose arrays exceed them (sceneArraysTooLarge) before packing it.
BufferLimits sceneBufferLimits(const VulkanContext& ctx);

// The descriptor set asks for more than Vulkan guarantees every device (4
// storage buffers and 16 samplers per stage; desktop GPUs and lavapipe
// offer far more): what a device with these limits lacks, in words ("offers
// 4 storage buffers per shader stage; whitted needs 9"), or "" when it has
// enough. A Renderer refuses such a device before building its pipeline.
std::string descriptorLimitShortfall(const vk::PhysicalDeviceLimits& limits);

// The path a render takes on this device: settings.trace resolved to Bvh or
// RayQuery; throws when ray queries are asked for and the device lacks them.
TracePath resolveTrace(const VulkanContext& ctx, const RenderSettings& settings);

// The embedded builds of shaders/whitted.comp.
enum class ShaderVariant {
    Addresses,       // kWhittedCompSpv: the scene's arrays through their device addresses
    StorageBuffers,  // kWhittedCompStorageBuffersSpv (-DWHITTED_SCENE_STORAGE_BUFFERS): through descriptors
    RayQuery,        // kWhittedCompRayQuerySpv (-DWHITTED_RAY_QUERY): the device's acceleration structures
    // kWhittedCompLeanSpv (-DWHITTED_NO_CSG -DWHITTED_NO_TEXTURES): Addresses without the code of csg objects
    // and textures, for a scene with neither; the same image as Addresses, bit for bit.
    AddressesLean,
};

// The build a packed scene runs with on this device along `trace` (resolved).
// fitted: a scene without csg objects and textures gets AddressesLean rather than Addresses.
ShaderVariant shaderVariantFor(const VulkanContext& ctx, const GpuScene& scene, TracePath trace, SceneReads reads,
                               bool fitted = true);

// The specialization constants for a packed scene, in the order of
// gpu::kSpecShapeMask, gpu::kSpecTransparency, gpu::kSpecListShapeMask,
// gpu::kSpecOutputOptions (the auxiliary outputs its settings ask for: a
// render without them compiles none of their code, the ids' probe ray
// included), gpu::kSpecDistribution (a lens, gloss, area lights: a scene
// without them compiles none of their sampling), gpu::kSpecFeatures (Fresnel,
// absorption, checkers, smooth triangles, spot and directional lights,
// falloff, an environment and its light: likewise).
using Specialization = std::array<uint32_t, 6>;
Specialization specializationFor(const GpuScene& scene);
// `constants` with the ones that follow the scene's materials, lights and
// camera (transparency, the distribution effects, the features but smooth
// triangles) taken from `scene`: what an edit of those changes. The
// primitives may be gone from `scene` (uploaded): what depends on them stays.
Specialization withShading(Specialization constants, const GpuScene& scene);

// A pipeline whose descriptor set layout is the tracer's along `trace`
// (kTracerBindings, and gpu::kBindingTlas for ray queries), so that a
// Renderer's descriptor set binds to it, specialised with `constants`: the
// tracer itself and the builds that run beside it on its uploaded scene
// (render/ray_tree.h, render/ray_cast.h).
ComputePipeline createTracerPipeline(const VulkanContext& ctx, std::span<const uint32_t> spirv, TracePath trace,
                                     const Specialization& constants, uint32_t pushConstantSize);

}  // namespace whitted

#include "render/device_policy.h"

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace whitted {
namespace {

// Whether the shader reads BVH nodes, primitives, materials and lights
// through kBindingBvhNodeBuffer... instead of their device addresses (the
// variant kWhittedCompStorageBuffersSpv, shaders/scene.glsl): on lavapipe
// before Mesa 25, whose device-address loads go lane by lane and word by word
// (measured: see tools/benchmark_results/README.md; from Mesa 25 the
// addresses are the faster), when every array fits one storage buffer range.
// `reads` other than Auto forces either (the latter only where the arrays
// fit; tests). In a developer build WHITTED_SCENE_READS=address or
// descriptor does the same for a render whose settings leave it at Auto
// (profiling).
bool sceneFromStorageBuffers(const VulkanContext& ctx, const GpuScene& scene, SceneReads reads) {
    auto chain = ctx.physicalDevice.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties>();
    const vk::PhysicalDeviceProperties& properties = chain.get<vk::PhysicalDeviceProperties2>().properties;
    bool fits = scene.bvhNodes.size() * sizeof(gpu::BvhNode) <= properties.limits.maxStorageBufferRange &&
                scene.primitives.size() * sizeof(gpu::Primitive) <= properties.limits.maxStorageBufferRange &&
                scene.materials.size() * sizeof(gpu::Material) <= properties.limits.maxStorageBufferRange &&
                scene.lights.size() * sizeof(gpu::Light) <= properties.limits.maxStorageBufferRange;
#ifdef WHITTED_DEVELOPER
    if (const char* force = std::getenv("WHITTED_SCENE_READS"); reads == SceneReads::Auto && force && *force)
        reads = std::string_view(force) == "descriptor" ? SceneReads::Descriptor : SceneReads::Address;
#endif
    if (reads != SceneReads::Auto) return fits && reads == SceneReads::Descriptor;
    // lavapipe's driverVersion is 1; its driverInfo reads "Mesa 22.3.6 (LLVM 15.0.6)".
    const auto& driver = chain.get<vk::PhysicalDeviceDriverProperties>();
    std::string_view info(driver.driverInfo.data());
    bool oldLavapipe = driver.driverID == vk::DriverId::eMesaLlvmpipe && info.starts_with("Mesa ") &&
                       std::atoi(info.substr(5).data()) < 25;
    return fits && oldLavapipe;
}

}  // namespace

BufferLimits sceneBufferLimits(const VulkanContext& ctx) {
    BufferLimits limits;
    const vk::raii::PhysicalDevice& physical = ctx.physicalDevice;
    auto extensions = physical.enumerateDeviceExtensionProperties();
    bool maintenance4 = physical.getProperties().apiVersion >= VK_API_VERSION_1_3 ||
                        std::any_of(extensions.begin(), extensions.end(), [](const vk::ExtensionProperties& e) {
                            return std::string_view(e.extensionName.data()) == VK_KHR_MAINTENANCE_4_EXTENSION_NAME;
                        });
    if (maintenance4) {
        auto props = physical.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceMaintenance3Properties,
                                             vk::PhysicalDeviceMaintenance4Properties>();
        limits.maxAllocationSize = props.get<vk::PhysicalDeviceMaintenance3Properties>().maxMemoryAllocationSize;
        limits.maxBufferSize = props.get<vk::PhysicalDeviceMaintenance4Properties>().maxBufferSize;
    } else {
        auto props = physical.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceMaintenance3Properties>();
        limits.maxAllocationSize = props.get<vk::PhysicalDeviceMaintenance3Properties>().maxMemoryAllocationSize;
    }
    return limits;
}

std::string descriptorLimitShortfall(const vk::PhysicalDeviceLimits& limits) {
    constexpr uint32_t kUniformBindings = 1;
    const struct {
        uint32_t offered, needed;
        const char* what;
    } needs[] = {
        {limits.maxPerStageDescriptorStorageBuffers, kTracerStorageBindings, "storage buffers per shader stage"},
        {limits.maxDescriptorSetStorageBuffers, kTracerStorageBindings, "storage buffers per descriptor set"},
        {limits.maxPerStageDescriptorSamplers, gpu::kMaxTextures, "samplers per shader stage"},
        {limits.maxPerStageDescriptorSampledImages, gpu::kMaxTextures, "sampled images per shader stage"},
        {limits.maxDescriptorSetSamplers, gpu::kMaxTextures, "samplers per descriptor set"},
        {limits.maxDescriptorSetSampledImages, gpu::kMaxTextures, "sampled images per descriptor set"},
        {limits.maxPerStageResources, kUniformBindings + kTracerStorageBindings + gpu::kMaxTextures,
         "resources per shader stage"},
    };
    for (const auto& n : needs)
        if (n.offered < n.needed)
            return "offers " + std::to_string(n.offered) + " " + n.what + "; whitted needs " + std::to_string(n.needed);
    return "";
}

// README "Ray queries": ray queries where asked for, or by default on a GPU
// that has them; on a CPU device (lavapipe) our BVH, which measured faster
// there. Without a BVH (--no-bvh, the brute-force reference) every primitive
// is tested in the shader either way.
TracePath resolveTrace(const VulkanContext& ctx, const RenderSettings& settings) {
    const DeviceInfo& device = ctx.deviceInfo();
    switch (settings.trace) {
        case TracePath::Bvh: return TracePath::Bvh;
        case TracePath::RayQuery:
            if (!device.rayQuery)
                throw std::runtime_error("--trace rayquery: device '" + device.name + "' (" + device.driver +
                                         ") lacks VK_KHR_ray_query or VK_KHR_acceleration_structure; use --trace bvh or auto");
            return settings.useBvh ? TracePath::RayQuery : TracePath::Bvh;
        case TracePath::Auto: break;
    }
    return device.rayQuery && settings.useBvh && device.type != "cpu" ? TracePath::RayQuery : TracePath::Bvh;
}

// Whether the scene has csg objects among the primitives the shader tests.
bool hasCsg(const GpuScene& scene) {
    size_t listEnd = scene.params.firstListPrimitive + scene.params.listPrimitiveCount;
    for (size_t i = 0; i < listEnd; ++i)
        if (scene.primitives[i].shape == gpu::kShapeCsg) return true;
    return false;
}

ShaderVariant shaderVariantFor(const VulkanContext& ctx, const GpuScene& scene, TracePath trace, SceneReads reads,
                               bool fitted) {
    if (trace == TracePath::RayQuery) return ShaderVariant::RayQuery;
    if (sceneFromStorageBuffers(ctx, scene, reads)) return ShaderVariant::StorageBuffers;
    return fitted && scene.textures.empty() && !hasCsg(scene) ? ShaderVariant::AddressesLean
                                                               : ShaderVariant::Addresses;
}

// The shapes in the BVH, any transparency, the shapes outside it (planes),
// the auxiliary outputs, the distribution effects (a lens, gloss, area
// lights), the shading features (Fresnel, absorption, checkers, smooth
// triangles, spot and directional lights, falloff, an environment and its
// light). What a scene lacks
// compiles out (on lavapipe every branch costs, taken or not:
// shaders/intersect.glsl).
Specialization specializationFor(const GpuScene& scene) {
    // The auxiliary outputs and the number of depth-split layers (bits 8..15).
    constexpr uint32_t kOutputOptions = gpu::kOptionWriteAovs | gpu::kOptionWriteIds | 0xffu << gpu::kOptionAovBouncesShift;
    Specialization constants = {0u, 0u, 0u, scene.params.options & kOutputOptions, 0u, 0u};
    // The csg leaves after the listed primitives are intersected by
    // intersectCsg only; smooth triangles count anywhere.
    size_t listEnd = scene.params.firstListPrimitive + scene.params.listPrimitiveCount;
    for (size_t i = 0; i < scene.primitives.size(); ++i) {
        const gpu::Primitive& p = scene.primitives[i];
        if (i < listEnd) constants[i < scene.params.firstListPrimitive ? 0 : 2] |= 1u << p.shape;
        if (p.shape == gpu::kShapeTriangle && gpu::triangleSmooth(p))
            constants[5] |= gpu::kFeatureSmoothTriangles;
    }
    // With instances, the prototypes' shapes are tested in the same walk.
    if (!scene.instances.empty()) constants[0] |= scene.prototypeShapes;
    return withShading(constants, scene);
}

Specialization withShading(Specialization constants, const GpuScene& scene) {
    constants[1] = std::any_of(scene.materials.begin(), scene.materials.end(),
                               [](const gpu::Material& m) { return m.kt > 0.0f; }) ? 1u : 0u;
    uint32_t distribution = scene.params.apertureRadius > 0.0f ? gpu::kDistributionLens : 0u;
    for (const gpu::Material& m : scene.materials)
        if ((m.flags & gpu::kMaterialGlossy) != 0u) distribution |= gpu::kDistributionGloss;
    for (const gpu::Light& l : scene.lights)
        if (l.type == gpu::kLightRect || l.radius > 0.0f) distribution |= gpu::kDistributionAreaLights;
    constants[4] = distribution;
    uint32_t features = constants[5] & gpu::kFeatureSmoothTriangles;
    for (const gpu::Material& m : scene.materials) {
        if ((m.flags & gpu::kMaterialFresnel) != 0u) features |= gpu::kFeatureFresnel;
        if (m.absorption != glm::vec3(0.0f)) features |= gpu::kFeatureAbsorption;
        if (m.checkerSize > 0.0f) features |= gpu::kFeatureChecker;
    }
    for (const gpu::Light& l : scene.lights) {
        if (l.type == gpu::kLightSpot) features |= gpu::kFeatureSpotLights;
        if (l.type == gpu::kLightDirectional) features |= gpu::kFeatureDirectionalLights;
        if (l.falloff == gpu::kFalloffInverseSquare) features |= gpu::kFeatureFalloff;
    }
    if (scene.params.environment.kind != gpu::kEnvironmentNone) {
        features |= gpu::kFeatureEnvironment;
        if (scene.params.environment.shadowSamples > 0) features |= gpu::kFeatureEnvironmentLight;
    }
    constants[5] = features;
    return constants;
}

ComputePipeline createTracerPipeline(const VulkanContext& ctx, std::span<const uint32_t> spirv, TracePath trace,
                                     const Specialization& constants, uint32_t pushConstantSize) {
    const vk::SpecializationMapEntry entries[] = {{gpu::kSpecShapeMask, 0, sizeof(uint32_t)},
                                                  {gpu::kSpecTransparency, sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecListShapeMask, 2 * sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecOutputOptions, 3 * sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecDistribution, 4 * sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecFeatures, 5 * sizeof(uint32_t), sizeof(uint32_t)}};
    vk::SpecializationInfo specialization{.mapEntryCount = 6, .pMapEntries = entries,
                                          .dataSize = sizeof(constants), .pData = constants.data()};
    std::vector<DescriptorBinding> bindings(std::begin(kTracerBindings), std::end(kTracerBindings));
    if (trace == TracePath::RayQuery) bindings.push_back({gpu::kBindingTlas, vk::DescriptorType::eAccelerationStructureKHR});
    return createComputePipeline(ctx, spirv, bindings, pushConstantSize, &specialization);
}

}  // namespace whitted

#include "render/renderer.h"

#include "shapes/shapes.h"

#include <cstdint>

#include "whitted_comp.h"  // kWhittedCompSpv, generated from shaders/whitted.comp
#include "whitted_comp_ray_query.h"  // kWhittedCompRayQuerySpv: the same with -DWHITTED_RAY_QUERY
#include "whitted_comp_storage_buffers.h"  // kWhittedCompStorageBuffersSpv: the same with -DWHITTED_SCENE_STORAGE_BUFFERS

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace whitted {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr uint32_t kTileSize = 128;

// At most this many samples of a pixel in one dispatch. llvmpipe (lavapipe)
// caps the loop iterations of one shader run at 65535, counted over ALL its
// loops together (LP_MAX_TGSI_LOOP_ITERATIONS in Mesa's gallivm), then ends
// every loop silently: 16 samples of a pixel seen through a lattice of
// 10,000 spheres overran it and lost whole samples. Fewer samples per
// dispatch keep each run far below the cap; render() checks the count of
// camera rays and reports any that are still cut off.
constexpr uint32_t kMaxSamplesPerInvocation = 4;

// Dispatches recorded into one command buffer and submission.
constexpr size_t kDispatchesPerSubmit = 4;

// Profiling hook (tools/profile_shader.sh): WHITTED_SHADER_SPV names a
// SPIR-V file compiled from shaders/whitted.comp with some feature switched
// off, used instead of the embedded shader. Empty when unset.
std::vector<uint32_t> profilingShaderVariant() {
    const char* path = std::getenv("WHITTED_SHADER_SPV");
    if (!path || !*path) return {};
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    if (!in.good() && !in.eof()) throw std::runtime_error(std::string(path) + ": cannot read WHITTED_SHADER_SPV");
    if (bytes.empty() || bytes.size() % 4 != 0)
        throw std::runtime_error(std::string(path) + ": WHITTED_SHADER_SPV is not a SPIR-V file");
    std::vector<uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), bytes.size());
    return words;
}

constexpr vk::BufferUsageFlags kStorage = vk::BufferUsageFlagBits::eStorageBuffer;

// Packs the scene after checking that each of its arrays fits one device
// buffer: a scene too large is refused before its BVH is built. Running out
// of host memory while packing or building the BVH says so with the sizes.
GpuScene packSceneThatFits(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings) {
    SceneArrayCounts counts = countSceneArrays(scene);
    if (auto problem = sceneArraysTooLarge(counts, sceneBufferLimits(ctx))) throw std::runtime_error(*problem);
    try {
        return packScene(scene, settings);
    } catch (const std::bad_alloc&) {
        uint64_t bytes = counts.primitives * sizeof(gpu::Primitive) + counts.bvhNodes * sizeof(gpu::BvhNode);
        throw std::runtime_error("out of host memory packing the scene's " + std::to_string(counts.primitives) +
                                 " primitives and building their BVH (the packed arrays alone take up to " +
                                 std::to_string(bytes >> 20) + " MiB)");
    }
}

// Whether the shader reads BVH nodes, primitives, materials and lights
// through kBindingBvhNodeBuffer... instead of their device addresses (the
// variant kWhittedCompStorageBuffersSpv, shaders/scene.glsl): on lavapipe
// before Mesa 25, whose device-address loads go lane by lane and word by word
// (measured on 22.3: the room renders 2.7x faster through the descriptors;
// 25.0: nodes alone 1.8x slower), when every array fits one storage buffer
// range.
// WHITTED_SCENE_READS=address or descriptor overrides the choice (the
// latter only where the arrays fit; profiling, tests).
bool sceneFromStorageBuffers(const VulkanContext& ctx, const GpuScene& scene) {
    auto chain = ctx.physicalDevice.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties>();
    const vk::PhysicalDeviceProperties& properties = chain.get<vk::PhysicalDeviceProperties2>().properties;
    bool fits = scene.bvhNodes.size() * sizeof(gpu::BvhNode) <= properties.limits.maxStorageBufferRange &&
                scene.primitives.size() * sizeof(gpu::Primitive) <= properties.limits.maxStorageBufferRange &&
                scene.materials.size() * sizeof(gpu::Material) <= properties.limits.maxStorageBufferRange &&
                scene.lights.size() * sizeof(gpu::Light) <= properties.limits.maxStorageBufferRange;
    if (const char* force = std::getenv("WHITTED_SCENE_READS"); force && *force)
        return fits && std::string_view(force) == "descriptor";
    // lavapipe's driverVersion is 1; its driverInfo reads "Mesa 22.3.6 (LLVM 15.0.6)".
    const auto& driver = chain.get<vk::PhysicalDeviceDriverProperties>();
    std::string_view info(driver.driverInfo.data());
    bool oldLavapipe = driver.driverID == vk::DriverId::eMesaLlvmpipe && info.starts_with("Mesa ") &&
                       std::atoi(info.substr(5).data()) < 25;
    return fits && oldLavapipe;
}

// Specialization constants for a packed scene: the shapes in the BVH, any
// transparency, the shapes outside it (planes). What a scene lacks compiles
// out (on lavapipe every branch costs, taken or not: shaders/intersect.glsl).
std::array<uint32_t, 4> specializationFor(const VulkanContext& ctx, const GpuScene& scene) {
    std::array<uint32_t, 4> constants = {0u, 0u, 0u, 0u};
    // The csg leaves after the listed primitives are intersected by
    // intersectCsg only.
    size_t listEnd = scene.params.firstListPrimitive + scene.params.listPrimitiveCount;
    for (size_t i = 0; i < listEnd; ++i)
        constants[i < scene.params.firstListPrimitive ? 0 : 2] |= 1u << scene.primitives[i].shape;
    for (const gpu::Material& m : scene.materials) constants[1] |= m.kt > 0.0f ? 1u : 0u;
    constants[3] = sceneFromStorageBuffers(ctx, scene) ? 1u : 0u;  // not a constant: the shader variant
    return constants;
}

// The descriptor set: the scene's arrays are not in it (device addresses,
// shaders/scene.glsl).
constexpr DescriptorBinding kBindings[] = {{gpu::kBindingParams, vk::DescriptorType::eUniformBuffer},
                                           {gpu::kBindingOutput, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingCounters, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingPixelList, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingGuide, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingSampleStats, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingBvhNodeBuffer, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingPrimitiveBuffer, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingMaterialBuffer, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingLightBuffer, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingTextures, vk::DescriptorType::eCombinedImageSampler,
                                            gpu::kMaxTextures}};
constexpr uint32_t kStorageBindings = uint32_t(std::ranges::count(
    kBindings, vk::DescriptorType::eStorageBuffer, &DescriptorBinding::type));

// The path a render takes on this device (README "Ray queries"): ray
// queries where asked for, or by default on a GPU that has them; on a CPU
// device (lavapipe) our BVH, which measured faster there. Without a BVH
// (--no-bvh, the brute-force reference) every primitive is tested in the
// shader either way.
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

// The device address of a buffer as the (low, high) words FrameParams holds.
glm::uvec2 addressWords(const Buffer& b) { return {uint32_t(b.address), uint32_t(b.address >> 32)}; }

constexpr vk::MemoryPropertyFlags kHostVisible =
    vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent;

// The region a render covers: settings.region, checked against the image.
PixelRegion regionFor(const RenderSettings& settings, int width, int height) {
    if (!settings.region) return {0, 0, width, height};
    const PixelRegion& r = *settings.region;
    if (r.x0 < 0 || r.y0 < 0 || r.x1 > width || r.y1 > height || r.x0 >= r.x1 || r.y0 >= r.y1)
        throw std::invalid_argument("region " + std::to_string(r.x0) + "," + std::to_string(r.y0) + "," +
                                    std::to_string(r.x1) + "," + std::to_string(r.y1) +
                                    " is empty or outside the " + std::to_string(width) + "x" +
                                    std::to_string(height) + " image");
    return r;
}

}  // namespace

std::string descriptorLimitShortfall(const vk::PhysicalDeviceLimits& limits) {
    constexpr uint32_t kUniformBindings = 1;
    const struct {
        uint32_t offered, needed;
        const char* what;
    } needs[] = {
        {limits.maxPerStageDescriptorStorageBuffers, kStorageBindings, "storage buffers per shader stage"},
        {limits.maxDescriptorSetStorageBuffers, kStorageBindings, "storage buffers per descriptor set"},
        {limits.maxPerStageDescriptorSamplers, gpu::kMaxTextures, "samplers per shader stage"},
        {limits.maxPerStageDescriptorSampledImages, gpu::kMaxTextures, "sampled images per shader stage"},
        {limits.maxDescriptorSetSamplers, gpu::kMaxTextures, "samplers per descriptor set"},
        {limits.maxDescriptorSetSampledImages, gpu::kMaxTextures, "sampled images per descriptor set"},
        {limits.maxPerStageResources, kUniformBindings + kStorageBindings + gpu::kMaxTextures,
         "resources per shader stage"},
    };
    for (const auto& n : needs)
        if (n.offered < n.needed)
            return "offers " + std::to_string(n.offered) + " " + n.what + "; whitted needs " + std::to_string(n.needed);
    return "";
}


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

Renderer::Renderer(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx), settings_(settings), scene_(packSceneThatFits(ctx, scene, settings)),
      trace_(resolveTrace(ctx, settings)) {
    if (scene_.width < 1 || scene_.height < 1 || scene_.width > 16384 || scene_.height > 16384)
        throw std::runtime_error("image size " + std::to_string(scene_.width) + "x" + std::to_string(scene_.height) +
                                 " is outside 1..16384");
    if (settings.samplesPerPixel < 1 || settings.samplesPerPixel > 65536)
        throw std::runtime_error("samples per pixel must be in 1..65536, got " + std::to_string(settings.samplesPerPixel));
    if (settings.maxDepth < 0 || settings.maxDepth > int(gpu::kMaxDepthLimit))
        throw std::runtime_error("max depth must be in 0.." + std::to_string(gpu::kMaxDepthLimit) + ", got " +
                                 std::to_string(settings.maxDepth));
    if (settings.aovBounces < 0 || settings.aovBounces > int(gpu::kAovBouncesMax))
        throw std::runtime_error("auxiliary bounces must be in 0.." + std::to_string(gpu::kAovBouncesMax) + ", got " +
                                 std::to_string(settings.aovBounces));
    layerCount_ = settings.auxiliary ? gpu::kAovCount + 2 * uint32_t(settings.aovBounces) : 1;
    layout_ = {.fullWidth = scene_.width, .fullHeight = scene_.height,
               .region = regionFor(settings, scene_.width, scene_.height), .layerCount = layerCount_};

    // Bands of whole rows of the region, as many rows as bandBytes pays for
    // (output layers, plus the adaptive pass's list, statistics and guide),
    // and never more than one storage buffer can address. bandBytes 0 keeps
    // the whole image (the window draws from it).
    const PixelRegion& region = layout_.region;
    bool adaptive = settings.antiAliasing == AntiAliasing::Adaptive;
    vk::DeviceSize maxRange = ctx.physicalDevice.getProperties().limits.maxStorageBufferRange;
    vk::DeviceSize outputRow = vk::DeviceSize(layerCount_) * region.width() * sizeof(glm::vec4);
    // The adaptive passes trace a border of up to `border` pixels around the band.
    uint32_t border = adaptive ? uint32_t(refinementLevels(uint32_t(settings.samplesPerPixel)).size()) : 0;
    vk::DeviceSize rowBytes = outputRow + (adaptive ? vk::DeviceSize(region.width() + 2 * border) * (4 + 32 + 16) : 0);
    if (settings.bandBytes == 0) {
        bandRows_ = uint32_t(region.height());
        if (outputRow * bandRows_ > maxRange)
            throw std::runtime_error("the image and its auxiliary layers need " +
                                     std::to_string((outputRow * bandRows_) >> 20) +
                                     " MiB, more than this device's storage buffer limit of " +
                                     std::to_string(maxRange >> 20) + " MiB; render smaller or with --aov none");
    } else {
        vk::DeviceSize rows = std::min(settings.bandBytes / rowBytes, maxRange / outputRow);
        bandRows_ = uint32_t(std::clamp<vk::DeviceSize>(rows, 1, vk::DeviceSize(region.height())));
    }

    size_t bandPixels = size_t(bandRows_ + 2 * border) * (region.width() + 2 * border);
    params_ = createBuffer(ctx, sizeof(gpu::FrameParams), vk::BufferUsageFlagBits::eUniformBuffer, kHostVisible);
    output_ = createDeviceBuffer(ctx, nullptr, outputRow * bandRows_, kStorage | vk::BufferUsageFlagBits::eTransferSrc);
    counters_ = createBuffer(ctx, sizeof(gpu::RayCounters), kStorage, kHostVisible);
    size_t adaptivePixels = adaptive ? bandPixels : 1;  // a buffer must not be empty
    pixelList_ = createBuffer(ctx, adaptivePixels * sizeof(uint32_t), kStorage, kHostVisible);
    sampleStats_ = createBuffer(ctx, adaptivePixels * 2 * sizeof(glm::uvec4), kStorage, kHostVisible);
    guide_ = createBuffer(ctx, adaptivePixels * sizeof(glm::uvec4), kStorage, kHostVisible);
    if (settings.bandBytes != 0)
        readback_ = createBuffer(ctx, outputRow * bandRows_, vk::BufferUsageFlagBits::eTransferDst, kHostVisible);
    vk::DescriptorPoolSize poolSizes[] = {{vk::DescriptorType::eUniformBuffer, 1},
                                          {vk::DescriptorType::eStorageBuffer, kStorageBindings},
                                          {vk::DescriptorType::eCombinedImageSampler, gpu::kMaxTextures},
                                          {vk::DescriptorType::eAccelerationStructureKHR, 1}};
    uint32_t poolSizeCount = trace_ == TracePath::RayQuery ? 4 : 3;
    descriptorPool_ = vk::raii::DescriptorPool(
        ctx.device, vk::DescriptorPoolCreateInfo{.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                 .maxSets = 1, .poolSizeCount = poolSizeCount, .pPoolSizes = poolSizes});
    buildPipeline();
    uploadScene();
}

// The pipeline specialised for scene_, and the one descriptor set (from a
// pool of one) that uploadScene() fills.
void Renderer::buildPipeline() {
    auto start = Clock::now();
    if (std::string shortfall = descriptorLimitShortfall(ctx_.physicalDevice.getProperties().limits); !shortfall.empty())
        throw std::runtime_error("device " + ctx_.deviceInfo().name + " " + shortfall);
    specialization_ = specializationFor(ctx_, scene_);
    const vk::SpecializationMapEntry entries[] = {{gpu::kSpecShapeMask, 0, sizeof(uint32_t)},
                                                  {gpu::kSpecTransparency, sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecListShapeMask, 2 * sizeof(uint32_t), sizeof(uint32_t)}};
    vk::SpecializationInfo specialization{.mapEntryCount = 3, .pMapEntries = entries,
                                          .dataSize = sizeof(specialization_), .pData = specialization_.data()};
    std::vector<uint32_t> variant = profilingShaderVariant();
    bool rayQuery = trace_ == TracePath::RayQuery;
    std::span<const uint32_t> embedded = rayQuery                ? std::span<const uint32_t>(kWhittedCompRayQuerySpv)
                                         : specialization_[3] != 0u ? std::span<const uint32_t>(kWhittedCompStorageBuffersSpv)
                                                                    : std::span<const uint32_t>(kWhittedCompSpv);
    std::vector<DescriptorBinding> bindings(std::begin(kBindings), std::end(kBindings));
    if (rayQuery) bindings.push_back({gpu::kBindingTlas, vk::DescriptorType::eAccelerationStructureKHR});
    descriptorSet_ = nullptr;  // freed before the layout it was allocated with goes
    pipeline_ = createComputePipeline(ctx_, variant.empty() ? embedded : variant, bindings, sizeof(gpu::TileParams),
                                      &specialization);
    vk::DescriptorSetLayout setLayout = *pipeline_.setLayout;
    descriptorSet_ = std::move(vk::raii::DescriptorSets(
        ctx_.device, {.descriptorPool = *descriptorPool_, .descriptorSetCount = 1, .pSetLayouts = &setLayout}).front());
    pipelineSeconds_ = secondsSince(start);
}

// Scene buffers, their addresses in the uniform block, and the descriptor
// set naming the uniform block and the outputs.
void Renderer::uploadScene() {
    auto start = Clock::now();
    auto upload = [&](const auto& array, const char* what) {
        vk::DeviceSize bytes = array.size() * sizeof(array[0]);
        try {
            return createDeviceBuffer(ctx_, array.data(), bytes,
                                      vk::BufferUsageFlagBits::eShaderDeviceAddress | kStorage);
        } catch (const std::runtime_error& e) {
            throw std::runtime_error("uploading the scene's " + std::to_string(array.size()) + " " + what + " (" +
                                     std::to_string(bytes) + " bytes; " + std::to_string(deviceBytes_ >> 20) +
                                     " MiB already on the device): " + e.what());
        }
    };
    deviceBytes_ = params_.size + output_.size + counters_.size + pixelList_.size + guide_.size + sampleStats_.size +
                   readback_.size;
    primitives_ = {};  // a re-upload (setScene) frees the old arrays first
    materials_ = {};
    lights_ = {};
    bvhNodes_ = {};
    csgNodes_ = {};
    accelerationStructures_ = {};
    if (trace_ == TracePath::RayQuery) {
        // The device's structures over the bounded primitives replace the
        // BVH, whose nodes the shader variant never reads.
        accelerationStructures_ = buildAccelerationStructures(
            ctx_, std::span(scene_.primitives).first(scene_.params.firstListPrimitive));
        deviceBytes_ += accelerationStructures_.bytes();
        std::vector<gpu::BvhNode>().swap(scene_.bvhNodes);
    }
    // The large arrays live on the device from now on: their host copies go
    // as soon as they are uploaded (a 10M-triangle mesh: 1 GB less host memory).
    primitives_ = upload(scene_.primitives, "primitives");
    deviceBytes_ += primitives_.size;
    std::vector<gpu::Primitive>().swap(scene_.primitives);
    bvhNodes_ = upload(scene_.bvhNodes, "BVH nodes");
    deviceBytes_ += bvhNodes_.size;
    std::vector<gpu::BvhNode>().swap(scene_.bvhNodes);
    materials_ = upload(scene_.materials, "materials");
    deviceBytes_ += materials_.size;
    lights_ = upload(scene_.lights, "lights");
    deviceBytes_ += lights_.size;
    csgNodes_ = upload(scene_.csgNodes, "CSG nodes");
    deviceBytes_ += csgNodes_.size;
    glm::uvec2 p = addressWords(primitives_), n = addressWords(bvhNodes_);
    glm::uvec2 m = addressWords(materials_), l = addressWords(lights_);
    scene_.params.primitiveAddress = p;
    scene_.params.bvhNodeAddress = n;
    scene_.params.materialAddress = m;
    scene_.params.lightAddress = l;
    scene_.params.csgNodeAddress = addressWords(csgNodes_);
    // Textures and the per-primitive surface attributes (UVs of textured
    // meshes; address 0 when no mesh needs them).
    attributes_ = {};
    textures_ = {};
    textures_ = TextureSet(ctx_, scene_.textures);
    deviceBytes_ += textures_.bytes();
    if (!scene_.attributes.empty()) {
        attributes_ = upload(scene_.attributes, "surface attributes");
        deviceBytes_ += attributes_.size;
        std::vector<gpu::SurfaceAttributes>().swap(scene_.attributes);
    }
    scene_.params.attributeAddress = addressWords(attributes_);  // 0 when not made
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));

    // In the order of kBindings.
    const Buffer* buffers[] = {&params_, &output_, &counters_, &pixelList_, &guide_, &sampleStats_, &bvhNodes_,
                               &primitives_, &materials_, &lights_};
    // Arrays beyond one storage buffer range are read through their address
    // only (sceneFromStorageBuffers); the descriptor then names the first range.
    vk::DeviceSize maxRange = ctx_.physicalDevice.getProperties().limits.maxStorageBufferRange;
    std::vector<vk::DescriptorBufferInfo> infos;
    for (const Buffer* b : buffers) infos.push_back({*b->buffer, 0, std::min(b->size, maxRange)});
    std::vector<vk::WriteDescriptorSet> writes;
    for (uint32_t i = 0; i < infos.size(); ++i)
        writes.push_back({.dstSet = *descriptorSet_, .dstBinding = kBindings[i].binding, .descriptorCount = 1,
                          .descriptorType = kBindings[i].type, .pBufferInfo = &infos[i]});
    std::vector<vk::DescriptorImageInfo> textureInfos = textures_.descriptorInfos();
    writes.push_back({.dstSet = *descriptorSet_,
                      .dstBinding = gpu::kBindingTextures,
                      .descriptorCount = gpu::kMaxTextures,
                      .descriptorType = vk::DescriptorType::eCombinedImageSampler,
                      .pImageInfo = textureInfos.data()});
    vk::AccelerationStructureKHR tlas = *accelerationStructures_.top.handle;
    vk::WriteDescriptorSetAccelerationStructureKHR tlasInfo{.accelerationStructureCount = 1,
                                                            .pAccelerationStructures = &tlas};
    if (trace_ == TracePath::RayQuery)
        writes.push_back({.pNext = &tlasInfo, .dstSet = *descriptorSet_, .dstBinding = gpu::kBindingTlas,
                          .descriptorCount = 1, .descriptorType = vk::DescriptorType::eAccelerationStructureKHR});
    ctx_.device.updateDescriptorSets(writes, nullptr);
    uploadSeconds_ = secondsSince(start);
}

void Renderer::setScene(const Scene& scene) {
    RenderSettings settings = settings_;
    settings.width = scene_.width;  // the image size stays
    settings.height = scene_.height;
    scene_ = packSceneThatFits(ctx_, scene, settings);
    // A shape or glass the old scene lacked needs the pipeline that has it.
    if (specializationFor(ctx_, scene_) != specialization_) buildPipeline();
    uploadScene();
}

void Renderer::setCamera(const Camera& camera) {
    Scene cameraOnly;
    cameraOnly.camera = camera;
    RenderSettings settings = settings_;
    settings.width = scene_.width;
    settings.height = scene_.height;
    gpu::FrameParams fresh = packScene(cameraOnly, settings).params;
    scene_.params.eye = fresh.eye;
    scene_.params.forward = fresh.forward;
    scene_.params.right = fresh.right;
    scene_.params.up = fresh.up;
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));
}

void Renderer::recordClear(const vk::raii::CommandBuffer& cmd) const {
    vk::MemoryBarrier before{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eShaderRead,
                             .dstAccessMask = vk::AccessFlagBits::eTransferWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eTransfer, {}, before,
                        nullptr, nullptr);
    cmd.fillBuffer(*output_.buffer, 0, VK_WHOLE_SIZE, 0);
}

void Renderer::recordDispatch(const vk::raii::CommandBuffer& cmd, const gpu::TileParams& params, uint32_t groupsX,
                              uint32_t groupsY) const {
    vk::MemoryBarrier accumulate{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite |
                                                  vk::AccessFlagBits::eHostWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer |
                            vk::PipelineStageFlagBits::eHost,
                        vk::PipelineStageFlagBits::eComputeShader, {}, accumulate, nullptr, nullptr);
    cmd.pushConstants<gpu::TileParams>(*pipeline_.layout, vk::ShaderStageFlagBits::eCompute, 0, params);
    cmd.dispatch(groupsX, groupsY, 1);
}

// One dispatch per kMaxSamplesPerInvocation samples of the range (lavapipe's
// loop cap, see above), each after a barrier on the ones before.
void Renderer::recordTile(const vk::raii::CommandBuffer& cmd, const gpu::TileParams& tile) const {
    if (settings_.bandBytes != 0) throw std::logic_error("Renderer::recordTile needs the whole image resident");
    cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_.pipeline);
    cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline_.layout, 0, *descriptorSet_, nullptr);
    for (uint32_t done = 0; done < tile.sampleCount; done += kMaxSamplesPerInvocation) {
        gpu::TileParams part = tile;
        part.firstSample = tile.firstSample + done;
        part.sampleCount = std::min(kMaxSamplesPerInvocation, tile.sampleCount - done);
        part.patternSize = uint32_t(settings_.samplesPerPixel);
        part.flags = 0u;
        part.outputOrigin = glm::uvec2(0, 0);
        part.outputSize = glm::uvec2(scene_.width, scene_.height);
        recordDispatch(cmd, part, (tile.tileSize.x + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize,
                       (tile.tileSize.y + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize);
    }
}

RenderResult Renderer::readMeans() const {
    RenderResult result;
    result.width = scene_.width;
    result.height = scene_.height;
    result.hasAuxiliary = settings_.auxiliary;
    size_t pixels = size_t(scene_.width) * scene_.height;
    std::vector<float> raw(pixels * 4 * layerCount_);
    result.layers.resize(std::max(gpu::kAovCount, layerCount_));
    readBuffer(ctx_, output_, raw.data(), raw.size() * sizeof(float));
    uint32_t minimum = UINT32_MAX;
    for (size_t i = 0; i < pixels; ++i) minimum = std::min(minimum, uint32_t(raw[i * 4 + 3]));
    result.samplesPerPixel = int(minimum);
    for (uint32_t layer = 0; layer < layerCount_; ++layer) {
        auto& out = result.layers[layer];
        out.assign(raw.begin() + layer * pixels * 4, raw.begin() + (layer + 1) * pixels * 4);
        for (size_t i = 0; i < pixels; ++i) {
            float count = raw[i * 4 + 3];
            for (int c = 0; c < 4; ++c) out[i * 4 + c] = count > 0 ? out[i * 4 + c] / count : 0.0f;
        }
    }
    result.bvh = scene_.bvhStats;
    result.trace = trace_;
    result.accelerationStructureSeconds = accelerationStructures_.buildSeconds;
    return result;
}

// Dispatches go to the queue in batches of kDispatchesPerSubmit, each after
// a barrier (later dispatches may accumulate into the same pixels); the ray
// counters are read, and the camera rays checked, once per batch.
class Renderer::Batch {
public:
    Batch(const Renderer& renderer, RenderResult& result)
        : renderer_(renderer), result_(result),
          commandBuffers_(renderer.ctx_.device, {.commandPool = *renderer.ctx_.commandPool,
                                                 .level = vk::CommandBufferLevel::ePrimary, .commandBufferCount = 1}),
          fence_(renderer.ctx_.device, vk::FenceCreateInfo{}) {}

    // One dispatch; `cameraSamples` = pixels x samples it traces.
    void add(const gpu::TileParams& params, uint32_t groupsX, uint32_t groupsY, uint64_t cameraSamples) {
        vk::raii::CommandBuffer& cmd = commandBuffers_.front();
        if (recorded_ == 0) {
            begin();
            cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *renderer_.pipeline_.pipeline);
            cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *renderer_.pipeline_.layout, 0,
                                   *renderer_.descriptorSet_, nullptr);
        }
        renderer_.recordDispatch(cmd, params, groupsX, groupsY);
        expected_ += cameraSamples;
        if (++recorded_ == kDispatchesPerSubmit) flush();
    }

    // Submits what is recorded, with `copyBand` bytes of the output buffer
    // copied to the read-back buffer after it, and waits.
    void flush(vk::DeviceSize copyBand = 0) {
        vk::raii::CommandBuffer& cmd = commandBuffers_.front();
        if (recorded_ == 0 && copyBand == 0) return;
        if (recorded_ == 0) begin();
        if (copyBand > 0) {
            vk::MemoryBarrier toCopy{.srcAccessMask = vk::AccessFlagBits::eShaderWrite,
                                     .dstAccessMask = vk::AccessFlagBits::eTransferRead};
            cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eTransfer, {},
                                toCopy, nullptr, nullptr);
            cmd.copyBuffer(*renderer_.output_.buffer, *renderer_.readback_.buffer, vk::BufferCopy{0, 0, copyBand});
        }
        vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eHostRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                            vk::PipelineStageFlagBits::eHost, {}, toHost, nullptr, nullptr);
        cmd.end();
        vk::CommandBuffer raw = *cmd;
        renderer_.ctx_.queue.submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &raw}, *fence_);
        vk::Result waited = renderer_.ctx_.device.waitForFences(*fence_, VK_TRUE, UINT64_MAX);
        if (waited != vk::Result::eSuccess) throw std::runtime_error("vkWaitForFences: " + vk::to_string(waited));
        renderer_.ctx_.device.resetFences(*fence_);

        // One camera ray per sample: fewer means the driver cut a run short.
        const auto* counters = static_cast<const gpu::RayCounters*>(renderer_.counters_.mapped);
        if (counters->primary < expected_) result_.lostSamples += expected_ - counters->primary;
        result_.rays.primary += counters->primary;
        result_.rays.shadow += counters->shadow;
        result_.rays.secondary += counters->secondary;
        result_.samplesTaken += expected_;
        recorded_ = 0;
        expected_ = 0;
    }

private:
    // A fresh command buffer, and ray counters zeroed for it.
    void begin() {
        *static_cast<gpu::RayCounters*>(renderer_.counters_.mapped) = {};
        commandBuffers_.front().reset();
        commandBuffers_.front().begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
    }

    const Renderer& renderer_;
    RenderResult& result_;
    vk::raii::CommandBuffers commandBuffers_;
    vk::raii::Fence fence_;
    size_t recorded_ = 0;
    uint64_t expected_ = 0;
};

namespace {

// Tiles of at most kTileSize^2 pixels covering `rect`.
template <typename F>
void forEachTile(const PixelRect& rect, F&& f) {
    for (uint32_t y = 0; y < rect.height; y += kTileSize)
        for (uint32_t x = 0; x < rect.width; x += kTileSize)
            f(PixelRect{rect.x0 + x, rect.y0 + y, std::min(kTileSize, rect.width - x), std::min(kTileSize, rect.height - y)});
}

glm::uvec2 originOf(const PixelRect& r) { return {r.x0, r.y0}; }
glm::uvec2 sizeOf(const PixelRect& r) { return {r.width, r.height}; }

uint32_t groupsFor(uint32_t n) { return (n + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize; }

}  // namespace

// Every pixel of the band takes samples [0, spp) of the spp pattern, in
// dispatches of at most samplesPerDispatch camera samples and
// kMaxSamplesPerInvocation samples a pixel; the first replaces the band
// buffer's old sums. Sample indices are global, so the split changes only
// the grouping, never which samples are traced or the order they are added.
void Renderer::renderBandUniform(Batch& batch, const PixelRect& band) {
    uint32_t spp = uint32_t(settings_.samplesPerPixel);
    forEachTile(band, [&](const PixelRect& tile) {
        uint64_t pixels = uint64_t(tile.width) * tile.height;
        uint32_t chunk = uint32_t(std::clamp<uint64_t>(std::max<uint64_t>(settings_.samplesPerDispatch, 1) / pixels, 1, spp));
        chunk = std::min(chunk, kMaxSamplesPerInvocation);
        for (uint32_t s = 0; s < spp; s += chunk) {
            uint32_t n = std::min(chunk, spp - s);
            gpu::TileParams params{.tileOrigin = originOf(tile),
                                   .tileSize = sizeOf(tile),
                                   .firstSample = s,
                                   .sampleCount = n,
                                   .patternSize = spp,
                                   .flags = s == 0 ? gpu::kTileOverwrite : 0u,
                                   .outputOrigin = originOf(band),
                                   .outputSize = sizeOf(band)};
            batch.add(params, groupsFor(tile.width), groupsFor(tile.height), pixels * n);
        }
    });
}

// Adaptive anti-aliasing (render/adaptive.h): the centre sample of every
// pixel of the band and of its one-pixel border (the border only feeds the
// guide), then refinement passes over the pixels that need them.
void Renderer::renderBandAdaptive(Batch& batch, const PixelRect& band) {
    // Level k's pixels are decided on the band grown by L - k + 1 pixels
    // (L levels), from level k - 1's samples one pixel further out: each
    // level is traced in a border one pixel narrower, down to the band.
    std::vector<uint32_t> levels = refinementLevels(uint32_t(settings_.samplesPerPixel));
    uint32_t border = uint32_t(levels.size());
    uint32_t width = uint32_t(scene_.width), height = uint32_t(scene_.height);
    PixelRect guideRect = grow(band, border, width, height);
    forEachTile(guideRect, [&](const PixelRect& tile) {
        gpu::TileParams params{.tileOrigin = originOf(tile),
                               .tileSize = sizeOf(tile),
                               .firstSample = 0,
                               .sampleCount = 1,
                               .patternSize = 1,
                               .flags = gpu::kTileOverwrite | gpu::kTileGuide,
                               .outputOrigin = originOf(band),
                               .outputSize = sizeOf(band),
                               .guideOrigin = originOf(guideRect),
                               .guideSize = sizeOf(guideRect)};
        batch.add(params, groupsFor(tile.width), groupsFor(tile.height), uint64_t(tile.width) * tile.height);
    });
    batch.flush();
    if (levels.empty()) return;
    std::vector<uint32_t> list = pixelsToRefine(
        std::span(static_cast<const glm::uvec4*>(guide_.mapped), size_t(guideRect.width) * guideRect.height), guideRect,
        grow(band, border - 1, width, height), settings_.aaThreshold);

    for (size_t level = 0; level < levels.size() && !list.empty(); ++level) {
        uint32_t n = levels[level];
        std::memcpy(pixelList_.mapped, list.data(), list.size() * sizeof(uint32_t));
        // Slices of the list small enough for samplesPerDispatch.
        uint32_t chunk = std::min(n, kMaxSamplesPerInvocation);
        uint32_t slice = uint32_t(std::max<uint64_t>(settings_.samplesPerDispatch / chunk, gpu::kListGroupSize));
        for (uint32_t first = 0; first < list.size(); first += slice) {
            uint32_t count = std::min<uint32_t>(slice, uint32_t(list.size()) - first);
            for (uint32_t s = 0; s < n; s += chunk) {
                uint32_t k = std::min(chunk, n - s);
                uint32_t flags = gpu::kTileList | gpu::kTileStats | (s == 0 ? gpu::kTileOverwrite : 0u);
                gpu::TileParams params{.firstSample = s,
                                       .sampleCount = k,
                                       .patternSize = n,
                                       .flags = flags,
                                       .outputOrigin = originOf(band),
                                       .outputSize = sizeOf(band),
                                       .listFirst = first,
                                       .listCount = count};
                batch.add(params, (count + gpu::kListGroupSize - 1) / gpu::kListGroupSize, 1, uint64_t(count) * k);
            }
        }
        batch.flush();
        if (level + 1 == levels.size()) break;
        list = pixelsStillVarying(list, std::span(static_cast<const glm::uvec4*>(sampleStats_.mapped), 2 * list.size()),
                                  settings_.aaThreshold, grow(band, border - 2 - uint32_t(level), width, height));
    }
}

RenderResult Renderer::renderTo(BandSink& sink, const ProgressCallback& progress, uint32_t firstBand,
                                uint32_t bandStep) {
    if (settings_.bandBytes == 0) throw std::logic_error("Renderer::renderTo needs bands (RenderSettings::bandBytes)");
    auto start = Clock::now();
    RenderResult result;
    result.width = layout_.region.width();
    result.height = layout_.region.height();
    result.samplesPerPixel = settings_.samplesPerPixel;
    result.hasAuxiliary = settings_.auxiliary;
    result.layout = layout_;
    Batch batch(*this, result);

    const PixelRegion& region = layout_.region;
    std::vector<float> counts;
    uint32_t bandCount = (uint32_t(region.height()) + bandRows_ - 1) / bandRows_;
    uint32_t mine = firstBand < bandCount ? (bandCount - firstBand + bandStep - 1) / bandStep : 0;
    for (uint32_t index = firstBand; index < bandCount; index += bandStep) {
        int y = region.y0 + int(index * bandRows_);
        PixelRect band{uint32_t(region.x0), uint32_t(y), uint32_t(region.width()),
                       uint32_t(std::min<int>(int(bandRows_), region.y1 - y))};
        if (settings_.antiAliasing == AntiAliasing::Adaptive)
            renderBandAdaptive(batch, band);
        else
            renderBandUniform(batch, band);
        size_t pixels = size_t(band.width) * band.height;
        batch.flush(vk::DeviceSize(layerCount_) * pixels * sizeof(glm::vec4));

        // Sums to means: every layer of a pixel over the samples it took
        // (w of its colour layer); the hit-mask layers average the same way.
        // In place, in the mapped read-back buffer: no host copy of the band.
        float* raw = static_cast<float*>(readback_.mapped);
        counts.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) counts[i] = raw[i * 4 + 3];
        for (uint32_t layer = 0; layer < layerCount_; ++layer)
            for (size_t i = 0; i < pixels; ++i) {
                float inverse = counts[i] > 0 ? 1.0f / counts[i] : 0.0f;
                for (int c = 0; c < 4; ++c) raw[(layer * pixels + i) * 4 + c] *= inverse;
            }
        std::span<const float> means(raw, size_t(layerCount_) * pixels * 4);
        sink.writeBand({.index = int(index), .y0 = y, .rows = int(band.height), .width = int(band.width), .layers = means,
                        .sampleCounts = counts});
        ++result.bands;
        if (progress) progress(double(result.bands) / double(mine));
    }
    result.renderSeconds = secondsSince(start);
    result.uploadSeconds = uploadSeconds_;
    result.pipelineSeconds = pipelineSeconds_;
    result.deviceBytes = deviceBytes_;
    result.bvh = scene_.bvhStats;
    result.trace = trace_;
    result.accelerationStructureSeconds = accelerationStructures_.buildSeconds;
    return result;
}

namespace {
// Keeps every band in a RenderResult's layers.
class MemorySink final : public BandSink {
public:
    explicit MemorySink(RenderResult& result) : result_(result) {
        size_t pixels = size_t(result.layout.region.width()) * result.layout.region.height();
        result_.layers.resize(std::max(gpu::kAovCount, result.layout.layerCount));
        for (uint32_t l = 0; l < result.layout.layerCount; ++l) result_.layers[l].resize(pixels * 4);
        result_.sampleCounts.resize(pixels);
    }
    void writeBand(const BandView& band) override {
        size_t offset = size_t(band.y0 - result_.layout.region.y0) * band.width;
        for (uint32_t l = 0; l < result_.layout.layerCount; ++l) {
            std::span<const float> from = band.layer(l);
            std::copy(from.begin(), from.end(), result_.layers[l].begin() + offset * 4);
        }
        std::copy(band.sampleCounts.begin(), band.sampleCounts.end(), result_.sampleCounts.begin() + offset);
    }

private:
    RenderResult& result_;
};
}  // namespace

RenderResult Renderer::render(const ProgressCallback& progress) {
    RenderResult pixels;
    pixels.layout = layout_;
    MemorySink sink(pixels);
    RenderResult result = renderTo(sink, progress);
    result.layers = std::move(pixels.layers);
    result.sampleCounts = std::move(pixels.sampleCounts);
    return result;
}

}  // namespace whitted

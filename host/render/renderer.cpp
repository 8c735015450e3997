#include "render/renderer.h"

#include "shapes/shapes.h"

#include "whitted_comp.h"  // kWhittedCompSpv, generated from shaders/whitted.comp
#include "whitted_comp_ray_query.h"  // kWhittedCompRayQuerySpv: the same with -DWHITTED_RAY_QUERY
#include "whitted_comp_storage_buffers.h"  // kWhittedCompStorageBuffersSpv: the same with -DWHITTED_SCENE_STORAGE_BUFFERS
#include "whitted_comp_lean.h"  // kWhittedCompLeanSpv: the same with -DWHITTED_NO_CSG -DWHITTED_NO_TEXTURES

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>
#ifdef WHITTED_DEVELOPER
#include <cstdlib>
#include <fstream>
#include <iterator>
#endif

namespace whitted {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

#ifdef WHITTED_DEVELOPER
// Developer build only (tools/profile_shader.sh): WHITTED_SHADER_SPV names a
// SPIR-V file compiled from shaders/whitted.comp with some feature switched
// off, used instead of the embedded shader. Empty when unset.
std::vector<uint32_t> shaderOverride() {
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
#endif

// The embedded SPIR-V of a tracer build.
std::span<const uint32_t> embeddedTracer(ShaderVariant variant) {
    switch (variant) {
        case ShaderVariant::StorageBuffers: return kWhittedCompStorageBuffersSpv;
        case ShaderVariant::RayQuery: return kWhittedCompRayQuerySpv;
        case ShaderVariant::AddressesLean: return kWhittedCompLeanSpv;
        case ShaderVariant::Addresses: break;
    }
    return kWhittedCompSpv;
}

constexpr vk::BufferUsageFlags kStorage = vk::BufferUsageFlagBits::eStorageBuffer;
// The per-pixel buffers, bound as storage buffers (the StorageBuffers variant) and read by address (the others).
constexpr vk::BufferUsageFlags kAddressedStorage = kStorage | vk::BufferUsageFlagBits::eShaderDeviceAddress;

// Packs the scene after checking that each of its arrays fits one device
// buffer: a scene too large is refused before its BVH is built. Running out
// of host memory while packing or building the BVH says so with the sizes.
GpuScene packSceneThatFits(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings,
                           BvhPartCache* parts = nullptr) {
    SceneArrayCounts counts = countSceneArrays(scene);
    if (auto problem = sceneArraysTooLarge(counts, sceneBufferLimits(ctx))) throw std::runtime_error(*problem);
    try {
        return packScene(scene, settings, parts);
    } catch (const std::bad_alloc&) {
        uint64_t bytes = counts.primitives * sizeof(gpu::Primitive) + counts.bvhNodes * sizeof(gpu::BvhNode);
        throw std::runtime_error("out of host memory packing the scene's " + std::to_string(counts.primitives) +
                                 " primitives and building their BVH (the packed arrays alone take up to " +
                                 std::to_string(bytes >> 20) + " MiB)");
    }
}

// The device address of a buffer as the (low, high) words FrameParams holds.
glm::uvec2 addressWords(const Buffer& b) { return {uint32_t(b.address), uint32_t(b.address >> 32)}; }

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

Renderer::Renderer(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx), settings_(settings), scene_(packSceneThatFits(ctx, scene, settings)),
      trace_(resolveTrace(ctx, settings)) {
    if (scene_.width < 1 || scene_.height < 1 || scene_.width > int(gpu::kMaxImageSide) ||
        scene_.height > int(gpu::kMaxImageSide))
        throw std::runtime_error("image size " + std::to_string(scene_.width) + "x" + std::to_string(scene_.height) +
                                 " is outside 1.." + std::to_string(gpu::kMaxImageSide));
    if (settings.samplesPerPixel < 1 || settings.samplesPerPixel > int(gpu::kMaxSamplesPerPixel))
        throw std::runtime_error("samples per pixel must be in 1.." + std::to_string(gpu::kMaxSamplesPerPixel) +
                                 ", got " + std::to_string(settings.samplesPerPixel));
    if (settings.maxDepth < 0 || settings.maxDepth > int(gpu::kMaxDepthLimit))
        throw std::runtime_error("max depth must be in 0.." + std::to_string(gpu::kMaxDepthLimit) + ", got " +
                                 std::to_string(settings.maxDepth));
    if (settings.aovBounces < 0 || settings.aovBounces > int(gpu::kAovBouncesMax))
        throw std::runtime_error("auxiliary bounces must be in 0.." + std::to_string(gpu::kAovBouncesMax) + ", got " +
                                 std::to_string(settings.aovBounces));
    bool ids = settings.auxiliary && settings.ids;
    layerCount_ = settings.auxiliary ? gpu::kAovCount + 2 * uint32_t(settings.aovBounces) + (ids ? 1 : 0) : 1;
    layout_ = {.fullWidth = scene_.width, .fullHeight = scene_.height,
               .region = regionFor(settings, scene_.width, scene_.height), .layerCount = layerCount_, .ids = ids,
               .environment = scene_.params.environment.kind != gpu::kEnvironmentNone};

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
    // The uniform parameters and the band's read-back are the host's; what
    // the shader writes or reads at every sample is the device's
    // (MirroredBuffer: in host memory only where the device works there).
    DeviceActivity activity(*ctx.events, "making the render's buffers");
    params_ = createBuffer(ctx, sizeof(gpu::FrameParams), vk::BufferUsageFlagBits::eUniformBuffer, MemoryUse::Upload);
    output_ = createDeviceBuffer(ctx, nullptr, outputRow * bandRows_, kAddressedStorage | vk::BufferUsageFlagBits::eTransferSrc);
    counters_ = MirroredBuffer(ctx, sizeof(gpu::RayCounters), kStorage);
    size_t adaptivePixels = adaptive ? bandPixels : 1;  // a buffer must not be empty
    pixelList_ = MirroredBuffer(ctx, adaptivePixels * sizeof(uint32_t), kAddressedStorage);
    sampleStats_ = MirroredBuffer(ctx, adaptivePixels * 2 * sizeof(glm::uvec4), kAddressedStorage);
    guide_ = MirroredBuffer(ctx, adaptivePixels * sizeof(glm::uvec4), kAddressedStorage);
    if (settings.bandBytes != 0)
        readback_ =
            createBuffer(ctx, outputRow * bandRows_, vk::BufferUsageFlagBits::eTransferDst, MemoryUse::Readback);
    vk::DescriptorPoolSize poolSizes[] = {{vk::DescriptorType::eUniformBuffer, 1},
                                          {vk::DescriptorType::eStorageBuffer, kTracerStorageBindings},
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
void Renderer::buildPipeline(std::optional<Specialization> constants) {
    auto start = Clock::now();
    if (std::string shortfall = descriptorLimitShortfall(ctx_.physicalDevice.getProperties().limits); !shortfall.empty())
        throw std::runtime_error("device " + ctx_.deviceInfo().name + " " + shortfall);
    // With `constants` the scene's arrays are on the device already: the
    // tracer build that reads them stays.
    if (!constants) shaderVariant_ = shaderVariantFor(ctx_, scene_, trace_, settings_.sceneReads, settings_.fittedShader);
    specialization_ = constants ? *constants : specializationFor(scene_);
    std::span<const uint32_t> spirv = embeddedTracer(shaderVariant_);
#ifdef WHITTED_DEVELOPER
    std::vector<uint32_t> override = shaderOverride();
    if (!override.empty()) spirv = override;
#endif
    descriptorSet_ = nullptr;  // freed before the layout it was allocated with goes
    pipeline_ = createTracerPipeline(ctx_, spirv, trace_, specialization_, sizeof(gpu::TileParams));
    vk::DescriptorSetLayout setLayout = *pipeline_.setLayout;
    descriptorSet_ = std::move(vk::raii::DescriptorSets(
        ctx_.device, {.descriptorPool = *descriptorPool_, .descriptorSetCount = 1, .pSetLayouts = &setLayout}).front());
    pipelineSeconds_ = secondsSince(start);
}

// Scene buffers, their addresses in the uniform block, and the descriptor
// set naming every buffer of kTracerBindings, the textures and, for ray
// queries, the top-level acceleration structure.
void Renderer::uploadScene() {
    auto start = Clock::now();
    DeviceActivity activity(*ctx_.events, "uploading the scene");
    // An array the size of the one before it, in host-visible memory (a
    // device that works in host memory, when an object moved), is written
    // in place: a new buffer's pages cost more to touch than to copy into.
    auto upload = [&](Buffer& target, const auto& array, const char* what) {
        vk::DeviceSize bytes = array.size() * sizeof(array[0]);
        if (target.mapped && bytes > 0 && target.size == bytes) {
            std::memcpy(target.mapped, array.data(), bytes);
            return;
        }
        target = {};  // the old array goes before the new one is made
        try {
            target = createDeviceBuffer(ctx_, array.data(), bytes,
                                        vk::BufferUsageFlagBits::eShaderDeviceAddress | kStorage);
        } catch (const DeviceFailure& e) {
            throw e.within("uploading the scene's " + std::to_string(array.size()) + " " + what + " (" +
                           std::to_string(bytes) + " bytes; " + std::to_string(deviceBytes_ >> 20) +
                           " MiB already on the device): ");
        }
    };
    deviceBytes_ = params_.size + output_.size + counters_.size() + pixelList_.size() + guide_.size() +
                   sampleStats_.size() + readback_.size;
    accelerationStructures_ = {};
    if (trace_ == TracePath::RayQuery) {
        // The device's structures over the bounded primitives replace the
        // BVH, whose nodes the shader variant never reads.
        accelerationStructures_ = buildAccelerationStructures(
            ctx_, std::span(scene_.primitives).first(scene_.params.firstListPrimitive),
            {scene_.primitives, scene_.instances, scene_.prototypeRanges, scene_.instancePrototypes});
        deviceBytes_ += accelerationStructures_.bytes();
        std::vector<gpu::BvhNode>().swap(scene_.bvhNodes);
    }
    // The large arrays live on the device from now on: their host copies go
    // as soon as they are uploaded (a 10M-triangle mesh: 1 GB less host memory).
    upload(primitives_, scene_.primitives, "primitives");
    deviceBytes_ += primitives_.size;
    std::vector<gpu::Primitive>().swap(scene_.primitives);
    upload(bvhNodes_, scene_.bvhNodes, "BVH nodes");
    deviceBytes_ += bvhNodes_.size;
    std::vector<gpu::BvhNode>().swap(scene_.bvhNodes);
    upload(materials_, scene_.materials, "materials");
    deviceBytes_ += materials_.size;
    upload(lights_, scene_.lights, "lights");
    deviceBytes_ += lights_.size;
    upload(csgNodes_, scene_.csgNodes, "CSG nodes");
    deviceBytes_ += csgNodes_.size;
    upload(environmentDistribution_, scene_.environmentDistribution, "environment distribution values");
    deviceBytes_ += environmentDistribution_.size;
    scene_.params.environment.distributionAddress = addressWords(environmentDistribution_);
    glm::uvec2 p = addressWords(primitives_), n = addressWords(bvhNodes_);
    glm::uvec2 m = addressWords(materials_), l = addressWords(lights_);
    scene_.params.primitiveAddress = p;
    scene_.params.bvhNodeAddress = n;
    scene_.params.materialAddress = m;
    scene_.params.lightAddress = l;
    scene_.params.csgNodeAddress = addressWords(csgNodes_);
    scene_.params.outputAddress = addressWords(output_);
    scene_.params.pixelListAddress = addressWords(pixelList_.device());
    scene_.params.guideAddress = addressWords(guide_.device());
    scene_.params.sampleStatsAddress = addressWords(sampleStats_.device());
    // Textures and the per-primitive surface attributes (UVs of textured
    // meshes; address 0 when no mesh needs them).
    texturesUploaded_ = !texturesMade_ || scene_.textures != uploadedTextures_;
    if (texturesUploaded_) {
        textures_ = {};
        textures_ = TextureSet(ctx_, scene_.textures);
        uploadedTextures_ = scene_.textures;
        texturesMade_ = true;
    }
    deviceBytes_ += textures_.bytes();
    if (!scene_.attributes.empty()) {
        upload(attributes_, scene_.attributes, "surface attributes");
        deviceBytes_ += attributes_.size;
        std::vector<gpu::SurfaceAttributes>().swap(scene_.attributes);
    } else {
        attributes_ = {};
    }
    scene_.params.attributeAddress = addressWords(attributes_);  // 0 when not made
    if (!scene_.instances.empty()) {
        upload(instances_, scene_.instances, "instances");
        deviceBytes_ += instances_.size;
    } else {
        instances_ = {};
    }
    scene_.params.instanceAddress = addressWords(instances_);  // 0 when not made
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));
    writeDescriptors();
    uploadSeconds_ = secondsSince(start);
}

// The descriptor set naming every buffer of kTracerBindings, the textures
// and, for ray queries, the top-level acceleration structure.
void Renderer::writeDescriptors() {
    // In the order of kTracerBindings.
    const Buffer* buffers[] = {&params_,      &output_,     &counters_.device(), &pixelList_.device(),
                               &guide_.device(), &sampleStats_.device(), &bvhNodes_, &primitives_,
                               &materials_,   &lights_};
    // Arrays beyond one storage buffer range are read through their address
    // only (render/device_policy.h); the descriptor then names the first range.
    vk::DeviceSize maxRange = ctx_.physicalDevice.getProperties().limits.maxStorageBufferRange;
    std::vector<vk::DescriptorBufferInfo> infos;
    for (const Buffer* b : buffers) infos.push_back({*b->buffer, 0, std::min(b->size, maxRange)});
    std::vector<vk::WriteDescriptorSet> writes;
    for (uint32_t i = 0; i < infos.size(); ++i)
        writes.push_back({.dstSet = *descriptorSet_, .dstBinding = kTracerBindings[i].binding,
                          .descriptorCount = 1, .descriptorType = kTracerBindings[i].type, .pBufferInfo = &infos[i]});
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
}

void Renderer::setScene(const Scene& scene) {
    RenderSettings settings = settings_;
    settings.width = scene_.width;  // the image size stays
    settings.height = scene_.height;
    // Ray queries build the device's own structures, not this BVH.
    scene_ = packSceneThatFits(ctx_, scene, settings, trace_ == TracePath::RayQuery ? nullptr : &bvhParts_);
    // A shape or glass the old scene lacked needs the pipeline that has it;
    // arrays of another size may need the other way of reading them.
    if (specializationFor(scene_) != specialization_ ||
        shaderVariantFor(ctx_, scene_, trace_, settings_.sceneReads, settings_.fittedShader) != shaderVariant_)
        buildPipeline();
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
    scene_.params.projection = fresh.projection;
    scene_.params.forward = fresh.forward;
    scene_.params.right = fresh.right;
    scene_.params.up = fresh.up;
    scene_.params.apertureRadius = fresh.apertureRadius;
    scene_.params.focusDistance = fresh.focusDistance;
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));
    if (respecialize()) writeDescriptors();  // a lens coming or going
}

bool Renderer::setMaterials(const Scene& scene) {
    GpuShading shading = packShading(scene);
    if (shading.materials.size() != scene_.materials.size() || shading.textures != scene_.textures) return false;
    scene_.materials = std::move(shading.materials);
    // Transparency or gloss coming or going needs the pipeline that has it
    // or not (withShading; the shapes, and so the other constants, stay).
    respecialize();
    materials_ = createDeviceBuffer(ctx_, scene_.materials.data(), scene_.materials.size() * sizeof(gpu::Material),
                                    vk::BufferUsageFlagBits::eShaderDeviceAddress | kStorage);
    scene_.params.materialAddress = addressWords(materials_);
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));
    writeDescriptors();
    return true;
}

void Renderer::setLights(const Scene& scene) {
    scene_.lights = packShading(scene).lights;
    lights_ = createDeviceBuffer(ctx_, scene_.lights.data(), scene_.lights.size() * sizeof(gpu::Light),
                                 vk::BufferUsageFlagBits::eShaderDeviceAddress | kStorage);
    scene_.params.lightAddress = addressWords(lights_);
    scene_.params.lightCount = uint32_t(scene_.lights.size());
    scene_.params.ambientLight = glm::vec3(scene.ambientLight);
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));
    respecialize();  // area lights coming or going
    writeDescriptors();
}

bool Renderer::respecialize() {
    Specialization next = withShading(specialization_, scene_);
    if (next == specialization_) return false;
    buildPipeline(next);
    return true;
}

void Renderer::recordClear(const vk::raii::CommandBuffer& cmd) const {
    vk::MemoryBarrier before{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eShaderRead,
                             .dstAccessMask = vk::AccessFlagBits::eTransferWrite};
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eTransfer, {}, before,
                        nullptr, nullptr);
    cmd.fillBuffer(*output_.buffer, 0, VK_WHOLE_SIZE, 0);
}

// One dispatch per kMaxSamplesPerInvocation samples of the range (lavapipe's
// loop cap, render/bands.h), each after a barrier on the ones before.
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
        recordDispatch(cmd, pipeline_, part, (tile.tileSize.x + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize,
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
    result.layout = layout_;
    for (uint32_t layer = 0; layer < layerCount_; ++layer) {
        auto& out = result.layers[layer];
        out.assign(raw.begin() + layer * pixels * 4, raw.begin() + (layer + 1) * pixels * 4);
        if (layer == layout_.idLayer()) continue;  // ids: uint bits, kept as they are
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

RenderResult Renderer::renderTo(BandSink& sink, const ProgressCallback& progress, uint32_t firstBand,
                                uint32_t bandStep) {
    if (settings_.bandBytes == 0) throw std::logic_error("Renderer::renderTo needs bands (RenderSettings::bandBytes)");
    auto start = Clock::now();
    RenderResult result = renderBands({.ctx = ctx_,
                                       .settings = settings_,
                                       .pipeline = pipeline_,
                                       .descriptorSet = *descriptorSet_,
                                       .imageWidth = scene_.width,
                                       .imageHeight = scene_.height,
                                       .layout = layout_,
                                       .bandRows = bandRows_,
                                       .output = output_,
                                       .readback = readback_,
                                       .counters = counters_,
                                       .pixelList = pixelList_,
                                       .guide = guide_,
                                       .sampleStats = sampleStats_},
                                      sink, progress, firstBand, bandStep);
    result.renderSeconds = secondsSince(start);
    result.uploadSeconds = uploadSeconds_;
    result.pipelineSeconds = pipelineSeconds_;
    result.deviceBytes = deviceBytes_;
    result.bvh = scene_.bvhStats;
    result.trace = trace_;
    result.accelerationStructureSeconds = accelerationStructures_.buildSeconds;
    return result;
}

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

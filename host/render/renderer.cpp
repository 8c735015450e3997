#include "render/renderer.h"

#include "shapes/shapes.h"

#include <cstdint>

#include "whitted_comp.h"  // kWhittedCompSpv, generated from shaders/whitted.comp

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

// Specialization constants for a packed scene: the shapes in the BVH, any
// transparency, the shapes outside it (planes). What a scene lacks compiles
// out (on lavapipe every branch costs, taken or not: shaders/intersect.glsl).
std::array<uint32_t, 3> specializationFor(const GpuScene& scene) {
    std::array<uint32_t, 3> constants = {0u, 0u, 0u};
    for (size_t i = 0; i < scene.primitives.size(); ++i)
        constants[i < scene.params.accel.y ? 0 : 2] |= 1u << scene.primitives[i].info.x;
    for (const gpu::Material& m : scene.materials) constants[1] |= m.coefs1.y > 0.0f ? 1u : 0u;
    return constants;
}

// The descriptor set: the scene's arrays are not in it (device addresses,
// shaders/scene.glsl).
constexpr DescriptorBinding kBindings[] = {{gpu::kBindingParams, vk::DescriptorType::eUniformBuffer},
                                           {gpu::kBindingOutput, vk::DescriptorType::eStorageBuffer},
                                           {gpu::kBindingCounters, vk::DescriptorType::eStorageBuffer}};

// The device address of a buffer as the (low, high) words FrameParams holds.
glm::uvec2 addressWords(const Buffer& b) { return {uint32_t(b.address), uint32_t(b.address >> 32)}; }

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

Renderer::Renderer(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx), settings_(settings), scene_(packSceneThatFits(ctx, scene, settings)) {
    if (scene_.width < 1 || scene_.height < 1 || scene_.width > 16384 || scene_.height > 16384)
        throw std::runtime_error("image size " + std::to_string(scene_.width) + "x" + std::to_string(scene_.height) +
                                 " is outside 1..16384");
    if (settings.samplesPerPixel < 1 || settings.samplesPerPixel > 65536)
        throw std::runtime_error("samples per pixel must be in 1..65536, got " + std::to_string(settings.samplesPerPixel));
    if (settings.maxDepth < 0 || settings.maxDepth > int(gpu::kMaxDepthLimit))
        throw std::runtime_error("max depth must be in 0.." + std::to_string(gpu::kMaxDepthLimit) + ", got " +
                                 std::to_string(settings.maxDepth));

    // The output holds every layer of the whole image; refuse clearly what
    // the device can not address rather than fail inside the driver.
    layerCount_ = settings.auxiliary ? gpu::kAovCount : 1;
    vk::DeviceSize outputSize = vk::DeviceSize(layerCount_) * scene_.width * scene_.height * sizeof(glm::vec4);
    vk::DeviceSize maxRange = ctx.physicalDevice.getProperties().limits.maxStorageBufferRange;
    if (outputSize > maxRange)
        throw std::runtime_error("the image and its auxiliary layers need " + std::to_string(outputSize >> 20) +
                                 " MiB, more than this device's storage buffer limit of " +
                                 std::to_string(maxRange >> 20) + " MiB; render smaller or with --aov none");

    auto hostVisible = vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent;
    params_ = createBuffer(ctx, sizeof(gpu::FrameParams), vk::BufferUsageFlagBits::eUniformBuffer, hostVisible);
    output_ = createDeviceBuffer(ctx, nullptr, outputSize, kStorage | vk::BufferUsageFlagBits::eTransferSrc);
    counters_ = createBuffer(ctx, sizeof(gpu::RayCounters), kStorage, hostVisible);
    vk::DescriptorPoolSize poolSizes[] = {{vk::DescriptorType::eUniformBuffer, 1},
                                          {vk::DescriptorType::eStorageBuffer, 2}};
    descriptorPool_ = vk::raii::DescriptorPool(
        ctx.device, vk::DescriptorPoolCreateInfo{.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                 .maxSets = 1, .poolSizeCount = 2, .pPoolSizes = poolSizes});
    buildPipeline();
    uploadScene();
}

// The pipeline specialised for scene_, and the one descriptor set (from a
// pool of one) that uploadScene() fills.
void Renderer::buildPipeline() {
    auto start = Clock::now();
    specialization_ = specializationFor(scene_);
    const vk::SpecializationMapEntry entries[] = {{gpu::kSpecShapeMask, 0, sizeof(uint32_t)},
                                                  {gpu::kSpecTransparency, sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecListShapeMask, 2 * sizeof(uint32_t), sizeof(uint32_t)}};
    vk::SpecializationInfo specialization{.mapEntryCount = 3, .pMapEntries = entries,
                                          .dataSize = sizeof(specialization_), .pData = specialization_.data()};
    std::vector<uint32_t> variant = profilingShaderVariant();
    descriptorSet_ = nullptr;  // freed before the layout it was allocated with goes
    pipeline_ = createComputePipeline(ctx_, variant.empty() ? std::span<const uint32_t>(kWhittedCompSpv) : variant,
                                      kBindings, sizeof(gpu::TileParams), &specialization);
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
            return createDeviceBuffer(ctx_, array.data(), bytes, vk::BufferUsageFlagBits::eShaderDeviceAddress);
        } catch (const std::runtime_error& e) {
            throw std::runtime_error("uploading the scene's " + std::to_string(array.size()) + " " + what + " (" +
                                     std::to_string(bytes) + " bytes; " + std::to_string(deviceBytes_ >> 20) +
                                     " MiB already on the device): " + e.what());
        }
    };
    deviceBytes_ = params_.size + output_.size + counters_.size;
    primitives_ = {};  // a re-upload (setScene) frees the old arrays first
    materials_ = {};
    lights_ = {};
    bvhNodes_ = {};
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
    glm::uvec2 p = addressWords(primitives_), n = addressWords(bvhNodes_);
    glm::uvec2 m = addressWords(materials_), l = addressWords(lights_);
    scene_.params.addresses0 = glm::uvec4(p, n);
    scene_.params.addresses1 = glm::uvec4(m, l);
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));

    const Buffer* buffers[] = {&params_, &output_, &counters_};  // in the order of kBindings
    std::vector<vk::DescriptorBufferInfo> infos;
    for (const Buffer* b : buffers) infos.push_back({*b->buffer, 0, VK_WHOLE_SIZE});
    std::vector<vk::WriteDescriptorSet> writes;
    for (uint32_t i = 0; i < infos.size(); ++i)
        writes.push_back({.dstSet = *descriptorSet_, .dstBinding = kBindings[i].binding, .descriptorCount = 1,
                          .descriptorType = kBindings[i].type, .pBufferInfo = &infos[i]});
    ctx_.device.updateDescriptorSets(writes, nullptr);
    uploadSeconds_ = secondsSince(start);
}

void Renderer::setScene(const Scene& scene) {
    RenderSettings settings = settings_;
    settings.width = scene_.width;  // the image size stays
    settings.height = scene_.height;
    scene_ = packSceneThatFits(ctx_, scene, settings);
    // A shape or glass the old scene lacked needs the pipeline that has it.
    if (specializationFor(scene_) != specialization_) buildPipeline();
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

// One dispatch per kMaxSamplesPerInvocation samples of the range (lavapipe's
// loop cap, see above), each after a barrier on the ones before.
void Renderer::recordTile(const vk::raii::CommandBuffer& cmd, const gpu::TileParams& tile) const {
    cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_.pipeline);
    cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline_.layout, 0, *descriptorSet_, nullptr);
    for (uint32_t done = 0; done < tile.samples.y; done += kMaxSamplesPerInvocation) {
        gpu::TileParams part = tile;
        part.samples.x = tile.samples.x + done;
        part.samples.y = std::min(kMaxSamplesPerInvocation, tile.samples.y - done);
        vk::MemoryBarrier accumulate{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                                     .dstAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                            vk::PipelineStageFlagBits::eComputeShader, {}, accumulate, nullptr, nullptr);
        cmd.pushConstants<gpu::TileParams>(*pipeline_.layout, vk::ShaderStageFlagBits::eCompute, 0, part);
        cmd.dispatch((tile.tile.z + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize,
                     (tile.tile.w + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1);
    }
}

RenderResult Renderer::readMeans() const {
    RenderResult result;
    result.width = scene_.width;
    result.height = scene_.height;
    result.hasAuxiliary = settings_.auxiliary;
    size_t pixels = size_t(scene_.width) * scene_.height;
    std::vector<float> raw(pixels * 4 * layerCount_);
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
    return result;
}

// Tiles of kTileSize^2 pixels; each tile's samples are split into chunks so
// that no dispatch traces more than settings.samplesPerDispatch camera
// samples. Sample indices are global, so the split changes only the order of
// the floating-point sums, not which samples are traced.
std::vector<Renderer::WorkItem> Renderer::planWork() const {
    std::vector<WorkItem> items;
    uint32_t spp = uint32_t(settings_.samplesPerPixel);
    for (uint32_t y = 0; y < uint32_t(scene_.height); y += kTileSize)
        for (uint32_t x = 0; x < uint32_t(scene_.width); x += kTileSize) {
            uint32_t w = std::min(kTileSize, uint32_t(scene_.width) - x);
            uint32_t h = std::min(kTileSize, uint32_t(scene_.height) - y);
            uint32_t chunk = uint32_t(std::clamp<uint64_t>(std::max<uint64_t>(settings_.samplesPerDispatch, 1) / (uint64_t(w) * h), 1, spp));
            chunk = std::min(chunk, kMaxSamplesPerInvocation);
            for (uint32_t s = 0; s < spp; s += chunk) {
                uint32_t n = std::min(chunk, spp - s);
                items.push_back({.tile = {.tile = glm::uvec4(x, y, w, h), .samples = glm::uvec4(s, n, 0, 0)},
                                 .samples = uint64_t(w) * h * n});
            }
        }
    return items;
}

RenderResult Renderer::render(const ProgressCallback& progress) {
    auto start = Clock::now();
    std::vector<WorkItem> work = planWork();
    uint64_t totalSamples = 0, doneSamples = 0;
    for (const WorkItem& item : work) totalSamples += item.samples;

    RenderResult result;
    result.width = scene_.width;
    result.height = scene_.height;
    result.samplesPerPixel = settings_.samplesPerPixel;
    result.hasAuxiliary = settings_.auxiliary;

    vk::raii::CommandBuffers commandBuffers(ctx_.device, {.commandPool = *ctx_.commandPool,
                                                          .level = vk::CommandBufferLevel::ePrimary,
                                                          .commandBufferCount = 1});
    vk::raii::CommandBuffer& cmd = commandBuffers.front();
    vk::raii::Fence fence(ctx_.device, vk::FenceCreateInfo{});
    auto* counters = static_cast<gpu::RayCounters*>(counters_.mapped);

    // Dispatches go to the queue in batches of kDispatchesPerSubmit, each
    // followed by a barrier (later dispatches may accumulate into the same
    // pixels); the ray counters are read once per batch.
    for (size_t begin = 0; begin < work.size(); begin += kDispatchesPerSubmit) {
        size_t end = std::min(work.size(), begin + kDispatchesPerSubmit);
        *counters = {};
        cmd.reset();
        cmd.begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
        uint64_t batchSamples = 0;
        for (size_t i = begin; i < end; ++i) {
            recordTile(cmd, work[i].tile);
            batchSamples += work[i].samples;
        }
        vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eShaderWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eHostRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eHost, {}, toHost,
                            nullptr, nullptr);
        cmd.end();

        vk::CommandBuffer raw = *cmd;
        ctx_.queue.submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &raw}, *fence);
        vk::Result waited = ctx_.device.waitForFences(*fence, VK_TRUE, UINT64_MAX);
        if (waited != vk::Result::eSuccess) throw std::runtime_error("vkWaitForFences: " + vk::to_string(waited));
        ctx_.device.resetFences(*fence);

        // One camera ray per sample: fewer means the driver cut a run short.
        if (counters->primary < batchSamples) result.lostSamples += batchSamples - counters->primary;
        result.rays.primary += counters->primary;
        result.rays.shadow += counters->shadow;
        result.rays.secondary += counters->secondary;
        doneSamples += batchSamples;
        if (progress) progress(double(doneSamples) / double(totalSamples));
    }

    // Read back and turn sums into means (the w channel of the colour layers
    // holds the sample count; the hit-mask layers average the same way).
    size_t pixels = size_t(scene_.width) * scene_.height;
    std::vector<float> raw(pixels * 4 * layerCount_);
    readBuffer(ctx_, output_, raw.data(), raw.size() * sizeof(float));
    float inverseSpp = 1.0f / float(settings_.samplesPerPixel);
    for (uint32_t layer = 0; layer < layerCount_; ++layer) {
        auto& out = result.layers[layer];
        out.assign(raw.begin() + layer * pixels * 4, raw.begin() + (layer + 1) * pixels * 4);
        for (float& v : out) v *= inverseSpp;
    }
    result.renderSeconds = secondsSince(start);
    result.uploadSeconds = uploadSeconds_;
    result.pipelineSeconds = pipelineSeconds_;
    result.deviceBytes = deviceBytes_;
    result.bvh = scene_.bvhStats;
    return result;
}

}  // namespace whitted

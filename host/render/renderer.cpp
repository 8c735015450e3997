#include "render/renderer.h"

#include <cstdint>

#include "whitted_comp.h"  // kWhittedCompSpv, generated from shaders/whitted.comp

#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>

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

}  // namespace

Renderer::Renderer(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx), settings_(settings), scene_(packScene(scene, settings)) {
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
    vk::DeviceSize primitiveSize = scene_.primitives.size() * sizeof(gpu::Primitive);
    if (outputSize > maxRange)
        throw std::runtime_error("the image and its auxiliary layers need " + std::to_string(outputSize >> 20) +
                                 " MiB, more than this device's storage buffer limit of " +
                                 std::to_string(maxRange >> 20) + " MiB; render smaller or with --aov none");
    if (primitiveSize > maxRange)
        throw std::runtime_error("the scene's " + std::to_string(scene_.primitives.size()) +
                                 " primitives exceed this device's storage buffer limit");

    const vk::DescriptorType bindingTypes[] = {
        vk::DescriptorType::eUniformBuffer, vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer,
        vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer,
        vk::DescriptorType::eStorageBuffer};
    auto pipelineStart = Clock::now();
    // Specialization: the shapes and materials this scene lacks compile out
    // (on lavapipe every branch costs, taken or not: shaders/shapes/primitive.glsl).
    // constants: shapes in the BVH, transparency, shapes outside the BVH.
    std::array<uint32_t, 3> constants = {0u, 0u, 0u};
    for (size_t i = 0; i < scene_.primitives.size(); ++i)
        constants[i < scene_.params.accel.y ? 0 : 2] |= 1u << scene_.primitives[i].info.x;
    for (const gpu::Material& m : scene_.materials) constants[1] |= m.coefs1.y > 0.0f ? 1u : 0u;
    const vk::SpecializationMapEntry entries[] = {{gpu::kSpecShapeMask, 0, sizeof(uint32_t)},
                                                  {gpu::kSpecTransparency, sizeof(uint32_t), sizeof(uint32_t)},
                                                  {gpu::kSpecListShapeMask, 2 * sizeof(uint32_t), sizeof(uint32_t)}};
    vk::SpecializationInfo specialization{.mapEntryCount = 3, .pMapEntries = entries,
                                          .dataSize = sizeof(constants), .pData = constants.data()};
    std::vector<uint32_t> variant = profilingShaderVariant();
    pipeline_ = createComputePipeline(ctx, variant.empty() ? std::span<const uint32_t>(kWhittedCompSpv) : variant,
                                      bindingTypes, sizeof(gpu::TileParams), &specialization);
    pipelineSeconds_ = secondsSince(pipelineStart);

    // Scene upload.
    auto uploadStart = Clock::now();
    auto hostVisible = vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent;
    params_ = createBuffer(ctx, sizeof(gpu::FrameParams), vk::BufferUsageFlagBits::eUniformBuffer, hostVisible);
    std::memcpy(params_.mapped, &scene_.params, sizeof(gpu::FrameParams));
    primitives_ = createDeviceBuffer(ctx, scene_.primitives.data(), primitiveSize, kStorage);
    materials_ = createDeviceBuffer(ctx, scene_.materials.data(), scene_.materials.size() * sizeof(gpu::Material), kStorage);
    lights_ = createDeviceBuffer(ctx, scene_.lights.data(), scene_.lights.size() * sizeof(gpu::Light), kStorage);
    output_ = createDeviceBuffer(ctx, nullptr, outputSize, kStorage | vk::BufferUsageFlagBits::eTransferSrc);
    counters_ = createBuffer(ctx, sizeof(gpu::RayCounters), kStorage, hostVisible);
    bvhNodes_ = createDeviceBuffer(ctx, scene_.bvhNodes.data(), scene_.bvhNodes.size() * sizeof(gpu::BvhNode), kStorage);

    // One descriptor set for the whole render.
    vk::DescriptorPoolSize poolSizes[] = {{vk::DescriptorType::eUniformBuffer, 1}, {vk::DescriptorType::eStorageBuffer, 6}};
    descriptorPool_ = vk::raii::DescriptorPool(
        ctx.device, vk::DescriptorPoolCreateInfo{.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                 .maxSets = 1, .poolSizeCount = 2, .pPoolSizes = poolSizes});
    vk::DescriptorSetLayout setLayout = *pipeline_.setLayout;
    descriptorSet_ = std::move(vk::raii::DescriptorSets(
        ctx.device, {.descriptorPool = *descriptorPool_, .descriptorSetCount = 1, .pSetLayouts = &setLayout}).front());
    const Buffer* buffers[] = {&params_, &primitives_, &materials_, &lights_, &output_, &counters_, &bvhNodes_};
    std::vector<vk::DescriptorBufferInfo> infos;
    for (const Buffer* b : buffers) infos.push_back({*b->buffer, 0, VK_WHOLE_SIZE});
    std::vector<vk::WriteDescriptorSet> writes;
    for (uint32_t i = 0; i < infos.size(); ++i)
        writes.push_back({.dstSet = *descriptorSet_, .dstBinding = i, .descriptorCount = 1,
                          .descriptorType = bindingTypes[i], .pBufferInfo = &infos[i]});
    ctx.device.updateDescriptorSets(writes, nullptr);
    uploadSeconds_ = secondsSince(uploadStart);
    for (const Buffer* b : buffers) deviceBytes_ += b->size;
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
        cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_.pipeline);
        cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline_.layout, 0, *descriptorSet_, nullptr);
        uint64_t expected = 0, batchSamples = 0;
        for (size_t i = begin; i < end; ++i) {
            const WorkItem& item = work[i];
            vk::MemoryBarrier accumulate{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                                         .dstAccessMask = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite};
            cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                                vk::PipelineStageFlagBits::eComputeShader, {}, accumulate, nullptr, nullptr);
            cmd.pushConstants<gpu::TileParams>(*pipeline_.layout, vk::ShaderStageFlagBits::eCompute, 0, item.tile);
            cmd.dispatch((item.tile.tile.z + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize,
                         (item.tile.tile.w + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1);
            expected += uint64_t(item.tile.tile.z) * item.tile.tile.w * item.tile.samples.y;
            batchSamples += item.samples;
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

        if (counters->primary < expected) result.lostSamples += expected - counters->primary;
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

// Device memory (host/vk/memory.h): the sub-allocator's ranges and blocks,
// and memory as on a discrete GPU (ContextOptions::discreteMemory, which
// WHITTED_DISCRETE_MEMORY=1 sets in test builds): no shared device-local
// memory, uploads and read-backs through staging copies, and every shipped
// scene rendered bit for bit as with lavapipe's own memory.
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "vk/buffer.h"

#include <algorithm>
#include <cstring>
#include <set>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

VulkanContext& discreteContext() {
    static VulkanContext ctx(
        {.validation = true, .deviceName = "", .pipelineCacheFolder = fs::path(), .discreteMemory = true});
    return ctx;
}

// The scene on `ctx`, checked for validation messages.
RenderResult renderOn(VulkanContext& ctx, const Scene& scene, const RenderSettings& settings) {
    uint32_t before = ctx.validationMessageCount();
    Renderer renderer(ctx, scene, settings);
    RenderResult result = renderer.render();
    EXPECT_EQ(ctx.validationMessageCount(), before) << "the Vulkan validation layer reported messages (see stderr)";
    return result;
}

TEST(Memory, SmallRangesShareOneBlockAndComeBackToIt) {
    VulkanContext& ctx = testContext();
    vk::MemoryRequirements small{.size = 1000, .alignment = 256, .memoryTypeBits = ~0u};
    MemoryStats before = ctx.memory->stats();
    std::vector<Allocation> ranges;
    for (int i = 0; i < 64; ++i) ranges.push_back(ctx.memory->allocate(small, MemoryUse::Upload));
    MemoryStats after = ctx.memory->stats();
    // 64 ranges of 1000 bytes from at most one new block, each aligned, none overlapping.
    EXPECT_LE(after.allocationCalls - before.allocationCalls, 1u);
    std::set<std::pair<VkDeviceMemory, vk::DeviceSize>> starts;
    for (const Allocation& a : ranges) {
        EXPECT_EQ(a.offset() % 256, 0u);
        EXPECT_NE(a.mapped(), nullptr);
        starts.insert({a.memory(), a.offset()});
    }
    EXPECT_EQ(starts.size(), ranges.size());
    for (const Allocation& a : ranges)
        for (const Allocation& b : ranges)
            if (&a != &b && a.memory() == b.memory()) {
                EXPECT_GE(std::max(a.offset(), b.offset()) - std::min(a.offset(), b.offset()), 1000u);
            }
    // Freed ranges are joined again: one range of 64 times the size fits
    // where they were, with no new allocation.
    ranges.clear();
    Allocation joined = ctx.memory->allocate({.size = 64 * 1024, .alignment = 256, .memoryTypeBits = ~0u},
                                             MemoryUse::Upload);
    EXPECT_TRUE(joined);
    EXPECT_EQ(ctx.memory->stats().allocationCalls, after.allocationCalls);
}

TEST(Memory, LargeRequestsGetBlocksOfTheirOwnFreedWithThem) {
    VulkanContext& ctx = testContext();
    MemoryStats before = ctx.memory->stats();
    {
        Allocation large = ctx.memory->allocate({.size = 48u << 20, .alignment = 16, .memoryTypeBits = ~0u},
                                                MemoryUse::Device);
        EXPECT_EQ(large.offset(), 0u);
        EXPECT_EQ(ctx.memory->stats().blocks, before.blocks + 1);
    }
    EXPECT_EQ(ctx.memory->stats().blocks, before.blocks);
}

// A render's buffers and images (scene arrays, output, read-back,
// parameters, the adaptive pass's and the counters, textures, staging) come
// from a few blocks: one per memory use, not one per buffer.
TEST(Memory, ARendersBuffersComeFromAFewAllocations) {
    for (bool discrete : {false, true}) {
        VulkanContext ctx({.validation = true, .deviceName = "", .pipelineCacheFolder = fs::path(),
                           .discreteMemory = discrete});
        Scene scene = loadScene(sourceDir() / "tests" / "gpu_scenes" / "textured.xml");  // textures too
        RenderSettings settings{.width = 32, .height = 24, .samplesPerPixel = 4, .auxiliary = true,
                                .antiAliasing = AntiAliasing::Adaptive};
        RenderResult result = renderOn(ctx, scene, settings);
        MemoryStats stats = ctx.memory->stats();
        EXPECT_GT(result.rays.primary, 0u);
        // One block for each use: device-local buffers, images, upload and
        // read-back, and with lavapipe's memory the shared one.
        EXPECT_LE(stats.allocationCalls, discrete ? 4u : 5u) << "discrete " << discrete;
        EXPECT_GT(ctx.events->allocations(), 3 * stats.allocationCalls) << "discrete " << discrete;
    }
}

TEST(Memory, DiscreteMemoryMapsNoDeviceMemory) {
    VulkanContext& ctx = discreteContext();
    EXPECT_FALSE(ctx.memory->unified());
    EXPECT_THROW(ctx.memory->allocate({.size = 16, .alignment = 16, .memoryTypeBits = ~0u}, MemoryUse::Shared),
                 std::logic_error);
    Allocation device = ctx.memory->allocate({.size = 16, .alignment = 16, .memoryTypeBits = ~0u}, MemoryUse::Device);
    EXPECT_EQ(device.mapped(), nullptr);
    // A mirrored buffer is a device-local buffer and a host twin, copied both ways.
    MirroredBuffer mirrored(ctx, 64, vk::BufferUsageFlagBits::eStorageBuffer);
    EXPECT_TRUE(mirrored.staged());
    EXPECT_EQ(mirrored.device().mapped, nullptr);
    std::memset(mirrored.host(), 7, 64);
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) { mirrored.recordUpload(cmd, 64); });
    std::memset(mirrored.host(), 0, 64);
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) { mirrored.recordDownload(cmd, 64); });
    const auto* bytes = static_cast<const unsigned char*>(mirrored.host());
    EXPECT_TRUE(std::all_of(bytes, bytes + 64, [](unsigned char b) { return b == 7; }));
    // lavapipe's own memory: one buffer, mapped.
    EXPECT_TRUE(testContext().memory->unified());
    EXPECT_FALSE(MirroredBuffer(testContext(), 64, vk::BufferUsageFlagBits::eStorageBuffer).staged());
}

std::vector<std::string> sceneFiles() {
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(sourceDir() / "scenes"))
        if (entry.path().extension() == ".xml") files.push_back("scenes/" + entry.path().filename().string());
    files.push_back("tests/gpu_scenes/textured.xml");
    std::sort(files.begin(), files.end());
    return files;
}

// Every shipped scene (and the textured one of the GPU-readiness tier), all
// auxiliary images, adaptive sampling (its pixel list, guide and statistics
// go through staging copies), in bands of a few rows: every float of every
// layer, every sample count and the ray counts must be the same.
class DiscreteMemory : public ::testing::TestWithParam<std::string> {};

TEST_P(DiscreteMemory, RendersBitForBitAsUnified) {
    Scene scene = loadScene(sourceDir() / GetParam());
    RenderSettings settings{.width = 48, .height = 36, .samplesPerPixel = 4, .maxDepth = 6, .auxiliary = true,
                            .ids = true, .antiAliasing = AntiAliasing::Adaptive};
    settings.bandBytes = 96 * 1024;  // several bands
    MemoryStats before = discreteContext().memory->stats();
    RenderResult unified = renderOn(testContext(), scene, settings);
    RenderResult discrete = renderOn(discreteContext(), scene, settings);
    MemoryStats after = discreteContext().memory->stats();
    EXPECT_GT(unified.bands, 1u);
    ASSERT_EQ(unified.layers.size(), discrete.layers.size());
    for (size_t l = 0; l < unified.layers.size(); ++l) {
        ASSERT_EQ(unified.layers[l].size(), discrete.layers[l].size()) << "layer " << l;
        EXPECT_EQ(std::memcmp(unified.layers[l].data(), discrete.layers[l].data(), unified.layers[l].size() * 4), 0)
            << "layer " << l << " differs";
    }
    EXPECT_EQ(unified.sampleCounts, discrete.sampleCounts);
    EXPECT_EQ(unified.rays.primary, discrete.rays.primary);
    EXPECT_EQ(unified.rays.shadow, discrete.rays.shadow);
    EXPECT_EQ(unified.rays.secondary, discrete.rays.secondary);
    // Through staging: uploads and read-backs, and no shared memory at all.
    EXPECT_GT(after.requested[size_t(MemoryUse::Upload)], before.requested[size_t(MemoryUse::Upload)]);
    EXPECT_GT(after.requested[size_t(MemoryUse::Readback)], before.requested[size_t(MemoryUse::Readback)]);
    EXPECT_EQ(after.requested[size_t(MemoryUse::Shared)], 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, DiscreteMemory, ::testing::ValuesIn(sceneFiles()), [](const auto& info) {
    std::string name = fs::path(info.param).stem().string();
    return name;
});

}  // namespace
}  // namespace whitted::test

// The pipeline cache (host/vk/pipeline_cache.h): where its files go, which
// files it trusts, that a second context starts from what the first saved,
// and that a cache that cannot be read or written never fails a render.
#include "test_support.h"

#include "intersect_test_comp.h"  // kIntersectTestCompSpv: a small shader
#include "vk/compute_pipeline.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

fs::path scratchDir(const std::string& name) { return freshOutputDir("pipeline_cache", name); }

// Sets environment variables for one scope and restores them after.
class ScopedEnvironment {
public:
    void set(const char* name, const char* value) {
        const char* old = std::getenv(name);
        saved_.push_back({name, old ? std::optional<std::string>(old) : std::nullopt});
        value ? ::setenv(name, value, 1) : ::unsetenv(name);
    }
    ~ScopedEnvironment() {
        for (auto it = saved_.rbegin(); it != saved_.rend(); ++it)
            it->second ? ::setenv(it->first.c_str(), it->second->c_str(), 1) : ::unsetenv(it->first.c_str());
    }

private:
    std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

TEST(PipelineCache, FolderFromEnvironment) {
    ScopedEnvironment env;
    env.set("WHITTED_PIPELINE_CACHE", nullptr);
    env.set("XDG_CACHE_HOME", "/xdg/cache");
    env.set("HOME", "/home/someone");
    EXPECT_EQ(pipelineCacheFolderFromEnvironment(), fs::path("/xdg/cache/whitted"));
    env.set("XDG_CACHE_HOME", "relative/is/ignored");
    EXPECT_EQ(pipelineCacheFolderFromEnvironment(), fs::path("/home/someone/.cache/whitted"));
    env.set("XDG_CACHE_HOME", nullptr);
    EXPECT_EQ(pipelineCacheFolderFromEnvironment(), fs::path("/home/someone/.cache/whitted"));
    env.set("HOME", nullptr);
    EXPECT_EQ(pipelineCacheFolderFromEnvironment(), fs::path());
    env.set("WHITTED_PIPELINE_CACHE", "/elsewhere");
    EXPECT_EQ(pipelineCacheFolderFromEnvironment(), fs::path("/elsewhere"));
    env.set("WHITTED_PIPELINE_CACHE", "0");
    EXPECT_EQ(pipelineCacheFolderFromEnvironment(), fs::path()) << "0 turns the cache off";
}

TEST(PipelineCache, HeaderMustNameThisDevice) {
    vk::PhysicalDeviceProperties device{};
    device.vendorID = 0x10005;
    device.deviceID = 0x0123;
    for (uint8_t i = 0; i < VK_UUID_SIZE; ++i) device.pipelineCacheUUID[i] = i * 7;
    // VkPipelineCacheHeaderVersionOne, least significant byte first, then data.
    std::vector<uint8_t> data = {32, 0, 0, 0, 1, 0, 0, 0, 0x05, 0, 1, 0, 0x23, 0x01, 0, 0};
    for (uint8_t i = 0; i < VK_UUID_SIZE; ++i) data.push_back(i * 7);
    data.push_back(0xAB);
    EXPECT_TRUE(pipelineCacheHeaderMatches(data, device));

    auto changed = [&](size_t at, uint8_t value) {
        std::vector<uint8_t> d = data;
        d[at] = value;
        return d;
    };
    EXPECT_FALSE(pipelineCacheHeaderMatches(changed(0, 16), device)) << "header shorter than 32 bytes";
    EXPECT_FALSE(pipelineCacheHeaderMatches(changed(0, 200), device)) << "header longer than the data";
    EXPECT_FALSE(pipelineCacheHeaderMatches(changed(4, 2), device)) << "header version";
    EXPECT_FALSE(pipelineCacheHeaderMatches(changed(8, 6), device)) << "vendor";
    EXPECT_FALSE(pipelineCacheHeaderMatches(changed(13, 2), device)) << "device";
    EXPECT_FALSE(pipelineCacheHeaderMatches(changed(31, 0), device)) << "pipelineCacheUUID";
    EXPECT_FALSE(pipelineCacheHeaderMatches(std::span(data).first(31), device)) << "truncated";

    device.driverVersion = 0x12345678;
    EXPECT_EQ(pipelineCacheFileName(device), "pipelines-10005-0123-12345678-00070e151c232a31383f464d545b6269.bin");
}

// A context of its own (validation on) whose cache lives in `folder`; the
// test's messages are checked when it goes.
struct CachedContext {
    explicit CachedContext(const fs::path& folder)
        : ctx({.validation = true, .deviceName = "", .pipelineCacheFolder = folder}) {}
    ~CachedContext() { EXPECT_EQ(ctx.validationMessageCount(), 0u) << "validation messages (see stderr)"; }
    void createPipeline() {
        const vk::DescriptorType types[] = {vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer,
                                            vk::DescriptorType::eStorageBuffer};
        createComputePipeline(ctx, kIntersectTestCompSpv, types, sizeof(uint32_t));
    }
    VulkanContext ctx;
};

TEST(PipelineCache, SecondContextStartsFromWhatTheFirstSaved) {
    fs::path folder = scratchDir("reload") / "not_yet_there";
    fs::path file;
    {
        CachedContext first(folder);
        file = first.ctx.pipelineCache->file();
        EXPECT_EQ(file.parent_path(), folder);
        EXPECT_FALSE(first.ctx.pipelineCache->seededFromFile());
        first.createPipeline();
    }
    ASSERT_TRUE(fs::is_regular_file(file)) << "the folder is created and the file saved";
    CachedContext second(folder);
    EXPECT_TRUE(second.ctx.pipelineCache->seededFromFile());
    second.createPipeline();
    for (const auto& entry : fs::directory_iterator(folder))
        EXPECT_EQ(entry.path(), file) << "a temporary file was left behind";
}

TEST(PipelineCache, DamagedOrForeignFilesAreIgnoredAndReplaced) {
    fs::path folder = scratchDir("damaged");
    std::string good;
    fs::path file;
    {
        CachedContext first(folder);
        first.createPipeline();
        file = first.ctx.pipelineCache->file();
        std::ifstream in(file, std::ios::binary);
        good.assign(std::istreambuf_iterator<char>(in), {});
    }
    ASSERT_GE(good.size(), 24u + 32u) << "our prefix and the Vulkan header at least";

    auto damaged = [&](std::string text, const char* what) {
        std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
        CachedContext ctx(folder);
        EXPECT_FALSE(ctx.ctx.pipelineCache->seededFromFile()) << what;
        ctx.createPipeline();
        EXPECT_TRUE(CachedContext(folder).ctx.pipelineCache->seededFromFile()) << what << ": file not replaced";
    };
    damaged("", "empty file");
    damaged("garbage of some kind, long enough to hold a prefix and a header.........", "garbage");
    damaged(good.substr(0, good.size() - 1), "truncated");
    std::string flipped = good;
    flipped.back() ^= 1;
    damaged(flipped, "one bit changed");
    std::string foreign = good;
    foreign[24 + 8] ^= 1;  // the vendorID in the Vulkan header, hash made to match below
    {
        // Rehash so that only the Vulkan header check can refuse it.
        uint64_t h = 14695981039346656037ull;
        for (size_t i = 24; i < foreign.size(); ++i) h = (h ^ uint8_t(foreign[i])) * 1099511628211ull;
        std::memcpy(foreign.data() + 16, &h, 8);
    }
    damaged(foreign, "another vendor's header");
}

// The cache folder is under a regular file, so it can be neither created nor
// written (whoever runs the test, root included): one warning line however
// many pipelines are saved, and the pipelines are made all the same.
TEST(PipelineCache, UnwritableFolderWarnsOnceAndNeverFails) {
    fs::path dir = scratchDir("unwritable");
    std::ofstream(dir / "a_file") << "x";
    testing::internal::CaptureStderr();
    {
        CachedContext ctx(dir / "a_file" / "whitted");
        ctx.createPipeline();
        ctx.createPipeline();
    }
    std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("whitted: warning: pipeline cache not saved"), std::string::npos) << err;

    // The executable, end to end: the render succeeds with that one warning.
    fs::path scene = sourceDir() / "scenes" / "three_diffuse_spheres.xml";
    CommandRun r = runCommand("WHITTED_PIPELINE_CACHE='" + (dir / "a_file" / "whitted").string() +
                                  "' '" WHITTED_EXECUTABLE "' render '" + scene.string() +
                                  "' --width 8 --height 6 --aov none -q -o out.png",
                              dir);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out.png"));
}

}  // namespace
}  // namespace whitted::test

#include "test_support.h"

#include "scene/scene_loader.h"

#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>

namespace whitted::test {
namespace {
// No test may depend on pipelines an earlier run left in the user's cache
// folder: the executables the tests start inherit this and keep none
// (PipelineCache.* gives the cache folders of their own).
[[maybe_unused]] const bool kPipelineCacheOff = ::setenv("WHITTED_PIPELINE_CACHE", "0", 1) == 0;
}  // namespace

VulkanContext& testContext() {
    static VulkanContext ctx({.validation = true, .deviceName = "", .pipelineCacheFolder = std::filesystem::path()});
    return ctx;
}

RenderResult renderScene(const Scene& scene, const RenderSettings& settings) {
    VulkanContext& ctx = testContext();
    uint32_t before = ctx.validationMessageCount();
    Renderer renderer(ctx, scene, settings);
    RenderResult result = renderer.render();
    EXPECT_EQ(ctx.validationMessageCount(), before) << "the Vulkan validation layer reported messages (see stderr)";
    return result;
}

RenderResult renderXml(const std::string& xml, const RenderSettings& settings) {
    return renderScene(loadSceneFromString(xml, "inline.xml"), settings);
}

CommandRun runCommand(const std::string& command, const std::filesystem::path& cwd) {
    std::string full = "cd '" + cwd.string() + "' && " + command + " 2>&1";
    FILE* pipe = ::popen(full.c_str(), "r");
    if (!pipe) return {-1, "popen failed: " + command};
    std::string output;
    char buf[4096];
    while (size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
    int status = ::pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::filesystem::path sourceDir() { return WHITTED_SOURCE_DIR; }

std::filesystem::path outputDir() {
    std::filesystem::path dir = WHITTED_TEST_OUTPUT_DIR;
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace whitted::test

// Shared helpers for tests that render: one Vulkan context per test process
// with the Khronos validation layer on, and in-process rendering of scene
// files or inline XML. Any validation message fails the current test.
#pragma once

#include "render/renderer.h"
#include "scene/scene.h"
#include "vk/context.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace whitted::test {

VulkanContext& testContext();

// Renders and checks that the validation layer stayed silent.
RenderResult renderScene(const Scene& scene, const RenderSettings& settings);
RenderResult renderXml(const std::string& xml, const RenderSettings& settings);

// Runs `command` through the shell in folder `cwd`: its exit status (-1 if
// it did not exit normally) and its stdout and stderr together.
struct CommandRun {
    int status;
    std::string output;
};
CommandRun runCommand(const std::string& command, const std::filesystem::path& cwd);

std::filesystem::path sourceDir();
std::filesystem::path outputDir();  // created on demand, for diff images

// The golden-image metric between two 8-bit image files of the same size:
// mean absolute difference in 8-bit levels over all channels, and the
// fraction of pixels with some channel off by more than 16 levels. When
// either exceeds its bound (0.5 levels, 0.2%) a difference image is written
// to `diffPath` and the test fails with `what` in its messages.
void expectGoldenMatch(const std::filesystem::path& got, const std::filesystem::path& want,
                       const std::filesystem::path& diffPath, const std::string& what);

// Pixel access into an RGBA layer.
inline glm::vec4 pixel(const RenderResult& r, uint32_t layer, int x, int y) {
    const float* p = &r.layers[layer][(size_t(y) * r.width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

}  // namespace whitted::test

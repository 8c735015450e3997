// Shared helpers for tests that render: one Vulkan context per test process
// with the Khronos validation layer on, and in-process rendering of scene
// files or inline XML. Any validation message fails the current test.
#pragma once

#include "render/renderer.h"
#include "scene/scene.h"
#include "vk/context.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

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
// outputDir()/group/name, emptied and created: a test's scratch folder.
std::filesystem::path freshOutputDir(const std::string& group, const std::string& name);
// Standard base64 of `bytes`, for the data: URIs of generated glTF files.
std::string base64(const std::vector<unsigned char>& bytes);
// scene.obj and scene.mtl in `dir`: five triangles side by side, one per
// MTL illumination model (plastic: illum 2, mirror: 3, fresnel_mirror: 5,
// glass: 6, fresnel_glass: 7, the last with a texture named by a Windows
// path, "tex dir\quad.png", written beside them). Returns scene.obj.
std::filesystem::path writeIlluminationObj(const std::filesystem::path& dir);
// A model of Debian's assimp-testmodels (tools/install_deps.sh --all) by its path
// under /usr/share/assimp/models, e.g. "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb".
std::filesystem::path assimpTestModel(const std::string& relative);

// The golden-image metric between two 8-bit image files of the same size:
// mean absolute difference in 8-bit levels over all channels, and the
// fraction of pixels with some channel off by more than 16 levels. When
// either exceeds its bound (0.5 levels, 0.2%) a difference image is written
// to `diffPath` and the test fails with `what` in its messages.
void expectGoldenMatch(const std::filesystem::path& got, const std::filesystem::path& want,
                       const std::filesystem::path& diffPath, const std::string& what);

// Test textures (scenes/README.md "Textures"), written at run time as 8-bit sRGB PNG
// files: `colour(u, v)` gives the linear colour of the texel whose centre
// is at (u, v) (v up, as the scene's texture coordinates).
void writeTestTexture(const std::filesystem::path& path, int width, int height,
                      const std::function<glm::vec3(float u, float v)>& colour);
// 64x64, four flat quadrants (v up): top left red, top right green, bottom
// left blue, bottom right yellow (kQuadrant* in linear RGB).
inline const glm::vec3 kQuadrantTopLeft{0.8f, 0.1f, 0.1f}, kQuadrantTopRight{0.1f, 0.7f, 0.1f},
    kQuadrantBottomLeft{0.1f, 0.1f, 0.8f}, kQuadrantBottomRight{0.8f, 0.7f, 0.1f};
void writeQuadrantTexture(const std::filesystem::path& path);
// 64x64, smooth: red a sine of u (once around), green a ramp in v, blue a
// sine of u + v; no sharp edges, so lookups that differ by a fraction of a
// texel (POV-Ray's bilinear image_map against ours) differ little.
void writeSmoothTexture(const std::filesystem::path& path);

// Pixel access into an RGBA layer.
inline glm::vec4 pixel(const RenderResult& r, uint32_t layer, int x, int y) {
    const float* p = &r.layers[layer][(size_t(y) * r.width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

}  // namespace whitted::test

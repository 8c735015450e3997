// `whitted trace SCENE --pixel X,Y [--pixel X,Y ...]`: the ray tree behind
// each pixel (render/ray_tree.h), as indented text or, with --json, the full
// record (several pixels: a JSON array of records, one device start).
#include "app/cli_options.h"
#include "app/commands.h"
#include "scene/quick_look.h"
#include "device_types.h"
#include "output/ray_tree_json.h"
#include "render/ray_tree.h"
#include "render/renderer.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "vk/context.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <regex>
#include <string>
#include <utility>
#include <vector>

namespace whitted {
namespace {

struct TraceArguments {
    std::filesystem::path scene;
    std::vector<std::string> pixels;
    int width = 0, height = 0;
    int maxDepth = 6;
    bool json = false;
    std::string device;
    bool validation = false;
};

int runTrace(const TraceArguments& args) {
    static const std::regex kPixel(R"(^\s*(\d+)\s*,\s*(\d+)\s*$)");
    std::vector<std::pair<int, int>> pixels;
    for (const std::string& pixel : args.pixels) {
        std::smatch m;
        if (!std::regex_match(pixel, m, kPixel) || m[1].length() > 6 || m[2].length() > 6) {
            std::cerr << "whitted: --pixel: expected X,Y (two integers), got '" << pixel << "'\n";
            return kExitBadInput;
        }
        pixels.emplace_back(std::stoi(m[1].str()), std::stoi(m[2].str()));
    }
    Scene scene;
    try {
        scene = loadSceneOrModel(args.scene);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    RenderSettings settings = rayTreeSettings(args.width, args.height, args.maxDepth);
    // The image's size is known before the device starts: refuse the pixel first.
    int width = args.width > 0 ? args.width : scene.camera.width;
    int height = args.height > 0 ? args.height : scene.camera.height;
    for (auto [x, y] : pixels)
        if (x >= width || y >= height) {
            std::cerr << "whitted: --pixel " << x << "," << y << " is outside the " << width << "x" << height
                      << " image\n";
            return kExitBadInput;
        }
    std::vector<RayTree> trees;
    try {
        VulkanContext ctx({.validation = args.validation, .deviceName = args.device});
        Renderer renderer(ctx, scene, settings);
        RayTreeRecorder recorder(ctx);
        for (auto [x, y] : pixels) trees.push_back(recorder.trace(renderer, x, y));
        if (ctx.validationMessageCount() > 0) {
            std::cerr << "whitted: the Vulkan validation layer reported " << ctx.validationMessageCount()
                      << " message(s)\n";
            return kExitValidation;
        }
    } catch (const DeviceFailure& e) {
        std::cerr << "whitted: " << args.scene.string() << ": " << e.what() << "; nothing printed\n";
        return kExitFailure;
    }
    if (args.json)
        std::cout << (trees.size() == 1 ? rayTreeJson(trees[0], scene) : rayTreesJson(trees, scene));
    else
        for (size_t i = 0; i < trees.size(); ++i) std::cout << (i > 0 ? "\n" : "") << rayTreeText(trees[i], scene);
    return kExitOk;
}

}  // namespace

Command addTraceCommand(CLI::App& app) {
    auto args = std::make_shared<TraceArguments>();
    auto* cmd = app.add_subcommand("trace", "print the ray tree behind a pixel, each ray with its share of the colour");
    cmd->add_option("scene", args->scene, "scene XML file (.xml), or a model file")->required();
    cmd->add_option("--pixel", args->pixels, "the pixel X,Y (0,0 the top left); again for more pixels (--json: an array)")
        ->required();
    cmd->add_option("--width", args->width, "image width in pixels [scene's]")->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    cmd->add_option("--height", args->height, "image height in pixels [scene's]")
        ->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    cmd->add_option("--max-depth", args->maxDepth, "secondary bounces; 0 = local shading only")
        ->check(CLI::Range(0, int(gpu::kMaxDepthLimit)))->capture_default_str();
    cmd->add_flag("--json", args->json, "print the full record as JSON");
    cmd->add_option("--device", args->device, "Vulkan device index or name substring [best available]");
    cmd->add_flag("--validate", args->validation, "enable the Khronos validation layer; fail on any message");
    return {cmd, [args] {
                TraceArguments a = *args;
                a.validation = a.validation || validationFromEnvironment();
                return runTrace(a);
            }};
}

}  // namespace whitted

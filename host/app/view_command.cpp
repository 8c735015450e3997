// `whitted view`: its options; checks the scene, the script and the
// screenshot folder (bad input: FILE:LINE and exit status 2 before any window
// opens), then hands over to the live window (host/view/view_app.h).
#include <iostream>
#include <memory>

#include "app/cli_options.h"
#include "app/commands.h"
#include "scene/quick_look.h"
#include "device_types.h"
#include "tracer_types.h"
#include "scene/scene_loader.h"
#include "view/view_app.h"

#include <CLI/CLI.hpp>

namespace whitted {
namespace {

int runViewCommand(const ViewOptions& given) {
    // A model file is a quick look: the scene built for it is written, by
    // Ctrl+S, beside the model (never over it), and the model is not watched.
    ViewOptions options = given;
    if (!isSceneFile(options.scene)) options.sceneOut = quickLookScenePath(options.scene);
    Scene scene;
    try {
        scene = loadSceneOrModel(options.scene, options.camera);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    printSceneWarnings(scene, false);
    std::vector<ScriptCommand> script;
    if (options.script) {
        try {
            script = loadScript(*options.script, {.sampleBudget = uint32_t(options.settings.samplesPerPixel),
                                                  .aovBounces = options.settings.aovBounces});
            checkScriptOnScene(*options.script, script, scene);
        } catch (const std::invalid_argument& e) {
            std::cerr << e.what() << "\n";
            return kExitBadInput;
        }
    }
    if (options.screenshot) {
        std::filesystem::path parent =
            options.screenshot->parent_path().empty() ? "." : options.screenshot->parent_path();
        if (!std::filesystem::is_directory(parent)) {
            std::cerr << "whitted: screenshot folder " << parent.string() << " does not exist\n";
            return kExitBadInput;
        }
    }
    switch (runViewWindow(options, std::move(scene), std::move(script))) {
        case ViewOutcome::Closed: return kExitOk;
        case ViewOutcome::ScriptRefused: return kExitBadInput;
        case ViewOutcome::Failed: return kExitFailure;
        case ViewOutcome::ValidationMessages: return kExitValidation;
    }
    return kExitFailure;
}

}  // namespace

Command addViewCommand(CLI::App& app) {
    auto view = std::make_shared<ViewOptions>();
    view->settings.samplesPerPixel = 256;
    auto* cmd = app.add_subcommand("view", "open a scene in a live window (README \"Live window\")");
    cmd->add_option("scene", view->scene,
                    "scene XML file (.xml), or a model file (a quick look; Ctrl+S writes MODEL.whitted.xml)")
        ->required();
    cmd->add_option("--width", view->settings.width, "image width in pixels [scene's]")
        ->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    cmd->add_option("--height", view->settings.height, "image height in pixels [scene's]")
        ->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    cmd->add_option("--spp", view->settings.samplesPerPixel, "sample budget per pixel; tracing stops there")
        ->check(CLI::Range(1, int(gpu::kMaxSamplesPerPixel)))->capture_default_str();
    cmd->add_option("--max-depth", view->settings.maxDepth, "secondary bounces")
        ->check(CLI::Range(0, int(gpu::kMaxDepthLimit)))->capture_default_str();
    cmd->add_option("--aov-bounces", view->settings.aovBounces,
                    "also show reflection and transmission split by ray depth into B images each (L cycles)")
        ->check(CLI::Range(0, int(gpu::kAovBouncesMax)))->capture_default_str();
    cmd->add_option("--frames", view->frames, "close after N frames [until the window is closed]")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--screenshot", view->screenshot, "write the image shown as PNG when closing");
    cmd->add_option("--script", view->script, "timed input commands (see host/view/view_script.h)");
    cmd->add_option("--frame-ms", view->targetFrameMs, "target milliseconds per frame")
        ->check(CLI::Range(5.0, 1000.0))->capture_default_str();
    cmd->add_option("--device", view->device, "Vulkan device index or name substring [best available]");
    cmd->add_option("--camera", view->camera,
                    "the file's camera to start from: its index in node order (from 0) or its name [the first]");
    cmd->add_option("--exposure", view->exposure,
                    "scale the colour images shown and saved by 2^EV before encoding")
        ->check(CLI::Range(-64.0, 64.0))->capture_default_str();
    cmd->add_flag("--validate", view->validation, "enable the Khronos validation layer; fail on any message");
    return {cmd, [view] {
                ViewOptions options = *view;
                options.validation = options.validation || validationFromEnvironment();
                return runViewCommand(options);
            }};
}

}  // namespace whitted

// `whitted view`: checks the scene, the script and the screenshot folder
// (bad input: FILE:LINE and exit status 2 before any window opens), then
// hands over to the live window (host/view/view_app.h).
#include <iostream>

#include "app/commands.h"
#include "app/quick_look.h"
#include "scene/scene_loader.h"
#include "view/view_app.h"

namespace whitted {

int runViewCommand(const ViewOptions& given) {
    // A model file is a quick look: the scene built for it is written, by
    // Ctrl+S, beside the model (never over it), and the model is not watched.
    ViewOptions options = given;
    if (!isSceneFile(options.scene)) options.sceneOut = quickLookScenePath(options.scene);
    Scene scene;
    try {
        scene = loadSceneOrModel(options.scene);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    for (const std::string& warning : scene.warnings) std::cerr << "warning: " << warning << "\n";
    std::vector<ScriptCommand> script;
    if (options.script) {
        try {
            script = loadScript(*options.script);
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

}  // namespace whitted

// `whitted view`: the live window. The same Renderer and compute shader as
// `whitted render`, driven progressively (view/progressive.h), shown through
// view/presenter.h with the ImGui overlay and editor, the camera on the mouse
// and keyboard, and the scene file reloaded when it changes on disk.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "render/render_settings.h"
#include "scene/scene.h"
#include "view/view_script.h"

namespace whitted {

struct ViewOptions {
    std::filesystem::path scene;
    // Where Ctrl+S writes the scene when not over `scene` (a quick look of a
    // model file); then `scene` is not watched for changes either.
    std::optional<std::filesystem::path> sceneOut;
    RenderSettings settings;  // samplesPerPixel = the sample budget; auxiliary always on
    std::string device;
    bool validation = false;
    int frames = 0;                                   // stop after this many frames; 0 = until the window closes
    std::optional<std::filesystem::path> screenshot;  // written when the window closes
    std::optional<std::filesystem::path> script;
    std::filesystem::path historyRoot = "renders";
    double targetFrameMs = 40;
    double exposure = 0;  // EV: the colour images shown and saved are scaled by 2^exposure
    std::string camera;   // --camera INDEX|NAME of the file's cameras (empty: the first)
};

// How a window session ended; app/view_command.cpp maps it to an exit status.
enum class ViewOutcome {
    Closed,              // the window was closed, --frames ran out or the script quit
    ScriptRefused,       // a script command could not be carried out (FILE:LINE printed)
    Failed,              // a device or file failure, or a script wait that timed out
    ValidationMessages,  // the Vulkan validation layer reported a problem
};

// Opens the window on a loaded scene and runs until it closes, --frames
// runs out or the script quits. app/view_command.cpp checks the input first.
ViewOutcome runViewWindow(const ViewOptions& options, Scene scene, std::vector<ScriptCommand> script);

}  // namespace whitted

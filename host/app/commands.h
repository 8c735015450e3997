// The command-line verbs. main.cpp only parses arguments and calls these.
#pragma once

#include "output/aov_output.h"
#include "render/render_settings.h"

#include <filesystem>
#include <optional>
#include <string>

namespace whitted {

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;     // device or I/O failure
inline constexpr int kExitBadInput = 2;    // bad scene file or arguments
inline constexpr int kExitValidation = 3;  // the Vulkan validation layer reported a problem

struct RenderCommandOptions {
    std::filesystem::path scene;
    std::optional<std::filesystem::path> output;  // none: a new history folder
    std::filesystem::path historyRoot = "renders";
    RenderSettings settings;
    std::string aovs = "all";
    Tonemap tonemap = Tonemap::Clamp;
    std::string device;
    bool validation = false;
    bool quiet = false;
};

int runRenderCommand(const RenderCommandOptions& options);
int runDevicesCommand();

struct ViewOptions;  // view/view_app.h
int runViewCommand(const ViewOptions& options);

}  // namespace whitted

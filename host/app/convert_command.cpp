// `whitted convert INPUT -o OUT.xml`: any input the other commands take (a
// scene file, a model file through its quick look) written as a whitted
// scene file by the scene writer the window's Save uses, so that it can be
// edited and renders as the input does.
#include "app/cli_options.h"
#include "app/commands.h"
#include "scene/quick_look.h"
#include "scene/scene_error.h"
#include "scene/scene_writer.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

namespace whitted {
namespace {

struct ConvertOptions {
    std::filesystem::path input;
    std::filesystem::path output;
};

int runConvert(const ConvertOptions& options) {
    Scene scene;
    try {
        scene = loadSceneOrModel(options.input);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    printSceneWarnings(scene, false);
    std::filesystem::path folder = options.output.parent_path().empty() ? "." : options.output.parent_path();
    if (!std::filesystem::is_directory(folder)) {
        std::cerr << "whitted: " << options.output.string() << ": the folder " << folder.string()
                  << " does not exist\n";
        return kExitBadInput;
    }
    writeFilelessTextures(scene, options.output);
    writeSceneFile(scene, options.output);  // atomic: a temporary file renamed when complete
    return kExitOk;
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
    auto options = std::make_shared<ConvertOptions>();
    auto* cmd = app.add_subcommand("convert", "write a scene or model file as a whitted XML scene");
    cmd->add_option("input", options->input, "scene file (.xml) or model file (.obj, .glb, .ply, ...)")->required();
    cmd->add_option("-o,--output", options->output, "the XML scene file to write")->required();
    return {cmd, [options] { return runConvert(*options); }};
}

}  // namespace whitted

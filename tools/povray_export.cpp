// whitted_povray_export: writes a scene file as POV-Ray 3.7 SDL (see
// tools/povray/povray_export.h and tests/README.md "Cross-check against POV-Ray").
//
//   whitted_povray_export SCENE.xml OUT.pov [--width W] [--height H] [--max-depth D] [--blur-samples N]
//   povray -D +WW +HH +FE File_Gamma=1.0 +IOUT.pov +Oout.exr
//
// Exit statuses as whitted's: 0 success, 1 I/O failure, 2 bad input (the
// scene file's errors are reported as FILE:LINE: message).
#include "app/commands.h"
#include "device_types.h"
#include "povray/povray_export.h"
#include "scene/scene_loader.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <unistd.h>

int main(int argc, char** argv) {
    using namespace whitted;
    namespace fs = std::filesystem;
    CLI::App app{"whitted_povray_export: write a whitted scene as POV-Ray 3.7 SDL"};
    std::string scenePath, outPath;
    PovrayExportOptions options;
    app.add_option("scene", scenePath, "scene XML file")->required();
    app.add_option("output", outPath, "POV-Ray file to write (.pov)")->required();
    app.add_option("--width", options.width, "image width in pixels [scene's]")->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    app.add_option("--height", options.height, "image height in pixels [scene's]")->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    app.add_option("--max-depth", options.maxDepth, "secondary bounces; 0 = local shading only")
        ->check(CLI::Range(0, int(gpu::kMaxDepthLimit)))->capture_default_str();
    app.add_option("--blur-samples", options.blurSamples, "focal_blur rays per pixel, all traced (a camera with a lens)")
        ->check(CLI::Range(1, 4096))->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int status = app.exit(e);
        return status == 0 ? kExitOk : kExitBadInput;
    }

    Scene scene;
    try {
        scene = loadScene(scenePath);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    for (const std::string& warning : scene.warnings) std::cerr << "warning: " << warning << "\n";
    for (const std::string& note : povrayInexactMappings(scene))
        std::cerr << "warning: not exact in POV-Ray: " << note << "\n";

    // Written under a temporary name and renamed, so a failure leaves no
    // partial file.
    fs::path out = outPath;
    fs::path temporary = out.parent_path() / ("." + out.filename().string() + ".partial-" + std::to_string(::getpid()));
    {
        std::ofstream file(temporary, std::ios::binary);
        file << exportPovray(scene, options);
        file.close();
        if (!file) {
            std::error_code ignored;
            fs::remove(temporary, ignored);
            std::cerr << "whitted_povray_export: " << outPath << ": cannot write file\n";
            return kExitFailure;
        }
    }
    std::error_code ec;
    fs::rename(temporary, out, ec);
    if (ec) {
        fs::remove(temporary, ec);
        std::cerr << "whitted_povray_export: " << outPath << ": cannot write file: " << ec.message() << "\n";
        return kExitFailure;
    }
    return kExitOk;
}

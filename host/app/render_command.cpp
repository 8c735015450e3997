// `whitted render`: load, check outputs, render with progress, write files.
#include "app/commands.h"
#include "app/progress_bar.h"
#include "app/quick_look.h"
#include "io/image_io.h"
#include "io/image_library.h"
#include "output/render_record.h"
#include "render/multi_device.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "vk/context.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace whitted {
namespace {

// Refuses an output that can't be written before any work is done: its
// place at once, its format once the image module is loaded (after the
// pipeline is built, before any tracing).
std::optional<std::string> checkOutputPlace(const std::filesystem::path& path) {
    std::filesystem::path parent = path.parent_path().empty() ? "." : path.parent_path();
    if (!std::filesystem::is_directory(parent)) return "output folder " + parent.string() + " does not exist";
    if (std::filesystem::is_directory(path)) return "output " + path.string() + " is a folder, expected an image file";
    return std::nullopt;
}

std::optional<std::string> checkOutputFormat(const std::filesystem::path& path) {
    if (!isWritableFormat(path))
        return "cannot write images of type '" + path.extension().string() + "' (use .png, .exr, .jpg or .tif)";
    return std::nullopt;
}

std::string tonemapName(Tonemap t) { return t == Tonemap::Seed ? "seed" : "clamp"; }

// The devices --device names: "all" (every suitable one), a comma-separated
// list of indices or names, or one (empty: the best).
std::vector<std::string> deviceNames(const std::string& option) {
    std::vector<std::string> names;
    if (option == "all") {
        for (const DeviceInfo& d : VulkanContext::listDevices())
            if (d.suitable) names.push_back(std::to_string(d.index));
        if (names.empty()) names.push_back("");
        return names;
    }
    std::stringstream in(option);
    std::string item;
    while (std::getline(in, item, ',')) names.push_back(item);
    if (names.empty()) names.push_back("");
    return names;
}

// Thrown out of the history folder's fill when the validation layer spoke:
// the staging folder goes, nothing is written.
struct ValidationFailed {};

}  // namespace

int runRenderCommand(const RenderCommandOptions& options) {
    // Everything that can be refused is refused before the device starts.
    std::vector<std::string> aovs;
    try {
        aovs = parseAovList(options.aovs, options.settings.aovBounces);
    } catch (const std::invalid_argument& e) {
        std::cerr << "whitted: --aov: " << e.what() << " (see whitted render --help)\n";
        return kExitBadInput;
    }
    Scene scene;
    auto loadStart = std::chrono::steady_clock::now();
    try {
        scene = loadSceneOrModel(options.scene);  // a model file: a quick look
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count();
    for (const std::string& warning : scene.warnings) std::cerr << "warning: " << warning << "\n";
    if (options.output)
        if (auto problem = checkOutputPlace(*options.output)) {
            std::cerr << "whitted: " << *problem << "\n";
            return kExitBadInput;
        }

    RenderSettings settings = options.settings;
    settings.auxiliary = !aovs.empty();
    // Split layers only when a split image is written (they cost memory and bandwidth).
    if (!hasSplitAov(aovs)) settings.aovBounces = 0;
    // One context and renderer per device: --device all, or a list such as
    // 0,1 (the same device may be named twice, which tests the sharing).
    std::vector<std::unique_ptr<VulkanContext>> contexts;
    for (const std::string& name : deviceNames(options.device)) {
        contexts.push_back(std::make_unique<VulkanContext>(ContextOptions{.validation = options.validation, .deviceName = name}));
        const DeviceInfo& d = contexts.back()->deviceInfo();
        if (!options.quiet) std::cerr << "whitted: device " << d.name << " (" << d.type << ", " << d.driver << ")\n";
    }
    // The image module loads beside the pipeline build when a core is idle.
    preloadImageLibrary();
    VulkanContext& ctx = *contexts.front();
    auto validationMessages = [&] {
        uint32_t n = 0;
        for (const auto& c : contexts) n += c->validationMessageCount();
        return n;
    };

    std::vector<std::unique_ptr<Renderer>> renderers;
    std::vector<Renderer*> shares;
    try {
        for (const auto& c : contexts) shares.push_back(renderers.emplace_back(std::make_unique<Renderer>(*c, scene, settings)).get());
    } catch (const std::invalid_argument& e) {  // a region outside the image
        std::cerr << "whitted: --region: " << e.what() << "\n";
        return kExitBadInput;
    }
    Renderer* renderer = shares.front();
    if (options.output)
        if (auto problem = checkOutputFormat(*options.output)) {
            std::cerr << "whitted: " << *problem << "\n";
            return kExitBadInput;
        }
    auto sharedWith = [&] {
        std::vector<DeviceInfo> others;
        for (size_t i = 1; i < contexts.size(); ++i) others.push_back(contexts[i]->deviceInfo());
        return others;
    };

    // Bands stream into the image files as they complete (written under
    // temporary names, renamed only once the render is complete and clean);
    // the files go exactly where -o says, or into a new history folder.
    RenderResult result;
    std::vector<std::filesystem::path> files;
    std::filesystem::path shown;
    auto renderInto = [&](const std::filesystem::path& mainImage) {
        ImageFileSink sink(mainImage, aovs, options.tonemap, renderer->layout(), settings.samplesPerPixel);
        ProgressBar bar("rendering", !options.quiet);
        result = renderOnDevices(shares, sink, [&](double f) { bar.update(f); });
        bar.finish();
        if (result.lostSamples > 0)
            std::cerr << "warning: the driver cut " << result.lostSamples
                      << " camera samples short (lavapipe's loop iteration cap); the image is incomplete there\n";
        if (validationMessages() > 0) return false;
        files = sink.finish();
        return true;
    };
    auto recordJson = [&] {
        return renderRecordJson({.scenePath = options.scene, .settings = settings, .tonemap = tonemapName(options.tonemap),
                                 .device = ctx.deviceInfo(), .sharedWith = sharedWith(), .result = &result, .files = files, .loadSeconds = loadSeconds});
    };
    bool clean = true;
    if (options.output) {
        clean = renderInto(*options.output);
        shown = *options.output;
        // The record goes beside the image: out.png -> out.json.
        std::filesystem::path recordPath = *options.output;
        recordPath.replace_extension(".json");
        if (clean) writeTextFile(recordPath, recordJson());
    } else {
        try {
            shown = writeHistoryFolder(options.historyRoot, [&](const std::filesystem::path& staging) {
                if (!renderInto(staging / "image.png")) throw ValidationFailed{};
                if (isSceneFile(options.scene))
                    std::filesystem::copy_file(options.scene, staging / "scene.xml");
                else  // a quick look: the scene built for the model
                    writeSceneFile(scene, staging / "scene.xml");
                files.push_back(staging / "scene.xml");
                writeTextFile(staging / "render.json", recordJson());
            });
        } catch (const ValidationFailed&) {
            clean = false;
        }
    }
    if (!clean) {
        std::cerr << "whitted: the Vulkan validation layer reported " << validationMessages()
                  << " message(s); no image written\n";
        return kExitValidation;
    }

    if (!options.quiet) {
        // Scene preparation times: the loader (model files included), the
        // BVH build and the upload to the device.
        std::fprintf(stderr, "whitted: scene loaded in %.2f s, BVH of %u nodes built in %.2f s, uploaded in %.2f s\n",
                     loadSeconds, result.bvh.nodeCount, result.bvh.buildSeconds, result.uploadSeconds);
        double mrays = double(result.rays.total()) / std::max(result.renderSeconds, 1e-9) / 1e6;
        double meanSpp = double(result.samplesTaken) / (double(result.width) * result.height);
        std::fprintf(stderr, "whitted: wrote %s (%dx%d, %s %.2f spp of at most %d, %zu auxiliary) in %.2f s, %.1f Mrays/s\n",
                     shown.string().c_str(), result.width, result.height,
                     settings.antiAliasing == AntiAliasing::Adaptive ? "adaptive" : "uniform", meanSpp,
                     result.samplesPerPixel, aovs.size(), result.renderSeconds, mrays);
    }
    return kExitOk;
}

int runDevicesCommand() {
    for (const DeviceInfo& d : VulkanContext::listDevices())
        std::printf("%u: %s (%s, %s, Vulkan %u.%u)%s\n", d.index, d.name.c_str(), d.type.c_str(), d.driver.c_str(),
                    VK_API_VERSION_MAJOR(d.apiVersion), VK_API_VERSION_MINOR(d.apiVersion),
                    d.suitable ? "" : (" [unsuitable: " + d.unsuitable + "]").c_str());
    return kExitOk;
}

}  // namespace whitted

// `whitted render`: its options; load, check outputs, render with progress,
// write files.
#include "app/cli_options.h"
#include "app/commands.h"
#include "app/interrupt.h"
#include "app/progress_bar.h"
#include "device_types.h"
#include "tracer_types.h"
#include "scene/quick_look.h"
#include "io/image_io.h"
#include "io/image_library.h"
#include "output/aov_output.h"
#include "output/render_record.h"
#include "render/multi_device.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "vk/context.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace whitted {
namespace {

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
    bool verbose = false;  // -v: the lines summary warnings stand for
    std::string camera;    // --camera INDEX|NAME
    double exposure = 0;   // --exposure EV
    bool transparent = false;  // --background transparent: coverage as the image's alpha
    std::filesystem::path environment;  // --environment FILE: an image environment replacing the scene's
};

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

// One `whitted render` in its steps: load and check what was asked, open
// the devices and their renderers, render into the files, report.
class RenderRun {
public:
    explicit RenderRun(const RenderCommandOptions& options) : options_(options) {}

    // Everything that can be refused is refused before the device starts:
    // the auxiliary images asked for, the scene, the output's place.
    // Returns the exit code of a refusal.
    std::optional<int> load() {
        try {
            aovs_ = parseAovList(options_.aovs, options_.settings.aovBounces);
        } catch (const std::invalid_argument& e) {
            std::cerr << "whitted: --aov: " << e.what() << " (see whitted render --help)\n";
            return kExitBadInput;
        }
        auto loadStart = std::chrono::steady_clock::now();
        try {
            scene_ = loadSceneOrModel(options_.scene, options_.camera);  // a model file: authored or a quick look
            if (!options_.environment.empty()) scene_.environment = environmentFromImageFile(options_.environment);
        } catch (const SceneError& e) {
            std::cerr << e.what() << "\n";
            return kExitBadInput;
        }
        loadSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count();
        printSceneWarnings(scene_, options_.verbose);
        if (options_.output)
            if (auto problem = checkOutputPlace(*options_.output)) {
                std::cerr << "whitted: " << *problem << "\n";
                return kExitBadInput;
            }
        settings_ = options_.settings;
        settings_.auxiliary = !aovs_.empty() || options_.transparent;  // the alpha is the hit mask's
        settings_.transparentBackground = options_.transparent;
        // Split layers only when a split image is written (they cost memory and bandwidth).
        if (!hasSplitAov(aovs_)) settings_.aovBounces = 0;
        settings_.ids = hasIdAov(aovs_);  // the id layer, likewise
        return std::nullopt;
    }

    // One context and renderer per device: --device all, or a list such as
    // 0,1 (the same device may be named twice, which tests the sharing).
    // Returns the exit code of a refusal: a region outside the image, an
    // output format that can't be written.
    std::optional<int> openDevices() {
        for (const std::string& name : deviceNames(options_.device)) {
            contexts_.push_back(
                std::make_unique<VulkanContext>(ContextOptions{.validation = options_.validation, .deviceName = name}));
            const DeviceInfo& d = contexts_.back()->deviceInfo();
            if (!options_.quiet)
                std::cerr << "whitted: device " << d.name << " (" << d.type << ", " << d.driver << ")\n";
        }
        // The image module loads beside the pipeline build when a core is
        // idle, unless the images go where it is not needed (PPM, PGM; a
        // scene's textures loaded it already).
        if (!options_.output || !writtenWithoutImageLibrary(*options_.output)) preloadImageLibrary();
        try {
            for (const auto& c : contexts_)
                shares_.push_back(renderers_.emplace_back(std::make_unique<Renderer>(*c, scene_, settings_)).get());
        } catch (const std::invalid_argument& e) {  // a region outside the image
            std::cerr << "whitted: --region: " << e.what() << "\n";
            return kExitBadInput;
        }
        if (options_.output)
            if (auto problem = checkOutputFormat(*options_.output)) {
                std::cerr << "whitted: " << *problem << "\n";
                return kExitBadInput;
            }
        return std::nullopt;
    }

    // Renders into the files exactly where -o says, or into a new history
    // folder, with the render record beside them. Returns the image shown
    // to the user, or nothing when the validation layer spoke.
    std::optional<std::filesystem::path> renderFiles() {
        if (options_.output) {
            if (!renderInto(*options_.output)) return std::nullopt;
            // The record goes beside the image: out.png -> out.json.
            std::filesystem::path recordPath = *options_.output;
            recordPath.replace_extension(".json");
            writeTextFile(recordPath, recordJson());
            return *options_.output;
        }
        try {
            return writeHistoryFolder(options_.historyRoot, [&](const std::filesystem::path& staging) {
                if (!renderInto(staging / "image.png")) throw ValidationFailed{};
                if (isSceneFile(options_.scene))
                    std::filesystem::copy_file(options_.scene, staging / "scene.xml");
                else  // a quick look: the scene built for the model
                    writeSceneFile(scene_, staging / "scene.xml");
                files_.push_back(staging / "scene.xml");
                writeTextFile(staging / "render.json", recordJson());
            });
        } catch (const ValidationFailed&) {
            return std::nullopt;
        }
    }

    uint32_t validationMessages() const {
        uint32_t n = 0;
        for (const auto& c : contexts_) n += c->validationMessageCount();
        return n;
    }

    // Scene preparation times (the loader, model files included; the BVH
    // build; the upload to the device), then the image written and the
    // render's speed.
    void printSummary(const std::filesystem::path& shown) const {
        const RenderResult& r = result_;
        std::fprintf(stderr, "whitted: scene loaded in %.2f s, BVH of %u wide nodes built in %.2f s, uploaded in %.2f s\n",
                     loadSeconds_, r.bvh.wideNodeCount, r.bvh.buildSeconds, r.uploadSeconds);
        double mrays = double(r.rays.total()) / std::max(r.renderSeconds, 1e-9) / 1e6;
        double meanSpp = double(r.samplesTaken) / (double(r.width) * r.height);
        std::fprintf(stderr, "whitted: wrote %s (%dx%d, %s %.2f spp of at most %d, %zu auxiliary) in %.2f s, %.1f Mrays/s\n",
                     shown.string().c_str(), r.width, r.height,
                     settings_.antiAliasing == AntiAliasing::Adaptive ? "adaptive" : "uniform", meanSpp,
                     r.samplesPerPixel, aovs_.size(), r.renderSeconds, mrays);
    }

private:
    // Bands stream into the image files as they complete (written under
    // temporary names, renamed only once the render is complete and
    // clean). Returns false when the validation layer spoke.
    bool renderInto(const std::filesystem::path& mainImage) {
        ImageFileSink sink(mainImage, aovs_, options_.tonemap, shares_.front()->layout(), settings_.samplesPerPixel,
                           options_.exposure, options_.transparent);
        ProgressBar bar("rendering", !options_.quiet);
        result_ = renderOnDevices(shares_, sink, [&](double f) {
            throwIfInterrupted();
            bar.update(f);
        });
        bar.finish();
        if (result_.lostSamples > 0)
            std::cerr << "warning: the driver cut " << result_.lostSamples
                      << " camera samples short (lavapipe's loop iteration cap); the image is incomplete there\n";
        if (validationMessages() > 0) return false;
        files_ = sink.finish();
        return true;
    }

    std::string recordJson() const {
        std::vector<DeviceInfo> sharedWith;
        for (size_t i = 1; i < contexts_.size(); ++i) sharedWith.push_back(contexts_[i]->deviceInfo());
        return renderRecordJson({.scenePath = options_.scene, .settings = settings_,
                                 .tonemap = tonemapName(options_.tonemap), .device = contexts_.front()->deviceInfo(),
                                 .sharedWith = sharedWith, .result = &result_, .files = files_,
                                 .loadSeconds = loadSeconds_, .warnings = scene_.warnings,
                                 .warningDetails = scene_.warningDetails, .masks = settings_.ids ? &scene_ : nullptr,
                                 .exposure = options_.exposure, .camera = options_.camera});
    }

    const RenderCommandOptions& options_;
    std::vector<std::string> aovs_;
    Scene scene_;
    double loadSeconds_ = 0;
    RenderSettings settings_;
    std::vector<std::unique_ptr<VulkanContext>> contexts_;
    std::vector<std::unique_ptr<Renderer>> renderers_;
    std::vector<Renderer*> shares_;  // the renderers, one per device
    RenderResult result_;
    std::vector<std::filesystem::path> files_;
};

int renderOrRefuse(const RenderCommandOptions& options) {
    RenderRun run(options);
    if (auto refused = run.load()) return *refused;
    if (auto refused = run.openDevices()) return *refused;
    std::optional<std::filesystem::path> shown = run.renderFiles();
    if (!shown) {
        std::cerr << "whitted: the Vulkan validation layer reported " << run.validationMessages()
                  << " message(s); no image written\n";
        return kExitValidation;
    }
    if (!options.quiet) run.printSummary(*shown);
    return kExitOk;
}

int runRenderCommand(const RenderCommandOptions& options) {
    InterruptScope interrupts;  // Ctrl+C: stop at the next submission, write nothing (main exits 130)
    try {
        return renderOrRefuse(options);
    } catch (const DeviceFailure& e) {  // a lost device, exhausted memory: the files were never completed
        std::cerr << "whitted: " << options.scene.string() << ": " << e.what() << "; nothing written\n";
        return kExitFailure;
    }
}

// The command line's words, as given; run() checks and maps them.
struct RenderArguments {
    RenderCommandOptions options;
    std::string output, aa = "adaptive", region, tonemap = "clamp", trace = "auto", background = "opaque";
    bool noBvh = false;

    int run() {
        RenderCommandOptions o = options;
        if (!output.empty()) o.output = output;
        o.settings.useBvh = !noBvh;
        if (noBvh && trace == "rayquery") {
            std::cerr << "whitted: --no-bvh and --trace rayquery exclude each other\n";
            return kExitBadInput;
        }
        o.settings.trace = trace == "rayquery" ? TracePath::RayQuery
                           : trace == "bvh"    ? TracePath::Bvh
                                               : TracePath::Auto;
        o.settings.antiAliasing = aa == "uniform" ? AntiAliasing::Uniform : AntiAliasing::Adaptive;
        if (!region.empty()) {
            try {
                o.settings.region = parsePixelRegion(region);
            } catch (const std::invalid_argument& e) {
                std::cerr << "whitted: --region: " << e.what() << "\n";
                return kExitBadInput;
            }
        }
        o.tonemap = tonemap == "seed" ? Tonemap::Seed : Tonemap::Clamp;
        o.transparent = background == "transparent";
        if (o.transparent && o.tonemap == Tonemap::Seed) {
            std::cerr << "whitted: --background transparent and --tonemap seed exclude each other\n";
            return kExitBadInput;
        }
        o.validation = o.validation || validationFromEnvironment();
        return runRenderCommand(o);
    }
};

// Refuses what CLI::Range lets through: NaN compares false with both ends
// (an --aa-threshold of nan would turn refinement off without a word).
// Text that is no number is left to the option's own conversion message.
CLI::Validator finiteNumber() {
    return CLI::Validator(
        [](const std::string& text) -> std::string {
            float value = 0;
            if (CLI::detail::lexical_cast(text, value) && !std::isfinite(value))
                return "must be a finite number, got " + text;
            return "";
        },
        "");
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArguments>();
    RenderCommandOptions& render = args->options;
    auto* cmd = app.add_subcommand("render", "render a scene file to images");
    cmd->add_option("scene", render.scene,
                    "scene XML file (.xml), or a model file (any other extension: a quick look)")->required();
    cmd->add_option("-o,--output", args->output,
                    "image to write (.png, .exr, ...); auxiliary images go beside it. "
                    "Default: a new folder under renders/");
    cmd->add_option("--width", render.settings.width, "image width in pixels [scene's]")
        ->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    cmd->add_option("--height", render.settings.height, "image height in pixels [scene's]")
        ->check(CLI::Range(1, int(gpu::kMaxImageSide)));
    render.settings.samplesPerPixel = 16;
    render.settings.antiAliasing = AntiAliasing::Adaptive;
    cmd->add_option("--spp", render.settings.samplesPerPixel,
                    "samples per pixel, stratified: the most a pixel takes (adaptive), or exactly (uniform)")
        ->check(CLI::Range(1, int(gpu::kMaxSamplesPerPixel)))->capture_default_str();
    cmd->add_option("--aa", args->aa, "anti-aliasing: adaptive (more samples where the image varies) or uniform")
        ->check(CLI::IsMember({"adaptive", "uniform"}))->capture_default_str();
    cmd->add_option("--aa-threshold", render.settings.aaThreshold,
                    "adaptive: refine where displayed colours differ by more than this (0..1)")
        ->check(finiteNumber())->check(CLI::Range(0.0f, 1.0f))->capture_default_str();
    cmd->add_option("--region", args->region,
                    "render only pixels X0 <= x < X1, Y0 <= y < Y1 of the image, exactly as a full render "
                    "would (PNG: region-sized; EXR: data window in the full display window)");
    cmd->add_option("--max-depth", render.settings.maxDepth, "secondary bounces; 0 = local shading only")
        ->check(CLI::Range(0, int(gpu::kMaxDepthLimit)))->capture_default_str();
    cmd->add_option("--aov", render.aovs,
                    "auxiliary images: all, none, or a list of ambient,diffuse,specular,reflection,"
                    "transmission,ambient_coef,diffuse_coef,specular_coef,reflection_coef,"
                    "transmission_coef,ior,depth,normal; with --aov-bounces B also reflection.1..B and "
                    "transmission.1..B")->capture_default_str();
    cmd->add_option("--aov-bounces", render.settings.aovBounces,
                    "split the reflection and transmission images by ray depth into B images each "
                    "(reflection.K: rays at depth K of the reflected subtree; the last holds all deeper ones)")
        ->check(CLI::Range(0, int(gpu::kAovBouncesMax)))->capture_default_str();
    cmd->add_option("--tonemap", args->tonemap, "clamp (sRGB) or seed (min-max normalisation, gamma 0.667)")
        ->check(CLI::IsMember({"clamp", "seed"}))->capture_default_str();
    cmd->add_option("--background", args->background,
                    "opaque, or transparent: camera rays do not see the environment, and the image gets the "
                    "coverage as alpha (PNG RGBA, EXR A; scenes/README.md \"Environment\")")
        ->check(CLI::IsMember({"opaque", "transparent"}))->capture_default_str();
    cmd->add_option("--environment", render.environment,
                    "an equirectangular image (EXR, HDR, PNG, ...) as the scene's environment, replacing its own: "
                    "seen where rays leave the scene and lighting it (scenes/README.md \"Environment\")");
    cmd->add_option("--device", render.device,
                    "Vulkan device index or name substring [best available]; all, or a list such as 0,1, "
                    "shares the bands of one render among several devices");
    cmd->add_flag("--no-bvh", args->noBvh, "test every primitive for every ray (reference for comparisons)");
    cmd->add_option("--trace", args->trace,
                    "how rays find the scene: bvh (our BVH), rayquery (the device's acceleration structures, "
                    "VK_KHR_ray_query), auto (ray queries on a GPU that has them, else bvh)")
        ->check(CLI::IsMember({"auto", "bvh", "rayquery"}))->capture_default_str();
    cmd->add_option("--camera", render.camera,
                    "the file's camera to render through: its index in node order (from 0) or its name "
                    "[the first]");
    cmd->add_option("--exposure", render.exposure,
                    "scale the image and the colour auxiliary images by 2^EV before encoding (EXR too)")
        ->check(finiteNumber())->check(CLI::Range(-64.0, 64.0))->capture_default_str();
    cmd->add_flag("--validate", render.validation, "enable the Khronos validation layer; fail on any message");
    cmd->add_flag("-q,--quiet", render.quiet, "no progress or summary");
    cmd->add_flag("-v,--verbose", render.verbose,
                  "after a warning that sums up many (a glTF file's degenerate triangles), each line it sums up "
                  "(the render record keeps them either way)");
    return {cmd, [args] { return args->run(); }};
}

}  // namespace whitted

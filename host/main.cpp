// whitted: command line. Parses arguments and hands over to host/app.
#include "app/commands.h"
#include "device_types.h"
#include "view/view_app.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace {
// WHITTED_VALIDATION=1 turns the validation layer on, as --validate does.
bool validationFromEnvironment() {
    const char* v = std::getenv("WHITTED_VALIDATION");
    return v && *v && std::string(v) != "0";
}
}  // namespace

int main(int argc, char** argv) {
    using namespace whitted;
    CLI::App app{"whitted: a Whitted-style ray tracer on Vulkan compute"};
    app.set_version_flag("--version", std::string("whitted ") + WHITTED_VERSION);
    app.require_subcommand(1);

    RenderCommandOptions render;
    std::string output;
    std::string tonemap = "clamp";
    auto* renderCmd = app.add_subcommand("render", "render a scene file to images");
    renderCmd->add_option("scene", render.scene,
                          "scene XML file (.xml), or a model file (any other extension: a quick look)")->required();
    renderCmd->add_option("-o,--output", output,
                          "image to write (.png, .exr, ...); auxiliary images go beside it. "
                          "Default: a new folder under renders/");
    renderCmd->add_option("--width", render.settings.width, "image width in pixels [scene's]")->check(CLI::Range(1, 16384));
    renderCmd->add_option("--height", render.settings.height, "image height in pixels [scene's]")->check(CLI::Range(1, 16384));
    render.settings.samplesPerPixel = 16;
    render.settings.antiAliasing = AntiAliasing::Adaptive;
    std::string aa = "adaptive", region;
    renderCmd->add_option("--spp", render.settings.samplesPerPixel,
                          "samples per pixel, stratified: the most a pixel takes (adaptive), or exactly (uniform)")
        ->check(CLI::Range(1, 65536))->capture_default_str();
    renderCmd->add_option("--aa", aa, "anti-aliasing: adaptive (more samples where the image varies) or uniform")
        ->check(CLI::IsMember({"adaptive", "uniform"}))->capture_default_str();
    renderCmd->add_option("--aa-threshold", render.settings.aaThreshold,
                          "adaptive: refine where displayed colours differ by more than this (0..1)")
        ->check(CLI::Range(0.0f, 1.0f))->capture_default_str();
    renderCmd->add_option("--region", region,
                          "render only pixels X0 <= x < X1, Y0 <= y < Y1 of the image, exactly as a full render "
                          "would (PNG: region-sized; EXR: data window in the full display window)");
    renderCmd->add_option("--max-depth", render.settings.maxDepth, "secondary bounces; 0 = local shading only")
        ->check(CLI::Range(0, int(gpu::kMaxDepthLimit)))->capture_default_str();
    renderCmd->add_option("--aov", render.aovs,
                          "auxiliary images: all, none, or a list of ambient,diffuse,specular,reflection,"
                          "transmission,ambient_coef,diffuse_coef,specular_coef,reflection_coef,"
                          "transmission_coef,ior,depth,normal; with --aov-bounces B also reflection.1..B and "
                          "transmission.1..B")->capture_default_str();
    renderCmd->add_option("--aov-bounces", render.settings.aovBounces,
                          "split the reflection and transmission images by ray depth into B images each "
                          "(reflection.K: rays at depth K of the reflected subtree; the last holds all deeper ones)")
        ->check(CLI::Range(0, int(gpu::kAovBouncesMax)))->capture_default_str();
    renderCmd->add_option("--tonemap", tonemap, "clamp (sRGB) or seed (min-max normalisation, gamma 0.667)")
        ->check(CLI::IsMember({"clamp", "seed"}))->capture_default_str();
    renderCmd->add_option("--device", render.device,
                          "Vulkan device index or name substring [best available]; all, or a list such as 0,1, "
                          "shares the bands of one render among several devices");
    bool noBvh = false;
    renderCmd->add_flag("--no-bvh", noBvh, "test every primitive for every ray (reference for comparisons)");
    std::string trace = "auto";
    renderCmd->add_option("--trace", trace,
                          "how rays find the scene: bvh (our BVH), rayquery (the device's acceleration structures, "
                          "VK_KHR_ray_query), auto (ray queries on a GPU that has them, else bvh)")
        ->check(CLI::IsMember({"auto", "bvh", "rayquery"}))->capture_default_str();
    renderCmd->add_flag("--validate", render.validation, "enable the Khronos validation layer; fail on any message");
    renderCmd->add_flag("-q,--quiet", render.quiet, "no progress or summary");

    app.add_subcommand("devices", "list the Vulkan devices");

    ViewOptions view;
    view.settings.samplesPerPixel = 256;
    auto* viewCmd = app.add_subcommand("view", "open a scene in a live window (README \"Live window\")");
    viewCmd->add_option("scene", view.scene,
                        "scene XML file (.xml), or a model file (a quick look; Ctrl+S writes MODEL.whitted.xml)")
        ->required();
    viewCmd->add_option("--width", view.settings.width, "image width in pixels [scene's]")->check(CLI::Range(1, 16384));
    viewCmd->add_option("--height", view.settings.height, "image height in pixels [scene's]")->check(CLI::Range(1, 16384));
    viewCmd->add_option("--spp", view.settings.samplesPerPixel, "sample budget per pixel; tracing stops there")
        ->check(CLI::Range(1, 65536))->capture_default_str();
    viewCmd->add_option("--max-depth", view.settings.maxDepth, "secondary bounces")
        ->check(CLI::Range(0, int(gpu::kMaxDepthLimit)))->capture_default_str();
    viewCmd->add_option("--aov-bounces", view.settings.aovBounces,
                        "also show reflection and transmission split by ray depth into B images each (L cycles)")
        ->check(CLI::Range(0, int(gpu::kAovBouncesMax)))->capture_default_str();
    viewCmd->add_option("--frames", view.frames, "close after N frames [until the window is closed]")->check(CLI::NonNegativeNumber);
    viewCmd->add_option("--screenshot", view.screenshot, "write the image shown as PNG when closing");
    viewCmd->add_option("--script", view.script, "timed input commands (see host/view/view_script.h)");
    viewCmd->add_option("--frame-ms", view.targetFrameMs, "target milliseconds per frame")
        ->check(CLI::Range(5.0, 1000.0))->capture_default_str();
    viewCmd->add_option("--device", view.device, "Vulkan device index or name substring [best available]");
    viewCmd->add_flag("--validate", view.validation, "enable the Khronos validation layer; fail on any message");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int status = app.exit(e);
        return status == 0 ? kExitOk : kExitBadInput;
    }

    try {
        if (renderCmd->parsed()) {
            if (!output.empty()) render.output = output;
            render.settings.useBvh = !noBvh;
            if (noBvh && trace == "rayquery") {
                std::cerr << "whitted: --no-bvh and --trace rayquery exclude each other\n";
                return kExitBadInput;
            }
            render.settings.trace = trace == "rayquery" ? TracePath::RayQuery
                                    : trace == "bvh"    ? TracePath::Bvh
                                                        : TracePath::Auto;
            render.settings.antiAliasing = aa == "uniform" ? AntiAliasing::Uniform : AntiAliasing::Adaptive;
            if (!region.empty()) {
                PixelRegion r;
                char tail = 0;
                if (std::sscanf(region.c_str(), "%d,%d,%d,%d%c", &r.x0, &r.y0, &r.x1, &r.y1, &tail) != 4) {
                    std::cerr << "whitted: --region: expected X0,Y0,X1,Y1 (four integers), got '" << region << "'\n";
                    return kExitBadInput;
                }
                render.settings.region = r;
            }
            render.tonemap = tonemap == "seed" ? Tonemap::Seed : Tonemap::Clamp;
            render.validation = render.validation || validationFromEnvironment();
            return runRenderCommand(render);
        }
        if (viewCmd->parsed()) {
            view.validation = view.validation || validationFromEnvironment();
            return runViewCommand(view);
        }
        return runDevicesCommand();
    } catch (const std::exception& e) {
        std::cerr << "whitted: " << e.what() << "\n";
        return kExitFailure;
    }
}

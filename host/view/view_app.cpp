#include "view/view_app.h"

#include "output/aov_output.h"
#include "io/image_io.h"
#include "output/render_record.h"
#include "render/ray_tree.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "view/camera_controller.h"
#include "view/editor_panel.h"
#include "view/file_watcher.h"
#include "view/imgui_layer.h"
#include "view/layer_views.h"
#include "view/presenter.h"
#include "view/progressive.h"
#include "view/ray_tree_overlay.h"
#include "view/script_runner.h"
#include "view/window.h"
#include "vk/context.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui/imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>

namespace whitted {
namespace {

using Clock = std::chrono::steady_clock;

// The image files the scene's materials and environment name (textures,
// normal maps, the panorama), resolved as the loader resolves them; hot
// reload watches them too.
std::vector<std::filesystem::path> textureFiles(const Scene& scene) {
    std::set<std::filesystem::path> files;
    for (const Object& o : scene.objects)
        for (const TextureRef* t : o.material.textures())
            if (*t && !t->written.empty()) {
                std::filesystem::path path(t->written);
                files.insert(path.is_relative() ? scene.sourcePath.parent_path() / path : path);
            }
    if (scene.environment && scene.environment->image && !scene.environment->imageWritten.empty()) {
        std::filesystem::path path(scene.environment->imageWritten);  // the environment's image too
        files.insert(path.is_relative() ? scene.sourcePath.parent_path() / path : path);
    }
    return {files.begin(), files.end()};
}

void writeRgba8Png(const std::filesystem::path& path, const Rgba8Image& image) {
    std::vector<float> rgb(size_t(image.width) * image.height * 3);
    for (size_t i = 0, n = size_t(image.width) * image.height; i < n; ++i)
        for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = float(image.pixels[i * 4 + c]) / 255.0f;
    // Linear8 stores round(v * 255): the bytes come out as they went in.
    writeImage(path, image.width, image.height, 3, rgb, PixelEncoding::Linear8);
}

class ViewApp final : public ScriptTarget {
public:
    ViewApp(const ViewOptions& options, Scene scene, std::vector<ScriptCommand> script)
        : options_(options),
          scene_(std::move(scene)),
          window_(windowSize(options, scene_).x * windowScale(options, scene_),
                  windowSize(options, scene_).y * windowScale(options, scene_),
                  "whitted view - " + options.scene.string()),
          ctx_(contextOptions(options)),
          renderer_(ctx_, scene_, rendererSettings(options)),
          presenter_(ctx_, window_.handle(), renderer_.outputBuffer(), renderer_.width(), renderer_.height()),
          imgui_(ctx_, window_.handle(), presenter_),
          camera_(scene_.camera, sceneRadius(scene_)),
          progressive_(renderer_.width(), renderer_.height(), uint32_t(options.settings.samplesPerPixel),
                       options.targetFrameMs / 1000.0),
          // A quick look does not watch (nor hold a copy of) the model file.
          watcher_(options.sceneOut ? *options.sceneOut : options.scene, std::chrono::milliseconds(250)),
          layers_(layerViews(renderer_.width(), renderer_.height(), options.settings.aovBounces)),
          script_(options.script.value_or(""), std::move(script)) {
        window_.setInputSink(this);
        watchTextures();
        camera_.takeChanged();  // the file's camera, already uploaded
        depthScale_ = float(sceneRadius(scene_));
        overlay_.device = ctx_.deviceInfo().name;
        log("opened " + options.scene.string() + " at " + std::to_string(renderer_.width()) + "x" +
            std::to_string(renderer_.height()) + ", " + std::to_string(options.settings.samplesPerPixel) +
            " spp, device " + ctx_.deviceInfo().name);
    }

    ViewOutcome run();

    // InputSink
    void onKey(int key, int action, int mods) override;
    void onMouseButton(int button, int action, double x, double y) override;
    void onCursor(double x, double y) override;
    void onScroll(double steps) override { camera_.zoom(steps); }

    // ScriptTarget
    long framesDrawn() const override { return frame_; }
    uint32_t completedSamples() const override { return progressive_.completedSamples(); }
    long reloads() const override { return reloadCount_; }
    glm::dvec2 cursor() const override { return cursor_; }
    std::optional<std::string> editObject(int object, ObjectField field, double value) override {
        std::optional<std::string> error = setObjectField(scene_, object, field, value);
        if (!error) uploadScene("edited object " + std::to_string(object));
        return error;
    }
    void select(bool light, int index) override {
        editor_.selectedLight = light ? index : -1;
        editor_.selectedObject = light ? -1 : index;
    }
    void showLayer(size_t index) override { layer_ = index; }
    std::optional<std::string> pickPixel(int x, int y) override {
        if (x >= renderer_.width() || y >= renderer_.height())
            return "pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                   std::to_string(renderer_.width()) + "x" + std::to_string(renderer_.height()) + " image";
        rayTree_.pixel = glm::ivec2(x, y);
        rayTree_.picking = false;
        retraceRayTree();
        return std::nullopt;
    }
    void screenshotAfterFrame(const std::filesystem::path& path, bool window) override {
        pendingShots_.emplace_back(path, window);
    }
    void saveImages() override;
    void saveScene() override;

private:
    static glm::ivec2 windowSize(const ViewOptions& o, const Scene& s) {
        return {o.settings.width > 0 ? o.settings.width : s.camera.width,
                o.settings.height > 0 ? o.settings.height : s.camera.height};
    }
    // Small images are shown enlarged by a whole factor (nearest pixel), so
    // that the overlay and the panel have room.
    static int windowScale(const ViewOptions& o, const Scene& s) {
        glm::ivec2 size = windowSize(o, s);
        return std::max(1, std::min(800 / size.x, 600 / size.y));
    }
    static ContextOptions contextOptions(const ViewOptions& o) {
        ContextOptions c{.validation = o.validation, .deviceName = o.device};
        c.instanceExtensions = Window::requiredInstanceExtensions();
        c.canPresent = [](VkInstance instance, VkPhysicalDevice device, uint32_t family) {
            return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
        };
        return c;
    }
    RenderSettings rendererSettings(const ViewOptions& o) const {
        RenderSettings s = o.settings;
        glm::ivec2 size = windowSize(o, scene_);
        s.width = size.x;
        s.height = size.y;
        s.auxiliary = true;
        s.ids = true;  // the masks are in the window's list
        // The window draws from the renderer's sums of the whole image, and
        // refines uniformly: every pass adds samples to every pixel, so the
        // picture sharpens evenly and the final sums equal render's
        // --aa uniform (README "Live window").
        s.bandBytes = 0;
        s.antiAliasing = AntiAliasing::Uniform;
        return s;
    }

    void log(const std::string& line) {
        std::printf("view: %s\n", line.c_str());
        std::fflush(stdout);
    }
    void restart(const std::string& why) {
        progressive_.restart();
        log("restart (" + why + ")");
    }
    void uploadScene(const std::string& why) {
        Scene shown = scene_;
        shown.camera = camera_.camera();
        renderer_.setScene(shown);
        restart(why);
        retraceRayTree();
    }
    // The picked pixel's tree for the scene and camera now uploaded.
    void retraceRayTree() {
        if (!rayTree_.pixel) return;
        rayTree_.tree = rayTreeRecorder_.trace(renderer_, rayTree_.pixel->x, rayTree_.pixel->y);
        glm::vec3 c = rayTree_.tree->color();
        log("ray tree of pixel " + std::to_string(rayTree_.pixel->x) + "," + std::to_string(rayTree_.pixel->y) + ": " +
            std::to_string(rayTree_.tree->rays.size()) + " rays, colour " + std::to_string(c.r) + " " +
            std::to_string(c.g) + " " + std::to_string(c.b));
    }
    void checkReload();
    void watchTextures();
    // A failed save (disk full, no permission) is shown, not fatal.
    template <typename F>
    void guarded(F&& f) {
        try {
            f();
        } catch (const std::exception& e) {
            overlay_.status = std::string("save failed: ") + e.what();
            log(overlay_.status);
        }
    }
    // " (N ms after the file changed)", from the file's modification time.
    std::string sinceChange() const {
        std::error_code ec;
        auto modified = std::filesystem::last_write_time(options_.scene, ec);
        if (ec) return "";
        auto age = std::filesystem::file_time_type::clock::now() - modified;
        return " (" + std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(age).count()) +
               " ms after the file changed)";
    }
    void flyFromKeys(double seconds);
    void writeScreenshot(const std::filesystem::path& path, bool window);

    const ViewOptions& options_;
    Scene scene_;
    Window window_;
    VulkanContext ctx_;
    Renderer renderer_;
    Presenter presenter_;
    ImGuiLayer imgui_;
    CameraController camera_;
    Progressive progressive_;
    FileWatcher watcher_;
    std::vector<FileWatcher> textureWatchers_;  // the scene's texture files (textureFiles)
    std::vector<LayerView> layers_;
    size_t layer_ = 0;
    float depthScale_ = 1;
    EditorState editor_;
    OverlayInfo overlay_;
    RayTreeRecorder rayTreeRecorder_{ctx_};
    RayTreeView rayTree_;

    // Input state.
    std::set<int> heldKeys_;
    int dragButton_ = -1;
    glm::dvec2 cursor_{0};

    // The script, started once the window and the renderer are up.
    ScriptRunner script_;
    long reloadCount_ = 0;  // file changes seen, loaded or refused
    std::vector<std::pair<std::filesystem::path, bool>> pendingShots_;  // path, whole window
    bool quit_ = false;
    ViewOutcome status_ = ViewOutcome::Closed;
    long frame_ = 0;
};

void ViewApp::onKey(int key, int action, int mods) {
    if (action == GLFW_RELEASE) {
        heldKeys_.erase(key);
        return;
    }
    if (action == GLFW_PRESS) heldKeys_.insert(key);
    if (action != GLFW_PRESS) return;
    switch (key) {
        case GLFW_KEY_ESCAPE:
            quit_ = true;
            break;
        case GLFW_KEY_R:
            camera_.reset();
            break;
        case GLFW_KEY_L:
            layer_ = (mods & GLFW_MOD_SHIFT) ? (layer_ + layers_.size() - 1) % layers_.size()
                                             : (layer_ + 1) % layers_.size();
            log("showing " + layers_[layer_].name);
            break;
        case GLFW_KEY_0:
            layer_ = 0;
            log("showing color");
            break;
        case GLFW_KEY_C:
            std::printf("%s", cameraXml(camera_.camera()).c_str());
            std::fflush(stdout);
            break;
        case GLFW_KEY_P:
            guarded([&] { saveImages(); });
            break;
        case GLFW_KEY_T:
            rayTree_.picking = true;
            overlay_.status = "click a pixel to see its ray tree";
            break;
        case GLFW_KEY_F1:
            editor_.visible = !editor_.visible;
            break;
        case GLFW_KEY_S:
            if (mods & GLFW_MOD_CONTROL) guarded([&] { saveScene(); });
            break;
        default:
            break;
    }
}

void ViewApp::onMouseButton(int button, int action, double x, double y) {
    cursor_ = {x, y};
    // T then a click, or Ctrl+click: the ray tree of the pixel under the cursor.
    bool control = heldKeys_.count(GLFW_KEY_LEFT_CONTROL) || heldKeys_.count(GLFW_KEY_RIGHT_CONTROL);
    if (button == GLFW_MOUSE_BUTTON_LEFT && action == GLFW_PRESS && (rayTree_.picking || control) &&
        !ImGui::GetIO().WantCaptureMouse) {
        int w = 0, h = 0;
        glfwGetWindowSize(window_.handle(), &w, &h);
        int px = std::clamp(int(x * renderer_.width() / std::max(w, 1)), 0, renderer_.width() - 1);
        int py = std::clamp(int(y * renderer_.height() / std::max(h, 1)), 0, renderer_.height() - 1);
        pickPixel(px, py);
        overlay_.status.clear();
        return;
    }
    if (action == GLFW_PRESS && dragButton_ < 0)
        dragButton_ = button;
    else if (action == GLFW_RELEASE && button == dragButton_)
        dragButton_ = -1;
}

void ViewApp::onCursor(double x, double y) {
    glm::dvec2 d = glm::dvec2(x, y) - cursor_;
    cursor_ = {x, y};
    if (dragButton_ == GLFW_MOUSE_BUTTON_LEFT)
        camera_.orbit(d.x, d.y);
    else if (dragButton_ == GLFW_MOUSE_BUTTON_RIGHT || dragButton_ == GLFW_MOUSE_BUTTON_MIDDLE) {
        int w = 0, h = 0;
        glfwGetWindowSize(window_.handle(), &w, &h);
        camera_.pan(d.x, d.y, h);
    }
}

void ViewApp::flyFromKeys(double seconds) {
    if (ImGui::GetIO().WantCaptureKeyboard || heldKeys_.count(GLFW_KEY_LEFT_CONTROL)) return;
    glm::dvec3 d(0);
    auto held = [&](int k) { return heldKeys_.count(k) ? 1.0 : 0.0; };
    d.z = held(GLFW_KEY_W) - held(GLFW_KEY_S);
    d.x = held(GLFW_KEY_D) - held(GLFW_KEY_A);
    d.y = held(GLFW_KEY_E) - held(GLFW_KEY_Q);
    if (d != glm::dvec3(0)) camera_.fly(d, std::min(seconds, 0.1));
}

// A changed file is loaded in full; a refused one leaves the last good scene
// in place and its FILE:LINE message on screen until a good version arrives.
void ViewApp::watchTextures() {
    textureWatchers_.clear();
    for (const std::filesystem::path& file : textureFiles(scene_))
        textureWatchers_.emplace_back(file, std::chrono::milliseconds(250));
}

// A changed texture file reloads the scene file as it is on disk (so the
// textures are read again) in the same way.
void ViewApp::checkReload() {
    if (options_.sceneOut) return;  // a quick look: the model file is not a scene to reload
    std::optional<std::string> text = watcher_.poll();
    bool textureChanged = false;
    for (FileWatcher& w : textureWatchers_) textureChanged |= w.poll().has_value();
    if (!text && !textureChanged) return;
    if (!text) {
        std::ifstream in(options_.scene, std::ios::binary);
        text = std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        log("texture file changed");
    }
    ++reloadCount_;
    try {
        Scene fresh = loadSceneFromString(*text, options_.scene);
        bool cameraChanged =
            fresh.camera.eye != scene_.camera.eye || fresh.camera.windowCenter != scene_.camera.windowCenter ||
            fresh.camera.up != scene_.camera.up || fresh.camera.verticalFovDegrees != scene_.camera.verticalFovDegrees ||
            fresh.camera.intrinsics != scene_.camera.intrinsics ||
            fresh.camera.apertureRadius != scene_.camera.apertureRadius ||
            fresh.camera.focusDistance != scene_.camera.focusDistance;
        scene_ = std::move(fresh);
        watchTextures();
        if (cameraChanged) camera_.setHome(scene_.camera, sceneRadius(scene_));
        depthScale_ = float(sceneRadius(scene_));
        overlay_.error.clear();
        overlay_.status = "reloaded " + options_.scene.filename().string();
        for (const std::string& w : scene_.warnings) log("warning: " + w);
        uploadScene("scene file reloaded");
        camera_.takeChanged();
        log("reloaded " + options_.scene.string() + sinceChange());
    } catch (const SceneError& e) {
        overlay_.error = e.what();
        log(std::string("reload refused: ") + e.what() + sinceChange());
    }
}

void ViewApp::saveImages() {
    RenderResult result = renderer_.readMeans();
    std::vector<std::string> aovs = parseAovList("all", renderer_.settings().aovBounces);
    std::filesystem::path folder = writeHistoryFolder(options_.historyRoot, [&](const std::filesystem::path& staging) {
        std::vector<std::filesystem::path> files =
            writeRenderImages(result, staging / "image.png", aovs, Tonemap::Clamp, options_.exposure);
        Scene shown = scene_;
        shown.camera = camera_.camera();
        writeSceneFile(shown, staging / "scene.xml");
        files.push_back(staging / "scene.xml");
        RenderSettings settings = renderer_.settings();
        settings.samplesPerPixel = result.samplesPerPixel;
        RenderRecord record{.scenePath = options_.scene,
                            .settings = settings,
                            .tonemap = "clamp",
                            .device = ctx_.deviceInfo(),
                            .sharedWith = {},
                            .result = &result,
                            .files = files,
                            .warnings = scene_.warnings,
                            .warningDetails = scene_.warningDetails,
                            .masks = &scene_,
                            .exposure = options_.exposure,
                            .camera = options_.camera};
        writeTextFile(staging / "render.json", renderRecordJson(record));
    });
    overlay_.status = "saved " + folder.string();
    log("saved images to " + folder.string() + " (" + std::to_string(result.samplesPerPixel) + " spp)");
}

// The scene as edited, with the current camera, over the scene file
// (atomically); the watcher is told, so the write does not count as an edit.
void ViewApp::saveScene() {
    Scene shown = scene_;
    shown.camera = camera_.camera();
    const std::filesystem::path& target = options_.sceneOut ? *options_.sceneOut : options_.scene;
    std::string text = sceneXml(shown, target);
    writeTextFile(target, text);
    if (!options_.sceneOut) watcher_.markSeen(text);
    overlay_.status = "saved " + target.string();
    log("saved scene to " + target.string());
}

void ViewApp::writeScreenshot(const std::filesystem::path& path, bool window) {
    Rgba8Image image = window ? presenter_.windowPixels() : presenter_.displayPixels();
    writeRgba8Png(path, image);
    log(std::string(window ? "window screenshot " : "screenshot ") + path.string() + " (" +
        std::to_string(progressive_.completedSamples()) + " spp, " + layers_[layer_].name + ")");
}

ViewOutcome ViewApp::run() {
    auto last = Clock::now();
    double smoothedRays = 0, smoothedMs = 0, overheadSeconds = 0;
    double traceTotal = 0, frameTotal = 0, frameMax = 0;
    long tracedFrames = 0;
    while (!quit_ && !window_.shouldClose()) {
        bool idle = progressive_.done() && script_.finished() && heldKeys_.empty() && dragButton_ < 0 &&
                    options_.frames == 0;
        if (idle)
            glfwWaitEventsTimeout(0.05);  // nothing to trace: don't spin the CPU
        else
            glfwPollEvents();
        auto now = Clock::now();
        double dt = std::chrono::duration<double>(now - last).count();
        last = now;

        ScriptStep step = script_.step(*this);
        if (step == ScriptStep::Refused) status_ = ViewOutcome::ScriptRefused;
        if (step == ScriptStep::TimedOut) status_ = ViewOutcome::Failed;
        if (step == ScriptStep::Refused || step == ScriptStep::TimedOut) break;
        if (step == ScriptStep::Quit) quit_ = true;
        flyFromKeys(dt);
        checkReload();

        imgui_.newFrame();
        EditorResult edit = drawEditorPanel(scene_, editor_);
        if (edit.changed) uploadScene("edited in the panel");
        if (edit.lensChanged) camera_.setLens(scene_.camera.apertureRadius, scene_.camera.focusDistance);
        if (edit.saveRequested) guarded([&] { saveScene(); });
        if (camera_.takeChanged()) {
            renderer_.setCamera(camera_.camera());
            restart("camera moved");
            retraceRayTree();
        }
        overlay_.layer = layers_[layer_].name;
        overlay_.samples = progressive_.completedSamples();
        overlay_.target = progressive_.targetSamples();
        overlay_.frameMs = smoothedMs;
        overlay_.raysPerSecond = smoothedRays;
        drawOverlay(overlay_);
        ImVec2 windowSize = ImGui::GetIO().DisplaySize;
        drawRayTreeView(rayTree_, scene_, camera_.camera(), glm::vec2(renderer_.width(), renderer_.height()),
                        glm::vec2(windowSize.x, windowSize.y));
        ImDrawData* drawData = imgui_.render();

        if (!presenter_.beginFrame()) {  // minimised, or the swapchain was rebuilt
            glfwWaitEventsTimeout(0.05);
            continue;
        }

        // Tracing in a submission of its own, so that its time is measured
        // apart from the display and the overlay; the budget gets what the
        // frame target leaves after them.
        renderer_.counters() = {};
        uint64_t recorded = 0;
        auto traceStart = Clock::now();
        if (!progressive_.done() || progressive_.needsClear())
            ctx_.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
                renderer_.recordCountersZero(cmd);
                recorded = progressive_.record(renderer_, cmd);
                renderer_.recordCountersDownload(cmd);
            });
        double traceSeconds = std::chrono::duration<double>(Clock::now() - traceStart).count();
        double target = options_.targetFrameMs / 1000.0;
        progressive_.setTargetSeconds(std::max(target - overheadSeconds, 0.25 * target));
        progressive_.frameDone(traceSeconds, recorded);

        gpu::DisplayParams display = layers_[layer_].params;
        display.depthMedian = depthScale_;
        display.exposure = float(options_.exposure);
        presenter_.recordDisplay(display);
        bool captureWindow = std::any_of(pendingShots_.begin(), pendingShots_.end(), [](auto& s) { return s.second; });
        presenter_.recordOverlay(drawData, captureWindow);
        double presentSeconds = presenter_.endFrame();
        overheadSeconds = overheadSeconds == 0 ? presentSeconds : 0.8 * overheadSeconds + 0.2 * presentSeconds;
        if (ctx_.validationMessageCount() > 0) {
            std::cerr << "whitted: the Vulkan validation layer reported " << ctx_.validationMessageCount()
                      << " message(s)\n";
            return ViewOutcome::ValidationMessages;
        }

        const gpu::RayCounters& rays = renderer_.counters();
        double frameRays = double(rays.primary) + rays.shadow + rays.secondary;
        double frameSeconds = traceSeconds + presentSeconds;
        smoothedMs = smoothedMs == 0 ? frameSeconds * 1e3 : 0.9 * smoothedMs + 0.1 * frameSeconds * 1e3;
        if (recorded > 0) {
            smoothedRays =
                smoothedRays == 0 ? frameRays / traceSeconds : 0.9 * smoothedRays + 0.1 * frameRays / traceSeconds;
            tracedFrames++;
            traceTotal += traceSeconds;
            frameTotal += frameSeconds;
            frameMax = std::max(frameMax, frameSeconds);
        }
        for (auto& [path, whole] : pendingShots_) writeScreenshot(path, whole);
        pendingShots_.clear();
        ++frame_;
        if (options_.frames > 0 && frame_ >= options_.frames) break;
    }
    if (options_.screenshot && status_ == ViewOutcome::Closed) writeScreenshot(*options_.screenshot, false);
    char timing[160];
    std::snprintf(timing, sizeof timing, "; frames that traced: %ld, mean %.1f ms (tracing %.1f ms), longest %.1f ms",
                  tracedFrames, tracedFrames ? 1e3 * frameTotal / tracedFrames : 0.0,
                  tracedFrames ? 1e3 * traceTotal / tracedFrames : 0.0, 1e3 * frameMax);
    log("closed after " + std::to_string(frame_) + " frames, " + std::to_string(progressive_.completedSamples()) +
        " spp" + timing);
    return status_;
}

}  // namespace

ViewOutcome runViewWindow(const ViewOptions& options, Scene scene, std::vector<ScriptCommand> script) {
    ViewApp app(options, std::move(scene), std::move(script));
    return app.run();
}

}  // namespace whitted

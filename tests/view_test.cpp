// `whitted view`, the live window, driven by --script under Xvfb with
// lavapipe (each test starts its own server with `xvfb-run -a`; CI has
// xvfb). The screenshot is the tone-mapped image the window shows, read
// back before the overlay is drawn.
//
// Tolerance against `whitted render`: at most 1 level of 255 per channel.
// Both trace the same sample indices with the same shader; what differs is
// how the float additions are grouped (render adds a pixel's samples inside
// one invocation and the colour components last; the window adds passes of
// 1, 1, 2, 4 samples, whole samples at a time), so sums differ in the last
// bits, and the sRGB curve (GLSL pow on the device, std::pow on the host).
// Either moves a value across an 8-bit rounding boundary at most, so 1
// level; a wrong sample count, a missed restart or stale scene data moves
// whole regions by far more.

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include "io/image_io.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"
#include "view/progressive.h"

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

// The window under its own virtual X server.
CommandRun runView(const std::string& args, const fs::path& cwd) {
    return runCommand("xvfb-run -a -s '-screen 0 1024x768x24' '" WHITTED_EXECUTABLE "' view " + args, cwd);
}

// The window refines uniformly: compare with render's uniform sampling.
CommandRun runRender(const std::string& args, const fs::path& cwd) {
    return runCommand("'" WHITTED_EXECUTABLE "' render -q --aa uniform " + args, cwd);
}

fs::path scratchDir(const std::string& name) { return freshOutputDir("view", name); }

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

struct Image8 {
    int width = 0, height = 0, channels = 0;
    std::vector<int> v;  // 0..255
    int at(int x, int y, int c) const { return v[(size_t(y) * width + x) * channels + c]; }
};

Image8 readPng(const fs::path& path) {
    Image8 image;
    std::vector<float> storage;
    readImageInto(path, image.width, image.height, image.channels, storage);
    for (float f : storage) image.v.push_back(int(std::lround(f * 255.0f)));
    return image;
}

struct Difference {
    int maxLevels = 0;
    double meanLevels = 0;
};

Difference compareRgb(const Image8& a, const Image8& b) {
    Difference d;
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    if (a.width != b.width || a.height != b.height) return {255, 255};
    double sum = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c) {
                int e = std::abs(a.at(x, y, c) - b.at(x, y, c));
                d.maxLevels = std::max(d.maxLevels, e);
                sum += e;
            }
    d.meanLevels = sum / (3.0 * a.width * a.height);
    return d;
}

std::string room() {
    return (sourceDir() / "scenes" / "room.xml").string();
}

constexpr const char* kSmall = "--width 160 --height 120 --spp 4";

TEST(View, ScreenshotAfterFramesMatchesRender) {
    fs::path dir = scratchDir("frames");
    CommandRun view = runView(room() + " " + kSmall + " --frames 150 --screenshot view.png", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    EXPECT_NE(view.output.find("closed after 150 frames, 4 spp"), std::string::npos) << view.output;
    ASSERT_EQ(runRender(room() + " " + kSmall + " --aov none -o render.png", dir).status, 0);
    Difference d = compareRgb(readPng(dir / "view.png"), readPng(dir / "render.png"));
    EXPECT_LE(d.maxLevels, 1) << "mean " << d.meanLevels;
}

// An authored glTF scene (its own camera, metal, glass, a point, a spot and
// a directional light, the README's picture) in the window looks as
// `render` draws it.
TEST(View, AuthoredGltfMatchesRender) {
    fs::path dir = scratchDir("authored");
    const std::string scene = (sourceDir() / "scenes" / "pictures" / "authored.gltf").string();
    const std::string size = "--width 160 --height 90 --spp 4";
    CommandRun view = runView(scene + " " + size + " --frames 150 --screenshot view.png", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    ASSERT_EQ(runRender(scene + " " + size + " --aov none -o render.png", dir).status, 0);
    Difference d = compareRgb(readPng(dir / "view.png"), readPng(dir / "render.png"));
    EXPECT_LE(d.maxLevels, 1) << "mean " << d.meanLevels;
}

TEST(View, CameraMoveRestartsAccumulation) {
    fs::path dir = scratchDir("camera");
    writeText(dir / "script.txt",
              "spp 4\nscreenshot before.png\n"
              "drag left 60 -20\nspp 4\nscreenshot moved.png\n"
              "key R\nspp 4\nscreenshot reset.png\nquit\n");
    CommandRun view = runView(room() + " " + kSmall + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    // The drag and the reset each restart.
    std::regex restart("restart \\(camera moved\\)");
    EXPECT_EQ(
        std::distance(std::sregex_iterator(view.output.begin(), view.output.end(), restart), std::sregex_iterator()), 2)
        << view.output;
    ASSERT_EQ(runRender(room() + " " + kSmall + " --aov none -o render.png", dir).status, 0);
    Image8 render = readPng(dir / "render.png");
    EXPECT_LE(compareRgb(readPng(dir / "before.png"), render).maxLevels, 1);
    EXPECT_GT(compareRgb(readPng(dir / "moved.png"), render).meanLevels, 5) << "the drag did not move the camera";
    // Back at the file's camera, a clean restart gives the render again: no
    // sample from the moved camera is left in the sums.
    Difference reset = compareRgb(readPng(dir / "reset.png"), render);
    EXPECT_LE(reset.maxLevels, 1) << "mean " << reset.meanLevels;
}

// The glass sphere's light turned blue in the file: picked up within a
// second, and the window then shows what `render` makes of the edited file.
TEST(View, FileEditIsPickedUp) {
    fs::path dir = scratchDir("edit");
    std::string original = readText(room());
    writeText(dir / "scene.xml", original);
    const std::string from = "<r>0.6</r><g>0.6</g><b>0.6</b>", to = "<r>0.2</r><g>0.2</g><b>0.9</b>";
    ASSERT_NE(original.find(from), std::string::npos);
    std::string edited = original;
    edited.replace(edited.find(from), from.size(), to);
    writeText(dir / "edited.xml", edited);
    writeText(dir / "script.txt", "spp 4\nscreenshot before.png\nreplace scene.xml " + from + " " + to +
                                      "\nreload\nspp 4\nscreenshot after.png\nquit\n");
    CommandRun view = runView("scene.xml " + std::string(kSmall) + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(view.output, m, std::regex("reloaded scene.xml \\((\\d+) ms after the file changed\\)")))
        << view.output;
    EXPECT_LT(std::stoi(m[1]), 1000);
    ASSERT_EQ(runRender("edited.xml " + std::string(kSmall) + " --aov none -o edited.png", dir).status, 0);
    Image8 after = readPng(dir / "after.png");
    EXPECT_LE(compareRgb(after, readPng(dir / "edited.png")).maxLevels, 1);
    EXPECT_GT(compareRgb(after, readPng(dir / "before.png")).meanLevels, 3) << "the edit changed nothing";
}

// A broken file keeps the window and the last good scene; the error, with
// its file and line, shows in a red banner until the file is good again.
TEST(View, BrokenEditKeepsWindowAndShowsError) {
    fs::path dir = scratchDir("broken");
    std::string original = readText(room());
    writeText(dir / "scene.xml", original);
    writeText(dir / "good.xml", original);
    writeText(dir / "script.txt",
              "spp 4\nframes 2\nwindow_screenshot good_window.png\n"
              "replace scene.xml </lights> </lihgts>\nreload\nframes 2\n"
              "screenshot broken.png\nwindow_screenshot broken_window.png\n"
              "copy good.xml scene.xml\nreload\nframes 2\nwindow_screenshot fixed_window.png\nquit\n");
    CommandRun view = runView("scene.xml " + std::string(kSmall) + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    EXPECT_TRUE(std::regex_search(view.output, std::regex("reload refused: scene\\.xml:\\d+: ")));
    EXPECT_NE(view.output.find("reloaded scene.xml"), std::string::npos) << view.output;

    // The last good scene stays, with its samples.
    ASSERT_EQ(runRender(room() + " " + kSmall + " --aov none -o render.png", dir).status, 0);
    EXPECT_LE(compareRgb(readPng(dir / "broken.png"), readPng(dir / "render.png")).maxLevels, 1);

    // The banner: pure red pixels (0.75, 0.05, 0.05) in the bottom rows.
    auto bannerPixels = [](const Image8& w) {
        int n = 0;
        for (int y = w.height * 3 / 4; y < w.height; ++y)
            for (int x = 0; x < w.width; ++x) n += w.at(x, y, 0) > 150 && w.at(x, y, 1) < 40 && w.at(x, y, 2) < 40;
        return n;
    };
    Image8 broken = readPng(dir / "broken_window.png");
    EXPECT_GT(bannerPixels(broken), broken.width * 20) << "no error banner";
    EXPECT_EQ(bannerPixels(readPng(dir / "good_window.png")), 0);
    EXPECT_EQ(bannerPixels(readPng(dir / "fixed_window.png")), 0) << "the banner stayed after a good reload";
}

// What the editor panel does (the same function): the glass sphere's IOR
// set to 1 makes it invisible but for its reflections; Save writes a file
// that loads to the edited scene and renders to what the window shows.
TEST(View, EditorEditAndSave) {
    fs::path dir = scratchDir("editor");
    writeText(dir / "scene.xml", readText(room()));
    writeText(dir / "script.txt",
              "spp 4\nscreenshot before.png\nedit 6 ior 1.0\nspp 4\nscreenshot ior1.png\n"
              "save_scene\nquit\n");
    CommandRun view = runView("scene.xml " + std::string(kSmall) + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    Scene saved = loadScene(dir / "scene.xml");
    ASSERT_EQ(saved.objects.size(), 9u);
    EXPECT_EQ(saved.objects[6].material.ior, 1.0);
    EXPECT_FALSE(fs::exists(dir / ".scene.xml.partial"));
    ASSERT_EQ(runRender("scene.xml " + std::string(kSmall) + " --aov none -o saved.png", dir).status, 0);
    Image8 ior1 = readPng(dir / "ior1.png");
    EXPECT_LE(compareRgb(ior1, readPng(dir / "saved.png")).maxLevels, 1);
    EXPECT_GT(compareRgb(ior1, readPng(dir / "before.png")).meanLevels, 0.05) << "the IOR edit changed nothing";
}

// The panel's checker and absorption fields (the script's `edit` does what
// the panel does): a checker added to the back wall, its colour changed, the
// glass sphere given an absorption; the saved file holds them and renders
// what the window showed. The panel is shown with the sphere selected.
TEST(View, EditorCheckerAndAbsorption) {
    fs::path dir = scratchDir("editor_checker");
    writeText(dir / "scene.xml", readText(room()));
    writeText(dir / "script.txt",
              "spp 4\nscreenshot before.png\nedit 0 checker_size 0.5\nedit 0 checker_g 0.1\n"
              "edit 6 absorption_r 0.5\nedit 6 absorption_g 3\nedit 6 absorption_b 3\nselect object 6\nspp 4\n"
              "screenshot edited.png\nwindow_screenshot panel.png\nsave_scene\nquit\n");
    CommandRun view = runView("scene.xml " + std::string(kSmall) + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    Scene original = loadScene(room());
    Scene saved = loadScene(dir / "scene.xml");
    ASSERT_EQ(saved.objects.size(), 9u);
    EXPECT_EQ(original.objects[0].material.checkerSize, 0.0);
    EXPECT_EQ(saved.objects[0].material.checkerSize, 0.5);
    EXPECT_EQ(saved.objects[0].material.checkerColor, glm::dvec3(1, 0.1, 1));
    EXPECT_EQ(saved.objects[6].material.absorption, glm::dvec3(0.5, 3, 3));
    ASSERT_EQ(runRender("scene.xml " + std::string(kSmall) + " --aov none -o saved.png", dir).status, 0);
    Image8 edited = readPng(dir / "edited.png");
    EXPECT_LE(compareRgb(edited, readPng(dir / "saved.png")).maxLevels, 1);
    EXPECT_GT(compareRgb(edited, readPng(dir / "before.png")).meanLevels, 1.0) << "the edits changed nothing";
    EXPECT_TRUE(fs::exists(dir / "panel.png"));

    writeText(dir / "bad.txt", "edit 6 absorption_g -1\n");
    CommandRun bad = runView("scene.xml " + std::string(kSmall) + " --script bad.txt", dir);
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.output.find("bad.txt:1: edit: absorption_g must be in [0, 1e6]"), std::string::npos) << bad.output;
}

// Auxiliary images on screen match the files `render` writes, and the save
// key fills a history folder like `render` does.
TEST(View, AuxiliaryLayersAndSave) {
    fs::path dir = scratchDir("layers");
    writeText(dir / "script.txt",
              "spp 4\nlayer diffuse\nframes 1\nscreenshot diffuse.png\n"
              "layer normal\nframes 1\nscreenshot normal.png\nsave_images\nquit\n");
    CommandRun view = runView(room() + " " + kSmall + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    ASSERT_EQ(runRender(room() + " " + kSmall + " -o r.png", dir).status, 0);
    EXPECT_LE(compareRgb(readPng(dir / "diffuse.png"), readPng(dir / "r.diffuse.png")).maxLevels, 1);
    EXPECT_LE(compareRgb(readPng(dir / "normal.png"), readPng(dir / "r.normal.png")).maxLevels, 1);
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(dir / "renders")) entries.push_back(e.path());
    ASSERT_EQ(entries.size(), 1u);
    for (const char* f : {"image.png", "image.diffuse.png", "image.depth.png", "scene.xml", "render.json"})
        EXPECT_TRUE(fs::exists(entries[0] / f)) << f;
    EXPECT_LE(compareRgb(readPng(entries[0] / "image.png"), readPng(dir / "r.png")).maxLevels, 1);
}

// --aov-bounces in the window: the split images are in the L list and show
// what `render` writes for them; P saves them too.
TEST(View, SplitReflectionImages) {
    fs::path dir = scratchDir("split");
    std::string scene = (sourceDir() / "scenes" / "several_mirrors.xml").string();
    writeText(dir / "script.txt", "spp 4\nlayer reflection.2\nframes 1\nscreenshot r2.png\n"
                                  "layer transmission.1\nframes 1\nscreenshot t1.png\nsave_images\nquit\n");
    CommandRun view = runView(scene + " " + kSmall + " --aov-bounces 2 --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    ASSERT_EQ(runRender(scene + " " + kSmall + " --aov-bounces 2 -o r.png", dir).status, 0);
    Image8 r2 = readPng(dir / "r2.png");
    EXPECT_LE(compareRgb(r2, readPng(dir / "r.reflection.2.png")).maxLevels, 1);
    EXPECT_LE(compareRgb(readPng(dir / "t1.png"), readPng(dir / "r.transmission.1.png")).maxLevels, 1);
    EXPECT_GT(compareRgb(r2, readPng(dir / "r.reflection.png")).meanLevels, 0.5) << "reflection.2 is not the total";
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(dir / "renders")) entries.push_back(e.path());
    ASSERT_EQ(entries.size(), 1u);
    EXPECT_TRUE(fs::exists(entries[0] / "image.reflection.2.png"));
    EXPECT_TRUE(fs::exists(entries[0] / "image.transmission.1.png"));
}

// Real X input (XTEST events from xdotool) through GLFW and ImGui: L shows
// the next layer, a left drag orbits, a click on "6: sphere" in the panel
// and one on the left end of its IOR slider set an IOR near 1.1, a click on
// Save writes it, Escape closes. The positions are those of the 800x600
// window of a 160x120 image (enlarged 5 times) with ImGui 1.86's default
// font; the sleeps leave the window several frames to see each move.
TEST(View, RealInputDrivesCameraAndPanel) {
    fs::path dir = scratchDir("xinput");
    writeText(dir / "scene.xml", readText(room()));
    writeText(
        dir / "drive.sh",
        "\"$1\" view scene.xml " + std::string(kSmall) +
            " > view.log 2>&1 &\n"
            "pid=$!\n"
            "xdotool search --sync --name 'whitted view' > /dev/null\n"
            "sleep 2\n"
            "xdotool mousemove 200 300 sleep 0.8 key l sleep 0.8\n"
            "xdotool mousedown 1 sleep 0.3 mousemove 250 300 sleep 0.3 mousemove 300 310 sleep 0.3 mouseup 1 sleep 1\n"
            "xdotool mousemove 650 247 sleep 0.8 click 1 sleep 1\n"
            "xdotool mousemove 440 551 sleep 0.8 click 1 sleep 1\n"
            "xdotool mousemove 443 45 sleep 0.8 click 1 sleep 1\n"
            "xdotool mousemove 200 300 sleep 0.5 key Escape\n"
            "wait $pid\n");
    CommandRun run =
        runCommand("xvfb-run -a -s '-screen 0 1024x768x24' sh drive.sh '" WHITTED_EXECUTABLE "'; echo status $?", dir);
    std::string log = readText(dir / "view.log");
    ASSERT_NE(run.output.find("status 0"), std::string::npos) << run.output << log;
    EXPECT_NE(log.find("showing ambient"), std::string::npos) << log;
    EXPECT_NE(log.find("restart (camera moved)"), std::string::npos) << log;
    EXPECT_NE(log.find("restart (edited in the panel)"), std::string::npos) << log;
    EXPECT_NE(log.find("saved scene to scene.xml"), std::string::npos) << log;
    Scene saved = loadScene(dir / "scene.xml");
    ASSERT_EQ(saved.objects.size(), 9u);
    EXPECT_GT(saved.objects[6].material.ior, 1.0);
    EXPECT_LT(saved.objects[6].material.ior, 1.3);
    EXPECT_EQ(saved.objects[6].material.transmission, 0.8);
}

// A quick look of a model file: Ctrl+S (save_scene) writes the generated
// scene beside the model, never over it; that scene renders what the window
// showed, and what `render MODEL` gives.
TEST(View, QuickLookSavesTheSceneBesideTheModel) {
    fs::path dir = scratchDir("quick_look");
    fs::copy_file(sourceDir() / "tests" / "meshes" / "pyramid.obj", dir / "pyramid.obj");
    std::string model = readText(dir / "pyramid.obj");
    writeText(dir / "script.txt", "spp 4\nscreenshot view.png\nsave_scene\nquit\n");
    CommandRun view = runView("pyramid.obj " + std::string(kSmall) + " --script script.txt", dir);
    ASSERT_EQ(view.status, 0) << view.output;
    EXPECT_NE(view.output.find("saved scene to pyramid.obj.whitted.xml"), std::string::npos) << view.output;
    EXPECT_EQ(readText(dir / "pyramid.obj"), model);
    ASSERT_TRUE(fs::exists(dir / "pyramid.obj.whitted.xml"));
    ASSERT_EQ(runRender("pyramid.obj.whitted.xml " + std::string(kSmall) + " --aov none -o saved.png", dir).status, 0);
    ASSERT_EQ(runRender("pyramid.obj " + std::string(kSmall) + " --aov none -o model.png", dir).status, 0);
    EXPECT_EQ(compareRgb(readPng(dir / "saved.png"), readPng(dir / "model.png")).maxLevels, 0);
    EXPECT_LE(compareRgb(readPng(dir / "view.png"), readPng(dir / "saved.png")).maxLevels, 1);
}

TEST(View, BadInputExitsBeforeOpeningAWindow) {
    fs::path dir = scratchDir("bad");
    CommandRun missing = runCommand("'" WHITTED_EXECUTABLE "' view no_such.xml", dir);
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.output.find("no_such.xml: cannot read file"), std::string::npos) << missing.output;
    writeText(dir / "script.txt", "spp 4\njump 3\n");
    CommandRun script = runCommand("'" WHITTED_EXECUTABLE "' view " + room() + " --script script.txt", dir);
    EXPECT_EQ(script.status, 2);
    EXPECT_NE(script.output.find("script.txt:2: unknown command 'jump'"), std::string::npos) << script.output;
    writeText(dir / "args.txt", "drag left 3\n");
    CommandRun args = runCommand("'" WHITTED_EXECUTABLE "' view " + room() + " --script args.txt", dir);
    EXPECT_EQ(args.status, 2);
    EXPECT_NE(args.output.find("args.txt:1: 'drag' takes 3 argument(s), got 2"), std::string::npos) << args.output;
}

// Every script argument is checked when the script is loaded, before the
// window opens: each of these is refused with SCRIPT:LINE and exit status 2
// without an X display (DISPLAY unset: a window could not open).
TEST(View, BadScriptArgumentsAreRefusedBeforeTheWindow) {
    fs::path dir = scratchDir("bad_script_args");
    size_t objects = loadScene(room()).objects.size();
    const std::string unknownField =
        "unknown field 'colour' (ior, kt, kr, ks, kd, ka, x, y, z, operation, checker_size, checker_r|g|b, "
        "absorption_r|g|b, texture_scale, normal_strength)";
    struct Case {
        std::string script, message;
    };
    const Case cases[] = {
        {"frames abc\n", "1: frames needs a count"},
        {"frames -1\n", "1: frames needs a count"},
        {"frames 2\nspp 4\nframes 1.5\n", "3: frames needs a count"},
        {"spp -3\n", "1: spp needs a count >= 1"},
        {"spp 5\n", "1: spp 5 is above the --spp budget"},
        {"key NOPE\n", "1: unknown key 'NOPE'"},
        {"hold W x\n", "1: hold KEY SECONDS"},
        {"hold NOPE 1\n", "1: hold KEY SECONDS"},
        {"drag left a b\n", "1: drag left|right|middle DX DY"},
        {"drag up 1 1\n", "1: drag left|right|middle DX DY"},
        {"scroll many\n", "1: scroll STEPS"},
        {"select lamp 1\n", "1: select light|object N"},
        {"select object x\n", "1: select light|object N"},
        {"layer albedo\n", "1: unknown layer 'albedo'"},
        {"layer reflection.1\n", "1: unknown layer 'reflection.1'"},  // without --aov-bounces
        {"edit 0 colour 0.5\n", "1: edit: " + unknownField},
        {"edit 0 kd high\n", "1: edit OBJECT FIELD VALUE"},
        {"edit x kd 0.5\n", "1: edit OBJECT FIELD VALUE"},
        {"edit 0 kd 2\n", "1: edit: kd must be in [0, 1]"},
        {"edit 0 kd nan\n", "1: edit: value is not finite"},
        // Needs the scene: checked once it is loaded, still before the window.
        {"spp 1\nedit 0 kd 0.5\nedit " + std::to_string(objects) + " kd 0.5\n",
         "3: edit: no object " + std::to_string(objects) + " (the scene has " + std::to_string(objects) + ")"},
        {"edit 0 operation 1\n", "1: edit: operation applies to csg objects only"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.script);
        writeText(dir / "script.txt", c.script);
        CommandRun run = runCommand("env -u DISPLAY -u WAYLAND_DISPLAY '" WHITTED_EXECUTABLE "' view " + room() + " " +
                                        kSmall + " --script script.txt",
                                    dir);
        EXPECT_EQ(run.status, 2);
        EXPECT_EQ(run.output, "script.txt:" + c.message + "\n");
    }
}

// load -> write -> load gives the same Scene: every scene shipped.
void expectClose(const glm::dvec3& a, const glm::dvec3& b, const std::string& what) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-12 * std::max(1.0, std::abs(a[i]))) << what;
}

// Written to another folder, a scene's texture paths are made relative to
// the new file, so the copy loads the same images.
TEST(SceneWriter, TexturePathsFollowTheWrittenFile) {
    fs::path dir = outputDir() / "scene_writer_elsewhere" / "deeper";
    fs::create_directories(dir);
    Scene a = loadScene(sourceDir() / "scenes" / "showcase.xml");
    writeSceneFile(a, dir / "copy.xml");
    Scene b = loadScene(dir / "copy.xml");
    ASSERT_EQ(a.objects.size(), b.objects.size());
    int textures = 0;
    for (size_t i = 0; i < a.objects.size(); ++i)
        for (auto member : {&Material::diffuseTexture, &Material::normalMap}) {
            const TextureRef &t = a.objects[i].material.*member, &u = b.objects[i].material.*member;
            ASSERT_EQ(bool(t), bool(u)) << "object " << i;
            if (!t) continue;
            ++textures;
            EXPECT_NE(t.written, u.written) << "the path was not relocated";
            EXPECT_EQ(fs::weakly_canonical(sourceDir() / "scenes" / t.written),
                      fs::weakly_canonical(dir / u.written));
        }
    EXPECT_EQ(textures, 3);
}

TEST(SceneWriter, RoundTripGivesEqualScene) {
    std::vector<fs::path> files;
    for (const char* folder : {"scenes", "tests/povray_scenes", "tests/legal_scenes"})
        for (const auto& e : fs::directory_iterator(sourceDir() / folder))
            if (e.path().extension() == ".xml") files.push_back(e.path());
    ASSERT_GE(files.size(), 10u);
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        Scene a = loadScene(file);
        std::string text = sceneXml(a);
        // Without a destination, file paths stay as the scene wrote them
        // (relative to its folder): read back as a file beside it.
        Scene b = loadSceneFromString(text, file.parent_path() / "written.xml");
        expectClose(a.camera.eye, b.camera.eye, "eye");
        expectClose(a.camera.windowCenter, b.camera.windowCenter, "window");
        expectClose(a.camera.up, b.camera.up, "up");
        EXPECT_EQ(a.camera.verticalFovDegrees, b.camera.verticalFovDegrees);
        EXPECT_EQ(a.camera.width, b.camera.width);
        EXPECT_EQ(a.camera.height, b.camera.height);
        EXPECT_EQ(a.ambientLight, b.ambientLight);
        ASSERT_EQ(a.lights.size(), b.lights.size());
        for (size_t i = 0; i < a.lights.size(); ++i) {
            EXPECT_EQ(a.lights[i].position, b.lights[i].position);
            EXPECT_EQ(a.lights[i].color, b.lights[i].color);
        }
        ASSERT_EQ(a.objects.size(), b.objects.size());
        for (size_t i = 0; i < a.objects.size(); ++i) {
            const Object &x = a.objects[i], &y = b.objects[i];
            ASSERT_EQ(x.shape.index(), y.shape.index()) << "object " << i;
            const Material &m = x.material, &n = y.material;
            EXPECT_EQ(m.diffuseColor, n.diffuseColor);
            EXPECT_EQ(m.specularColor, n.specularColor);
            EXPECT_EQ(m.ambient, n.ambient);
            EXPECT_EQ(m.diffuse, n.diffuse);
            EXPECT_EQ(m.specular, n.specular);
            EXPECT_EQ(m.shininess, n.shininess);
            EXPECT_EQ(m.reflection, n.reflection);
            EXPECT_EQ(m.transmission, n.transmission);
            EXPECT_EQ(m.ior, n.ior);
            EXPECT_EQ(m.checkerColor, n.checkerColor);
            EXPECT_EQ(m.checkerSize, n.checkerSize);
            EXPECT_EQ(m.checkerOrigin, n.checkerOrigin);
            EXPECT_EQ(m.absorption, n.absorption);
            std::string what = "object " + std::to_string(i);
            std::visit(
                [&](const auto& s) {
                    using T = std::decay_t<decltype(s)>;
                    const T& t = std::get<T>(y.shape);
                    if constexpr (std::is_same_v<T, Sphere>) {
                        EXPECT_EQ(s.center, t.center);
                        EXPECT_EQ(s.radius, t.radius);
                    } else if constexpr (std::is_same_v<T, Cylinder>) {
                        EXPECT_EQ(s.base, t.base);
                        expectClose(s.axis, t.axis, what);
                        EXPECT_EQ(s.radius, t.radius);
                        EXPECT_EQ(s.height, t.height);
                    } else if constexpr (std::is_same_v<T, Plane>) {
                        EXPECT_EQ(s.point, t.point);
                        expectClose(s.normal, t.normal, what);
                    } else if constexpr (std::is_same_v<T, Triangle>) {
                        EXPECT_EQ(s.v0, t.v0);
                        EXPECT_EQ(s.v1, t.v1);
                        EXPECT_EQ(s.v2, t.v2);
                    } else if constexpr (std::is_same_v<T, Box>) {
                        EXPECT_EQ(s.min, t.min);
                        expectClose(s.max, t.max, what);
                    } else if constexpr (std::is_same_v<T, Mesh>) {
                        ASSERT_EQ(s.triangles.size(), t.triangles.size());
                        EXPECT_EQ(s.normals.size(), t.normals.size());
                        EXPECT_EQ(s.source.has_value(), t.source.has_value()) << "a model file is written as <file>";
                        for (size_t k = 0; k < s.triangles.size(); ++k) {
                            EXPECT_EQ(s.triangles[k].v0, t.triangles[k].v0);
                            EXPECT_EQ(s.triangles[k].v1, t.triangles[k].v1);
                            EXPECT_EQ(s.triangles[k].v2, t.triangles[k].v2);
                        }
                    }
                },
                x.shape);
        }
    }
}

// A triangle or mesh is written in world space without a position, except
// with a checker anchored at its <position>: then the position is written
// and the vertices relative to it (equal within rounding).
TEST(SceneWriter, CheckerOfATriangleKeepsItsOrigin) {
    Scene a = loadSceneFromString(R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
      </camera><lights/><objects><object><position x="0.3" y="-1.7" z="2.1"/><properties><type>triangle</type>
      <vertex x="0" y="0" z="0"/><vertex x="1" y="0.1" z="0"/><vertex x="0" y="1" z="0.3"/>
      <checker_color r="0" g="0" b="1"/><checker_size>0.2</checker_size><absorption r="0.5" g="0" b="0"/>
      </properties></object></objects></scene>)",
                                  "a.xml");
    Scene b = loadSceneFromString(sceneXml(a), "b.xml");
    const Material &m = a.objects[0].material, &n = b.objects[0].material;
    EXPECT_EQ(n.checkerOrigin, glm::dvec3(0.3, -1.7, 2.1));
    EXPECT_EQ(m.checkerOrigin, n.checkerOrigin);
    EXPECT_EQ(n.checkerSize, 0.2);
    EXPECT_EQ(n.checkerColor, glm::dvec3(0, 0, 1));
    EXPECT_EQ(n.absorption, glm::dvec3(0.5, 0, 0));
    const Triangle &s = std::get<Triangle>(a.objects[0].shape), &t = std::get<Triangle>(b.objects[0].shape);
    expectClose(s.v0, t.v0, "v0");
    expectClose(s.v1, t.v1, "v1");
    expectClose(s.v2, t.v2, "v2");
}

TEST(SceneWriter, WritesAtomically) {
    fs::path dir = scratchDir("writer");
    Scene scene = loadScene(sourceDir() / "scenes" / "three_diffuse_spheres.xml");
    writeSceneFile(scene, dir / "out.xml");
    EXPECT_EQ(readText(dir / "out.xml"), sceneXml(scene));
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u) << "a temporary file was left behind";
}
}  // namespace
}  // namespace whitted::test

namespace whitted::test {
namespace {

// The progressive scheduler without a window: frames of a small budget,
// passes spread over several frames, end with the sums of render().
TEST(ViewProgressive, FramesAddUpToRender) {
    Scene scene = loadScene(sourceDir() / "scenes" / "room.xml");
    RenderSettings settings{
        .width = 96, .height = 72, .samplesPerPixel = 11};  // passes of 1 sample at the smallest budget
    RenderResult reference = renderScene(scene, settings);

    settings.bandBytes = 0;  // the window's renderer keeps the whole image
    Renderer renderer(testContext(), scene, settings);
    Progressive progressive(96, 72, 11, 1e-9);  // an impossible target: the budget falls to its minimum
    int frames = 0;
    uint64_t total = 0;
    while (!progressive.done()) {
        uint64_t recorded = 0, budget = progressive.budget();
        testContext().submitAndWait(
            [&](vk::raii::CommandBuffer& cmd) { recorded = progressive.record(renderer, cmd); });
        progressive.frameDone(1.0, recorded);
        // At most one band of 8 rows over (of one sample: at the smallest
        // budget, passes stay at one sample).
        EXPECT_LT(recorded, budget + 96 * gpu::kWorkgroupSize);
        total += recorded;
        ASSERT_LT(++frames, 1000);
    }
    EXPECT_EQ(total, 96u * 72u * 11u);
    EXPECT_GT(frames, 5 * 2) << "each pass should have taken several frames";
    EXPECT_EQ(testContext().validationMessageCount(), 0u);

    RenderResult means = renderer.readMeans();
    EXPECT_EQ(means.samplesPerPixel, 11);
    for (uint32_t layer : {gpu::kAovColor, gpu::kAovDiffuse, gpu::kAovNormal})
        for (size_t i = 0; i < reference.layers[layer].size(); ++i)
            ASSERT_NEAR(means.layers[layer][i], reference.layers[layer][i],
                        1e-5f * (1 + std::abs(reference.layers[layer][i])))
                << "layer " << layer << " value " << i;
}

// A scene replaced in a running Renderer (hot reload, the editor) may need
// shapes or glass the first scene's pipeline compiled out (specialization
// constants): the image must equal a fresh render of the new scene.
TEST(ViewProgressive, ReplacedSceneWithNewShapesRendersRight) {
    RenderSettings settings{.width = 64, .height = 48, .samplesPerPixel = 2, .auxiliary = true};
    Scene opaque = loadScene(sourceDir() / "scenes" / "three_diffuse_spheres.xml");
    Scene room = loadScene(sourceDir() / "scenes" / "room.xml");  // meshes, a cylinder, glass, a mirror
    RenderResult reference = renderScene(room, settings);

    settings.bandBytes = 0;  // the window's renderer keeps the whole image
    Renderer renderer(testContext(), opaque, settings);
    renderer.setScene(room);
    testContext().submitAndWait([&](vk::raii::CommandBuffer& cmd) {
        renderer.recordClear(cmd);
        renderer.recordTile(cmd, {.tileOrigin = glm::uvec2(0, 0), .tileSize = glm::uvec2(64, 48),
                                  .firstSample = 0, .sampleCount = 2});
    });
    EXPECT_EQ(testContext().validationMessageCount(), 0u);
    RenderResult means = renderer.readMeans();
    for (uint32_t layer : {gpu::kAovColor, gpu::kAovTransmission, gpu::kAovNormal})
        for (size_t i = 0; i < reference.layers[layer].size(); ++i)
            ASSERT_NEAR(means.layers[layer][i], reference.layers[layer][i], 1e-5f * (1 + std::abs(reference.layers[layer][i])))
                << "layer " << layer << " value " << i;
}

}  // namespace
}  // namespace whitted::test

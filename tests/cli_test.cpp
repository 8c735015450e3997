// The `whitted` executable as a user runs it: exit statuses, messages, the
// files it writes and the files it must not create or clobber.
#include "gltf_documents.h"
#include "test_support.h"

#include "output/aov_output.h"
#include "io/image_io.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

// Runs the executable with `args` in folder `cwd`, after shell variable
// assignments `environment` ("NAME=value ", or nothing).
CommandRun runWhitted(const std::string& args, const fs::path& cwd = fs::current_path(),
                      const std::string& environment = "") {
    return runCommand(environment + "'" WHITTED_EXECUTABLE "' " + args, cwd);
}

// A fresh, empty folder for one test.
fs::path scratchDir(const std::string& name) { return freshOutputDir("cli", name); }

std::string scene(const std::string& name) { return (sourceDir() / "scenes" / name).string(); }

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(Cli, VersionAndHelp) {
    CommandRun version = runWhitted("--version");
    EXPECT_EQ(version.status, 0);
    EXPECT_NE(version.output.find("whitted " WHITTED_VERSION), std::string::npos);
    CommandRun help = runWhitted("render --help");
    EXPECT_EQ(help.status, 0);
    EXPECT_NE(help.output.find("--max-depth"), std::string::npos);
}

TEST(Cli, UnknownOptionIsBadInput) {
    CommandRun r = runWhitted("render " + scene("room.xml") + " --no-such-option");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("--no-such-option"), std::string::npos);
}

// --aa-threshold is a finite number in [0, 1]: NaN, which compares false
// with both ends of a range, would turn refinement off without a word.
TEST(Cli, AaThresholdMustBeFiniteAndInRange) {
    fs::path dir = scratchDir("aa_threshold");
    std::string base = "render " + scene("room.xml") + " -o out.png --width 8 --height 6 --aa-threshold ";
    CommandRun r = runWhitted(base + "nan", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.output, "--aa-threshold: must be a finite number, got nan\nRun with --help for more information.\n");
    r = runWhitted(base + "inf", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.output, "--aa-threshold: must be a finite number, got inf\nRun with --help for more information.\n");
    r = runWhitted(base + "-1", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.output,
              "--aa-threshold: Value -1 not in range 0.000000 to 1.000000\nRun with --help for more information.\n");
    EXPECT_FALSE(fs::exists(dir / "out.png"));
}

TEST(Cli, RenderWritesMainAndAuxiliaryImages) {
    fs::path dir = scratchDir("render_o");
    CommandRun r = runWhitted("render " + scene("three_diffuse_spheres.xml") + " -o out.png --width 40 --height 30 --validate",
                       dir);
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* name : {"out.png", "out.ambient.png", "out.diffuse.png", "out.specular.png", "out.reflection.png",
                             "out.transmission.png", "out.reflection_coef.png", "out.transmission_coef.png",
                             "out.ior.png", "out.depth.png", "out.normal.png"})
        EXPECT_TRUE(fs::exists(dir / name)) << name;
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << entry.path();
}

// A model whose degenerate triangles lie in several nodes: one warning line
// with the totals; -v adds each node's line under it, indented; the render
// record keeps both either way.
TEST(Cli, DegenerateTrianglesOfSeveralNodesAreOneWarningLine) {
    fs::path dir = scratchDir("degenerate_summary");
    writeJson(dir / "flat.gltf", flattenedNodesDocument());
    auto warningLines = [](const std::string& output) {
        std::vector<std::string> lines;
        std::istringstream in(output);
        for (std::string line; std::getline(in, line);)
            if (line.starts_with("warning: ") || line.starts_with("  ")) lines.push_back(line);
        return lines;
    };
    const std::string summary = "flat.gltf: 4 degenerate triangles skipped in 2 nodes";
    const std::vector<std::string> details = {"flat.gltf: node \"node 0\": 2 degenerate triangles skipped",
                                              "flat.gltf: node \"flat\": 2 degenerate triangles skipped"};
    const std::string args = "render flat.gltf -o out.png --width 16 --height 12 --aov none -q";
    CommandRun r = runWhitted(args, dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(warningLines(r.output), std::vector<std::string>{"warning: " + summary}) << r.output;
    Json record = Json::parse(readText(dir / "out.json"));
    EXPECT_EQ(record["warnings"], Json::array({summary}));
    EXPECT_EQ(record["warning_details"], Json(details));

    r = runWhitted(args + " -v", dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(warningLines(r.output),
              (std::vector<std::string>{"warning: " + summary, "  " + details[0], "  " + details[1]}))
        << r.output;
}

TEST(Cli, AovListSelectsImagesAndExrIsFloat) {
    fs::path dir = scratchDir("render_exr");
    CommandRun r = runWhitted("render " + scene("three_diffuse_spheres.xml") +
                           " -o out.exr --width 20 --height 15 --aov depth,kt --validate", dir);
    EXPECT_EQ(r.status, 2) << "kt is not an auxiliary image name";
    EXPECT_NE(r.output.find("unknown auxiliary image 'kt'"), std::string::npos) << r.output;
    r = runWhitted("render " + scene("three_diffuse_spheres.xml") +
                       " -o out.exr --width 20 --height 15 --aov depth,transmission_coef --validate", dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out.exr"));
    EXPECT_TRUE(fs::exists(dir / "out.depth.exr"));
    EXPECT_TRUE(fs::exists(dir / "out.transmission_coef.exr"));
    EXPECT_FALSE(fs::exists(dir / "out.normal.exr"));
}

TEST(Cli, DefaultOutputIsANewHistoryFolder) {
    fs::path dir = scratchDir("history");
    CommandRun r = runWhitted("render " + scene("three_diffuse_spheres.xml") + " --width 20 --height 15 --spp 1 --aov none --validate",
                       dir);
    ASSERT_EQ(r.status, 0) << r.output;
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(dir / "renders")) entries.push_back(e.path());
    ASSERT_EQ(entries.size(), 1u);
    EXPECT_TRUE(fs::exists(entries[0] / "image.png"));
    EXPECT_TRUE(fs::exists(entries[0] / "scene.xml"));
    std::ifstream json(entries[0] / "render.json");
    std::stringstream text;
    text << json.rdbuf();
    EXPECT_NE(text.str().find("\"primary\": 300"), std::string::npos) << text.str();
    EXPECT_NE(text.str().find("\"spp\": 1"), std::string::npos);
}

// A bad scene gives FILE:LINE and exit status 2, and touches no output.
TEST(Cli, BadSceneIsRefusedWithoutTouchingTheOutput) {
    fs::path dir = scratchDir("bad_scene");
    std::ofstream(dir / "bad.xml") << "<scene>\n  <camera>\n    <position x=\"0\" y=\"0\" z=\"0\"/>\n  </camera>\n</scene>\n";
    std::ofstream(dir / "existing.png") << "previous contents";
    CommandRun r = runWhitted("render bad.xml -o existing.png", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("bad.xml:2:"), std::string::npos) << r.output;
    std::ifstream existing(dir / "existing.png");
    std::string contents((std::istreambuf_iterator<char>(existing)), {});
    EXPECT_EQ(contents, "previous contents");

    r = runWhitted("render bad.xml -o fresh.png", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_FALSE(fs::exists(dir / "fresh.png"));
    EXPECT_FALSE(fs::exists(dir / "fresh.ambient.png"));
}

TEST(Cli, MissingSceneFileIsBadInput) {
    CommandRun r = runWhitted("render /nonexistent/scene.xml -o /tmp/never.png");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("/nonexistent/scene.xml"), std::string::npos) << r.output;
}

TEST(Cli, UnwritableOutputIsRefusedBeforeRendering) {
    CommandRun r = runWhitted("render " + scene("room.xml") + " -o /nonexistent/folder/out.png");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("output folder /nonexistent/folder does not exist"), std::string::npos) << r.output;
    r = runWhitted("render " + scene("room.xml") + " -o out.unknownformat");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("cannot write images of type '.unknownformat'"), std::string::npos) << r.output;
}

TEST(Cli, DeviceIsChosenByNameOrRefusedClearly) {
    fs::path dir = scratchDir("device");
    CommandRun r = runWhitted("render " + scene("three_diffuse_spheres.xml") +
                                  " -o out.png --width 8 --height 6 --aov none --device 0", dir);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("whitted: device "), std::string::npos) << "prints which device it uses";
    r = runWhitted("render " + scene("three_diffuse_spheres.xml") + " -o out2.png --device no-such-gpu", dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("no Vulkan device matches 'no-such-gpu' (run `whitted devices` to list them)"),
              std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out2.png"));
}

// An ordinary Full HD render with every auxiliary image: its layers need
// 284 MiB, more than lavapipe's 128 MiB storage buffer limit, and render in
// bands streamed into the files.
TEST(Cli, FullHdWithEveryAuxiliaryImageRenders) {
    fs::path dir = scratchDir("full_hd");
    CommandRun r = runWhitted("render " + scene("room.xml") +
                                  " -o out.png --width 1920 --height 1080 --aa uniform --spp 1 --aov all --validate",
                              dir);
    ASSERT_EQ(r.status, 0) << r.output;
    for (const AovInfo& aov : allAovs()) {
        int w = 0, h = 0, c = 0;
        std::vector<float> pixels;
        readImageInto(aovPath(dir / "out.png", aov.name), w, h, c, pixels);
        EXPECT_EQ(w, 1920) << aov.name;
        EXPECT_EQ(h, 1080) << aov.name;
    }
    std::string record = readText(dir / "out.json");
    EXPECT_NE(record.find("\"primary\": 2073600"), std::string::npos) << record;
    EXPECT_EQ(record.find("\"bands\": 1,"), std::string::npos) << "rendered in more than one band: " << record;
}

#if defined(__SANITIZE_ADDRESS__)
#define WHITTED_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WHITTED_TEST_ASAN 1
#endif
#endif

// A tall image streams: memory does not grow with the image. 256 x 16384
// pixels with every auxiliary layer hold 576 MiB of layers, 432 MiB more than
// 256 x 4096; the process's peak memory may grow by a small part of that.
// Under AddressSanitizer, freed memory waits in a quarantine of up to 256 MiB
// that fills at a pace set by thread timing: with another test running
// beside it, the same pair of renders grew by 9 to 78 MiB (and by 0 to 10 MiB
// with a 16 MiB quarantine; 5 to 7 MiB unsanitized). So the sanitized
// build's child runs with a 16 MiB quarantine and the peak measures whitted.
TEST(Cli, TallImageStreamsWithBoundedMemory) {
    fs::path dir = scratchDir("tall");
#ifdef WHITTED_TEST_ASAN
    const std::string environment = "ASAN_OPTIONS=\"${ASAN_OPTIONS}:quarantine_size_mb=16\" ";
#else
    const std::string environment;
#endif
    auto peakFor = [&](int height) {
        std::string name = "out" + std::to_string(height);
        CommandRun r = runWhitted("render " + scene("three_diffuse_spheres.xml") + " -o " + name +
                                      ".exr --width 256 --height " + std::to_string(height) +
                                      " --aa uniform --spp 1 --aov all",
                                  dir, environment);
        EXPECT_EQ(r.status, 0) << r.output;
        std::string record = readText(dir / (name + ".json"));
        size_t at = record.find("\"peak_rss\": ");
        EXPECT_NE(at, std::string::npos) << record;
        int w = 0, h = 0, c = 0;
        std::vector<float> pixels;
        readImageInto(dir / (name + ".depth.exr"), w, h, c, pixels);
        EXPECT_EQ(h, height);
        return at == std::string::npos ? 0 : int64_t(std::stoull(record.substr(at + 12)));
    };
    int64_t small = peakFor(4096), tall = peakFor(16384);
    int64_t layerGrowth = int64_t(256) * (16384 - 4096) * gpu::kAovCount * 16;
    EXPECT_LT(tall - small, layerGrowth / 8)
        << "peak memory " << (small >> 20) << " MiB at 4096 rows, " << (tall >> 20) << " MiB at 16384 rows";
}

// --region: the crop of the full render, bit for bit, in PNG (region-sized)
// and EXR (full display window, the region as data window), auxiliary
// images included.
TEST(Cli, RegionIsTheCropOfTheFullRender) {
    fs::path dir = scratchDir("region");
    for (std::string ext : {".png", ".exr"}) {
        std::string opts = " --width 96 --height 72 --spp 4 --aov diffuse,depth,samples";
        CommandRun full = runWhitted("render " + scene("room.xml") + " -o full" + ext + opts, dir);
        ASSERT_EQ(full.status, 0) << full.output;
        CommandRun part = runWhitted("render " + scene("room.xml") + " -o part" + ext + opts + " --region 20,10,61,50", dir);
        ASSERT_EQ(part.status, 0) << part.output;
        for (std::string layer : {"", ".diffuse", ".samples", ".depth"}) {
            if (ext == ".png" && layer == ".depth") continue;  // 8-bit depth is scaled by the image's own median
            int fw = 0, fh = 0, fc = 0, pw = 0, ph = 0, pc = 0;
            std::vector<float> a, b;
            readImageInto(dir / ("full" + layer + ext), fw, fh, fc, a);
            readImageInto(dir / ("part" + layer + ext), pw, ph, pc, b);
            ASSERT_EQ(pw, 41) << layer << ext;
            ASSERT_EQ(ph, 40) << layer << ext;
            for (int y = 0; y < 40; ++y)
                for (int x = 0; x < 41; ++x)
                    for (int c = 0; c < fc; ++c)
                        ASSERT_EQ(a[(size_t(y + 10) * 96 + x + 20) * fc + c], b[(size_t(y) * 41 + x) * pc + c])
                            << layer << ext << " at " << x << "," << y;
        }
    }
    // The EXR keeps where the region sits in the full image.
    std::string info = runCommand("oiiotool --info -v part.exr", dir).output;
    EXPECT_NE(info.find("pixel data origin: x=20, y=10"), std::string::npos) << info;
    EXPECT_NE(info.find("full/display size: 96 x 72"), std::string::npos) << info;
}

TEST(Cli, BadRegionIsRefused) {
    fs::path dir = scratchDir("bad_region");
    std::string base = "render " + scene("room.xml") + " -o out.png --width 64 --height 48 --region ";
    CommandRun r = runWhitted(base + "10,10,10,20", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("whitted: --region: region 10,10,10,20 is empty or outside the 64x48 image"),
              std::string::npos) << r.output;
    r = runWhitted(base + "0,0,65,48", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("is empty or outside the 64x48 image"), std::string::npos) << r.output;
    r = runWhitted(base + "1,2,3", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("whitted: --region: expected X0,Y0,X1,Y1 (four integers), got '1,2,3'"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir / "out.png"));
}

// --device with the same device named twice shares the bands of one render
// between two contexts: the files are those of one device, bit for bit.
TEST(Cli, TwoDevicesShareTheBandsOfOneRender) {
    fs::path dir = scratchDir("two_devices");
    std::string opts = " --width 256 --height 4096 --spp 4 --aov all --validate";
    CommandRun one = runWhitted("render " + scene("room.xml") + " -o one.exr" + opts + " --device 0", dir);
    ASSERT_EQ(one.status, 0) << one.output;
    CommandRun two = runWhitted("render " + scene("room.xml") + " -o two.exr" + opts + " --device 0,0", dir);
    ASSERT_EQ(two.status, 0) << two.output;
    std::string record = readText(dir / "two.json");
    EXPECT_NE(record.find("\"devices\": 2"), std::string::npos) << record;
    EXPECT_EQ(record.find("\"bands\": 1,"), std::string::npos) << "more than one band to share: " << record;
    for (std::string layer : {"", ".diffuse", ".normal", ".samples", ".depth"}) {
        int w = 0, h = 0, c = 0;
        std::vector<float> a, b;
        readImageInto(dir / ("one" + layer + ".exr"), w, h, c, a);
        readImageInto(dir / ("two" + layer + ".exr"), w, h, c, b);
        ASSERT_EQ(a, b) << layer;
    }
    CommandRun all = runWhitted("render " + scene("three_diffuse_spheres.xml") + " -o all.png --width 64 --height 48 "
                                "--device all", dir);
    EXPECT_EQ(all.status, 0) << all.output;
}

TEST(Cli, DevicesListsLavapipeOrAGpu) {
    CommandRun r = runWhitted("devices");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.output.find("0: "), std::string::npos) << r.output;
}

// Ctrl+C during a render: whitted stops at its next submission, removes the
// image it was writing and exits 130; the same for SIGTERM. The signal is
// sent once the image's temporary file exists, that is while the render of
// a long one-band image runs, whenever that happens.
TEST(Cli, InterruptedRenderWritesNothingAndExits130) {
    for (int signal : {SIGINT, SIGTERM}) {
        fs::path dir = scratchDir("interrupted_" + std::to_string(signal));
        fs::path log = dir.parent_path() / ("interrupted_" + std::to_string(signal) + ".log");
        std::vector<std::string> args = {WHITTED_EXECUTABLE, "render", scene("three_diffuse_spheres.xml"),
                                         "-o", (dir / "x.png").string(), "--width", "320", "--height", "240",
                                         "--aa", "uniform", "--spp", "1024"};
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        pid_t pid = 0;
        ASSERT_EQ(posix_spawn(&pid, WHITTED_EXECUTABLE, &actions, nullptr, argv.data(), environ), 0);
        posix_spawn_file_actions_destroy(&actions);

        auto writing = [&] {
            for (const fs::directory_entry& e : fs::directory_iterator(dir))
                if (e.path().filename().string().find(".partial") != std::string::npos) return true;
            return false;
        };
        int status = 0;
        bool exited = false;
        while (!writing()) {
            ASSERT_EQ(waitpid(pid, &status, WNOHANG), 0) << "whitted ended before it began writing: " << readText(log);
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        ASSERT_EQ(::kill(pid, signal), 0);
        exited = waitpid(pid, &status, 0) == pid;
        ASSERT_TRUE(exited);
        ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
        EXPECT_EQ(WEXITSTATUS(status), 130);
        EXPECT_NE(readText(log).find("whitted: interrupted; nothing written"), std::string::npos) << readText(log);
        EXPECT_TRUE(fs::is_empty(dir)) << fs::directory_iterator(dir)->path();
    }
}

}  // namespace
}  // namespace whitted::test

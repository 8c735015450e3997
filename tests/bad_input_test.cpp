// Bad input, end to end: the real `whitted` executable run on every file of
// the bad-input catalogue (tests/bad_scenes/, messages in its expected.txt)
// and on the degenerate but legal scenes (tests/legal_scenes/).
//
// * BadInput/BadSceneTest.*: refused. Exit status 2, the exact "FILE:LINE: message" on
//   stderr, and the output untouched: `-o` naming a file that does not exist
//   creates nothing, `-o` naming an existing file leaves it as it was, and no
//   *.partial* file is left behind.
// * DegenerateButLegal/LegalSceneTest.*: accepted. Exit status 0, an image, and the exact warnings.
#include "gltf_documents.h"
#include "test_support.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

fs::path badScenesDir() { return sourceDir() / "tests" / "bad_scenes"; }
fs::path legalScenesDir() { return sourceDir() / "tests" / "legal_scenes"; }

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> linesOf(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

struct ProcessResult {
    int status;  // exit status, or -1 if the process did not exit normally
    std::string out, err;
};

fs::path stdoutFile(const fs::path& cwd) { return cwd.parent_path() / (cwd.filename().string() + ".stdout"); }
fs::path stderrFile(const fs::path& cwd) { return cwd.parent_path() / (cwd.filename().string() + ".stderr"); }

// Starts the executable with `args` in folder `cwd`, no shell involved. Its
// stdout and stderr go to files beside `cwd`, not in it, so that `cwd` holds
// only what the executable wrote. Returns the process id, or -1.
pid_t startWhitted(const std::vector<std::string>& args, const fs::path& cwd) {
    std::vector<std::string> argStrings{WHITTED_EXECUTABLE};
    argStrings.insert(argStrings.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argStrings) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string dir = cwd.string(), out = stdoutFile(cwd).string(), err = stderrFile(cwd).string();

    pid_t pid = ::fork();
    if (pid == 0) {  // only async-signal-safe calls until exec
        int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::chdir(dir.c_str()) != 0) ::_exit(127);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    return pid;
}

// Waits for a process startWhitted() started in `cwd`.
ProcessResult finishWhitted(pid_t pid, const fs::path& cwd) {
    int status = 0;
    if (pid < 0 || ::waitpid(pid, &status, 0) != pid) return {-1, "", "fork or waitpid failed"};
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(stdoutFile(cwd)), readFile(stderrFile(cwd))};
}

ProcessResult runWhitted(const std::vector<std::string>& args, const fs::path& cwd) {
    return finishWhitted(startWhitted(args, cwd), cwd);
}

// A fresh, empty folder.
fs::path freshDir(const fs::path& dir) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Everything under `dir`, as paths relative to it.
std::set<std::string> contentsOf(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        names.insert(fs::relative(entry.path(), dir).string());
    return names;
}

std::set<std::string> partialFilesUnder(const fs::path& dir) {
    std::set<std::string> partial;
    for (const std::string& name : contentsOf(dir))
        if (name.find(".partial") != std::string::npos) partial.insert(name);
    return partial;
}

bool hasLine(const std::string& text, const std::string& line) {
    std::vector<std::string> lines = linesOf(text);
    return std::find(lines.begin(), lines.end(), line) != lines.end();
}

// ---- The catalogue -------------------------------------------------------------------

struct BadCase {
    std::string file;      // name in tests/bad_scenes/, or of a generated case
    std::string expected;  // the stderr line, with FILE for the path given
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.file; }

// tests/bad_scenes/expected.txt: FILENAME<TAB>MESSAGE lines; # comments.
std::vector<BadCase> manifest() {
    std::vector<BadCase> cases;
    for (const std::string& line : linesOf(readFile(badScenesDir() / "expected.txt"))) {
        if (line.empty() || line[0] == '#') continue;
        size_t tab = line.find('\t');
        if (tab == std::string::npos) throw std::runtime_error("expected.txt: no tab in \"" + line + "\"");
        cases.push_back({line.substr(0, tab), line.substr(tab + 1)});
    }
    return cases;
}

// The square's .glb cut at the `index`th place of glbCuts().
void writeGlbCut(const fs::path& path, size_t index) {
    const std::vector<unsigned char> glb = glbBytes(squareDocument(false), squareBytes());
    writeBytes(path, glbCutAt(glb, glbCuts(glb).at(index)));
}

// A one-triangle OBJ using material "red" of the MTL library `mtl`, written beside it.
void writeObjWithMtl(const fs::path& path, const std::string& mtl) {
    const std::string library = path.stem().string() + ".mtl";
    std::ofstream(path.parent_path() / library) << mtl;
    std::ofstream(path) << "mtllib " << library << "\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
}

// The cases the manifest names that are made here rather than committed. Each
// writes its input at `path`.
const std::map<std::string, void (*)(const fs::path&)>& generatedCases() {
    static const std::map<std::string, void (*)(const fs::path&)> cases = {
        // 10^6 nested elements (7 MB): the XML parser must stop at its depth
        // limit rather than recurse a million times.
        {"million_deep_nesting.xml",
         [](const fs::path& path) {
             constexpr int kDepth = 1000000;
             std::string xml = "<!-- case: a million nested elements -->\n<scene>";
             xml.reserve(xml.size() + size_t(kDepth) * 7 + 16);
             for (int i = 0; i < kDepth; ++i) xml += "<a>";
             for (int i = 0; i < kDepth; ++i) xml += "</a>";
             xml += "</scene>\n";
             std::ofstream(path, std::ios::binary) << xml;
         }},
        {"nonexistent.xml", [](const fs::path&) {}},
        {"directory.xml", [](const fs::path& path) { fs::create_directories(path); }},
        // Model files given where a scene goes, each wrong in one way (the
        // readers' rules: scenes/README.md "glTF 2.0", "OBJ/MTL", "Limits").
        {"gltf_chain_5000.gltf", [](const fs::path& path) { writeJson(path, chain(5000)); }},
        {"gltf_chain_200000.gltf", [](const fs::path& path) { writeJson(path, chain(200000)); }},
        {"gltf_not_json.gltf", [](const fs::path& path) { std::ofstream(path) << "{\"asset\": {\"version\": \"2.0\"},"; }},
        {"gltf_version_1.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["asset"]["version"] = "1.0";
             writeJson(path, j);
         }},
        {"gltf_znear_negative.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["cameras"] = Json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", -1}}}}});
             writeJson(path, j);
         }},
        {"gltf_signed_indices.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["accessors"][1]["componentType"] = 5122;  // SHORT
             writeJson(path, j);
         }},
        {"gltf_float_indices.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["accessors"][1]["componentType"] = 5126;
             j["accessors"][1]["count"] = 3;
             writeJson(path, j);
         }},
        {"gltf_index_out_of_range.gltf",
         [](const fs::path& path) {
             std::vector<unsigned char> bytes = squareBytes();
             bytes[48 + 2 * 5] = 9;  // the sixth index names vertex 9 of 4
             writeJson(path, squareDocument(true, bytes));
         }},
        {"gltf_nan_position.gltf",
         [](const fs::path& path) {
             std::vector<unsigned char> bytes = squareBytes();
             const float nan = std::numeric_limits<float>::quiet_NaN();
             std::memcpy(bytes.data() + 4, &nan, 4);
             writeJson(path, squareDocument(true, bytes));
         }},
        {"gltf_huge_count.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["accessors"][0].erase("bufferView");
             j["accessors"][0]["count"] = 1000000000;
             writeJson(path, j);
         }},
        {"gltf_count_beyond_view.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["accessors"][0]["count"] = 400000000;
             writeJson(path, j);
         }},
        {"gltf_no_byte_length.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["buffers"][0].erase("byteLength");
             writeJson(path, j);
         }},
        {"gltf_short_stride.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["bufferViews"][0]["byteStride"] = 8;
             writeJson(path, j);
         }},
        {"gltf_duplicate_roots.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["scenes"] = Json::array({{{"nodes", {0, 0}}}});
             writeJson(path, j);
         }},
        {"gltf_cycle.gltf",
         [](const fs::path& path) {
             Json j = squareDocument();
             j["nodes"] = Json::array({{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}});
             j["scenes"] = Json::array({{{"nodes", {0}}}});
             writeJson(path, j);
         }},
        {"gltf_missing_buffer_file.gltf",
         [](const fs::path& path) {
             Json j = squareDocument(false);
             j["buffers"][0]["uri"] = "missing.bin";
             writeJson(path, j);
         }},
        {"glb_header_longer.glb",
         [](const fs::path& path) {
             std::vector<unsigned char> glb = glbBytes(squareDocument(false), squareBytes());
             const uint32_t claimed = uint32_t(glb.size() + 1000);
             std::memcpy(glb.data() + 8, &claimed, 4);
             writeBytes(path, glb);
         }},
        // The square's .glb cut at each chunk boundary and inside each chunk.
        {"glb_cut_0.glb", [](const fs::path& path) { writeGlbCut(path, 0); }},
        {"glb_cut_1.glb", [](const fs::path& path) { writeGlbCut(path, 1); }},
        {"glb_cut_2.glb", [](const fs::path& path) { writeGlbCut(path, 2); }},
        {"glb_cut_3.glb", [](const fs::path& path) { writeGlbCut(path, 3); }},
        {"glb_cut_4.glb", [](const fs::path& path) { writeGlbCut(path, 4); }},
        {"glb_cut_5.glb", [](const fs::path& path) { writeGlbCut(path, 5); }},
        {"glb_cut_6.glb", [](const fs::path& path) { writeGlbCut(path, 6); }},
        {"glb_cut_7.glb", [](const fs::path& path) { writeGlbCut(path, 7); }},
        {"obj_face_out_of_range.obj",
         [](const fs::path& path) { std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"; }},
        {"obj_nan_vertex.obj",
         [](const fs::path& path) { std::ofstream(path) << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"; }},
        {"obj_huge_vertex.obj",
         [](const fs::path& path) { std::ofstream(path) << "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n"; }},
        {"obj_all_degenerate.obj",
         [](const fs::path& path) { std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"; }},
        {"obj_empty.obj", [](const fs::path& path) { std::ofstream(path) << "# nothing\n"; }},
        {"mtl_bad_colour.obj", [](const fs::path& path) { writeObjWithMtl(path, "newmtl red\nKd 1 x 0\n"); }},
        {"mtl_colour_out_of_range.obj",
         [](const fs::path& path) { writeObjWithMtl(path, "newmtl red\nKd 1 0 -3\n"); }},
        {"mtl_specular_above_one.obj",
         [](const fs::path& path) { writeObjWithMtl(path, "newmtl red\nKs 0.9 0.9 8.9\nillum 3\n"); }},
        {"mtl_glass_index_too_small.obj",
         [](const fs::path& path) { writeObjWithMtl(path, "newmtl red\nNi 0.01\nillum 6\n"); }},
        {"mtl_bad_illum.obj", [](const fs::path& path) { writeObjWithMtl(path, "newmtl red\nillum 99\n"); }},
        {"mtl_missing_texture.obj",
         [](const fs::path& path) { writeObjWithMtl(path, "newmtl red\nmap_Kd no_such_texture.png\n"); }},
    };
    return cases;
}

// Test names may hold letters, digits and underscores only.
std::string testName(const std::string& file) {
    std::string name = fs::path(file).stem().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

class BadSceneTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadSceneTest, IsRefusedWithoutTouchingTheOutput) {
    const BadCase& c = GetParam();
    const fs::path root = outputDir() / "bad_input" / testName(c.file);
    freshDir(root);

    fs::path scene = badScenesDir() / c.file;
    if (auto generated = generatedCases().find(c.file); generated != generatedCases().end()) {
        scene = freshDir(root / "input") / c.file;
        generated->second(scene);
    }
    std::string expected = c.expected;
    ASSERT_TRUE(expected.starts_with("FILE") || expected.starts_with("DIR/"))
        << "expected.txt: the message must start with FILE or DIR/";
    if (expected.starts_with("FILE")) expected.replace(0, 4, scene.string());
    // DIR/: the scene's folder (a model file's MTL library and textures).
    for (size_t at; (at = expected.find("DIR/")) != std::string::npos;)
        expected.replace(at, 3, scene.parent_path().string());

    // Two runs, side by side: (a) -o names a file that does not exist,
    // (b) -o names an existing file.
    const fs::path fresh = freshDir(root / "fresh");
    const fs::path existing = freshDir(root / "existing");
    const std::string previous = "previous contents, not a PNG\n";
    std::ofstream(existing / "out.png", std::ios::binary) << previous;
    pid_t pa = startWhitted({"render", scene.string(), "-o", "out.png"}, fresh);
    pid_t pb = startWhitted({"render", scene.string(), "-o", "out.png"}, existing);
    ProcessResult a = finishWhitted(pa, fresh);
    ProcessResult b = finishWhitted(pb, existing);

    // (a) Nothing is created.
    EXPECT_EQ(a.status, 2) << a.err;
    EXPECT_TRUE(hasLine(a.err, expected)) << "expected on stderr:\n  " << expected << "\ngot:\n" << a.err;
    EXPECT_EQ(a.out, "");
    EXPECT_EQ(contentsOf(fresh), std::set<std::string>{}) << "a refused render created files";

    // (b) The existing file keeps its contents.
    EXPECT_EQ(b.status, 2) << b.err;
    EXPECT_TRUE(hasLine(b.err, expected)) << "expected on stderr:\n  " << expected << "\ngot:\n" << b.err;
    EXPECT_EQ(readFile(existing / "out.png"), previous) << "a refused render clobbered its output";
    EXPECT_EQ(contentsOf(existing), std::set<std::string>{"out.png"});

    EXPECT_EQ(partialFilesUnder(root), std::set<std::string>{});
    if (!generatedCases().contains(c.file)) {
        EXPECT_EQ(partialFilesUnder(badScenesDir()), std::set<std::string>{});
    }
}

INSTANTIATE_TEST_SUITE_P(BadInput, BadSceneTest, ::testing::ValuesIn(manifest()),
                         [](const auto& info) { return testName(info.param.file); });

// The manifest and the folder agree, every case says what it is, and the
// catalogue stays at least 30 cases strong.
TEST(BadSceneCatalogue, ManifestMatchesTheFiles) {
    std::vector<BadCase> cases = manifest();
    EXPECT_GE(cases.size(), 30u);
    std::set<std::string> listed;
    for (const BadCase& c : cases) {
        EXPECT_TRUE(listed.insert(c.file).second) << c.file << " is listed twice";
        EXPECT_TRUE(fs::is_regular_file(badScenesDir() / c.file) || generatedCases().contains(c.file))
            << c.file << " is listed in expected.txt but is neither in tests/bad_scenes/ nor generated";
        EXPECT_FALSE(fs::exists(badScenesDir() / c.file) && generatedCases().contains(c.file)) << c.file;
    }
    for (const auto& entry : fs::directory_iterator(badScenesDir())) {
        std::string name = entry.path().filename().string();
        if (name == "expected.txt") continue;
        EXPECT_TRUE(listed.contains(name)) << name << " has no line in expected.txt";
        // Its first bytes state the case; the empty file, the one of only
        // whitespace and the UTF-16 one cannot.
        if (name == "empty.xml" || name == "whitespace_only.xml" || name == "utf16.xml") continue;
        std::string text = readFile(entry.path());
        if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
        EXPECT_TRUE(text.starts_with("<!-- case: ")) << name << " does not start with <!-- case: ... -->";
    }
}

// ---- Degenerate but legal ------------------------------------------------------------

struct LegalCase {
    std::string file;                   // in tests/legal_scenes/
    std::vector<std::string> warnings;  // stderr "warning: " lines, FILE for the path
};

void PrintTo(const LegalCase& c, std::ostream* os) { *os << c.file; }

class LegalSceneTest : public ::testing::TestWithParam<LegalCase> {};

TEST_P(LegalSceneTest, RendersWithAWarning) {
    const LegalCase& c = GetParam();
    const fs::path scene = legalScenesDir() / c.file;
    const fs::path dir = freshDir(outputDir() / "legal_input" / testName(c.file));
    ProcessResult r = runWhitted({"render", scene.string(), "-o", "out.png", "--width", "16", "--height", "12", "--aov", "none",
                        "-q"},
                       dir);
    ASSERT_EQ(r.status, 0) << r.err;
    std::vector<std::string> warnings;
    for (const std::string& line : linesOf(r.err))
        if (line.starts_with("warning: ")) warnings.push_back(line);
    std::vector<std::string> expected;
    for (std::string w : c.warnings) expected.push_back("warning: " + w.replace(0, 4, scene.string()));
    EXPECT_EQ(warnings, expected) << r.err;
    EXPECT_EQ(contentsOf(dir), (std::set<std::string>{"out.json", "out.png"}));  // the image and its record
}

INSTANTIATE_TEST_SUITE_P(
    DegenerateButLegal, LegalSceneTest,
    ::testing::Values(
        LegalCase{"no_lights.xml", {"FILE:7: scene has no lights; only ambient light will show"}},
        LegalCase{"no_objects.xml", {"FILE:13: scene has no objects; the image will be black"}},
        LegalCase{"empty_scene.xml",
                   {"FILE:7: scene has no lights; only ambient light will show",
                    "FILE:8: scene has no objects; the image will be black"}},
        LegalCase{"degenerate_polygon_in_mesh.xml", {"FILE:24: degenerate polygon skipped"}},
        LegalCase{"degenerate_triangles_in_mesh_file.xml",
                  {"FILE:19: mesh file \"../meshes/one_degenerate.obj\": 2 degenerate triangles skipped"}}),
    [](const auto& info) { return testName(info.param.file); });

TEST(LegalSceneCatalogue, EveryFileIsTested) {
    std::set<std::string> files;
    for (const auto& entry : fs::directory_iterator(legalScenesDir())) files.insert(entry.path().filename().string());
    EXPECT_EQ(files, (std::set<std::string>{"no_lights.xml", "no_objects.xml", "empty_scene.xml",
                                            "degenerate_polygon_in_mesh.xml", "degenerate_triangles_in_mesh_file.xml"}));
}

}  // namespace
}  // namespace whitted::test

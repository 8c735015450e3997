// `whitted convert INPUT -o OUT.xml`: the converted scene renders the same
// image, bit for bit, as the input does, for every kind of input (a list:
// each new importer's files join it); bad input writes nothing.
#include "test_support.h"

#include "io/image_io.h"

#include <cstring>

#include <fstream>
#include <iterator>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

CommandRun whitted(const std::string& args, const fs::path& cwd) {
    return runCommand("'" WHITTED_EXECUTABLE "' " + args, cwd);
}

std::string bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<float> pixels(const fs::path& path) {
    std::vector<float> storage;
    int w = 0, h = 0, c = 0;
    readImageInto(path, w, h, c, storage);
    return storage;
}

// Every input kind the renderer takes: scene files (textures, csg, mirrors,
// glass) and model files through their quick look (OBJ, PLY, glTF with a
// texture of its own).
std::vector<fs::path> inputs() {
    const fs::path scenes = sourceDir() / "scenes", meshes = sourceDir() / "tests" / "meshes";
    return {scenes / "showcase.xml", scenes / "several_mirrors.xml", meshes / "pyramid.obj",
            meshes / "uv_sphere_12x24.obj", meshes / "pyramid.ply",
            assimpTestModel("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb")};
}

TEST(Convert, ConvertedSceneRendersBitIdentically) {
    fs::path dir = freshOutputDir("convert", "identical");
    int n = 0;
    for (const fs::path& input : inputs()) {
        ASSERT_TRUE(fs::exists(input)) << input << " (assimp-testmodels: tools/install_deps.sh)";
        std::string stem = "case" + std::to_string(n++);
        fs::path xml = dir / (stem + ".xml");
        CommandRun run = whitted("convert '" + input.string() + "' -o " + xml.string(), dir);
        ASSERT_EQ(run.status, 0) << input << ": " << run.output;
        const std::string size = " --width 96 --height 72 -q --aov diffuse,object_id ";
        for (const auto& [from, out] : {std::pair{input, stem + ".in.exr"}, std::pair{xml, stem + ".out.exr"}}) {
            CommandRun r = whitted("render '" + from.string() + "'" + size + "-o " + (dir / out).string(), dir);
            ASSERT_EQ(r.status, 0) << from << ": " << r.output;
        }
        for (const char* suffix : {".exr", ".diffuse.exr", ".object_id.exr"}) {
            std::vector<float> a = pixels(dir / (stem + ".in" + suffix)), b = pixels(dir / (stem + ".out" + suffix));
            ASSERT_EQ(a.size(), b.size()) << input << suffix;
            EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << input << suffix;
        }
        // Converting the converted scene changes nothing more.
        fs::path again = dir / (stem + ".again.xml");
        ASSERT_EQ(whitted("convert " + xml.string() + " -o " + again.string(), dir).status, 0);
        EXPECT_EQ(bytes(again), bytes(xml)) << input;
    }
}

// Bad input: status 2 with the file's message; nothing is written.
TEST(Convert, BadInputWritesNothing) {
    fs::path dir = freshOutputDir("convert", "bad");
    fs::path bad = sourceDir() / "tests" / "meshes" / "garbage.ply";
    CommandRun run = whitted("convert '" + bad.string() + "' -o out.xml", dir);
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("garbage.ply"), std::string::npos) << run.output;
    CommandRun missing = whitted("convert no_such.xml -o out.xml", dir);
    EXPECT_EQ(missing.status, 2) << missing.output;
    CommandRun noFolder = whitted("convert " + (sourceDir() / "scenes" / "room.xml").string() + " -o nowhere/out.xml", dir);
    EXPECT_EQ(noFolder.status, 2) << noFolder.output;
    EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace whitted::test

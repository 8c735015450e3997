// `whitted convert INPUT -o OUT.xml`: the converted scene renders the same
// image, bit for bit, as the input does, for every kind of input (a list:
// each new importer's files join it); bad input writes nothing.
#include "test_support.h"

#include "io/image_io.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/quaternion.hpp>

#include <cmath>
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

// An authored glTF scene: a camera under a node that rotates and scales,
// the three light types, a chrome sphere instanced by two nodes, a glass
// sphere (transmission, ior, volume) under a mirroring node, and a mesh of
// two primitives (a floor and a wall) with their own materials.
fs::path writeAuthoredGltf(const fs::path& dir) {
    using Json = nlohmann::json;
    const double pi = 3.14159265358979323846;
    std::vector<float> positions, normals;
    std::vector<uint16_t> indices;
    const int stacks = 8, slices = 12;  // a UV sphere of radius 0.5 with vertex normals
    for (int i = 0; i <= stacks; ++i)
        for (int k = 0; k <= slices; ++k) {
            double theta = pi * i / stacks, phi = 2 * pi * k / slices;
            float n[3] = {float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                          float(std::sin(theta) * std::sin(phi))};
            for (float c : n) positions.push_back(0.5f * c), normals.push_back(c);
        }
    for (int i = 0; i < stacks; ++i)
        for (int k = 0; k < slices; ++k) {
            uint16_t a = uint16_t(i * (slices + 1) + k), b = uint16_t(a + slices + 1);
            for (uint16_t v : {a, uint16_t(a + 1), b, uint16_t(a + 1), uint16_t(b + 1), b}) indices.push_back(v);
        }
    const size_t sphereVertices = positions.size() / 3, sphereIndices = indices.size();
    // The floor (y = 0, 4 x 4) and a wall behind (z = -1.5), each a quad facing the camera.
    const float quads[] = {-2, 0, 2, 2, 0, 2, 2, 0, -2, -2, 0, -2, -2, 0, -1.5f, 2, 0, -1.5f, 2, 2, -1.5f, -2, 2, -1.5f};
    const float quadNormals[] = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    positions.insert(positions.end(), std::begin(quads), std::end(quads));
    normals.insert(normals.end(), std::begin(quadNormals), std::end(quadNormals));
    const uint16_t v0 = uint16_t(sphereVertices);
    for (int q = 0; q < 2; ++q)
        for (int k : {0, 1, 2, 0, 2, 3}) indices.push_back(uint16_t(v0 + 4 * q + k));
    if (indices.size() % 2) indices.push_back(0);  // 4-byte alignment of what follows (nothing)

    std::vector<unsigned char> bytes;
    auto append = [&](const void* data, size_t size) {
        size_t at = bytes.size();
        bytes.resize(at + size);
        std::memcpy(bytes.data() + at, data, size);
        return at;
    };
    size_t pAt = append(positions.data(), positions.size() * 4), nAt = append(normals.data(), normals.size() * 4);
    size_t iAt = append(indices.data(), indices.size() * 2);
    Json j;
    j["asset"] = {{"version", "2.0"}};
    j["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_volume"};
    j["buffers"] = Json::array({{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}});
    j["bufferViews"] = Json::array({{{"buffer", 0}, {"byteOffset", pAt}, {"byteLength", positions.size() * 4}},
                                    {{"buffer", 0}, {"byteOffset", nAt}, {"byteLength", normals.size() * 4}},
                                    {{"buffer", 0}, {"byteOffset", iAt}, {"byteLength", indices.size() * 2}}});
    auto vec3 = [&](int view, size_t first, size_t count, bool withBounds) {
        Json a = {{"bufferView", view}, {"byteOffset", first * 12}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}};
        if (withBounds) a["min"] = {-2, -0.5, -2}, a["max"] = {2, 2, 2};
        return a;
    };
    j["accessors"] = Json::array(
        {vec3(0, 0, sphereVertices, true), vec3(1, 0, sphereVertices, false),
         {{"bufferView", 2}, {"componentType", 5123}, {"count", sphereIndices}, {"type", "SCALAR"}},
         vec3(0, 0, positions.size() / 3, true), vec3(1, 0, normals.size() / 3, false),
         {{"bufferView", 2}, {"byteOffset", sphereIndices * 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}},
         {{"bufferView", 2}, {"byteOffset", sphereIndices * 2 + 12}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}});
    j["materials"] = Json::array(
        {{{"name", "chrome"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.95, 0.93, 0.88, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}},
         {{"name", "glass"},
          {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
          {"extensions",
           {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
            {"KHR_materials_ior", {{"ior", 1.5}}},
            {"KHR_materials_volume", {{"thicknessFactor", 1}, {"attenuationColor", {0.7, 0.9, 1}}, {"attenuationDistance", 2}}}}}},
         {{"name", "floor"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}},
         {{"name", "wall"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.3, 0.2, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.5}}}}});
    auto primitive = [](int position, int normal, int index, int material) {
        return Json{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}, {"indices", index}, {"material", material}};
    };
    j["meshes"] = Json::array({{{"name", "ball"}, {"primitives", Json::array({primitive(0, 1, 2, 0)})}},
                               {{"name", "glass ball"}, {"primitives", Json::array({primitive(0, 1, 2, 1)})}},
                               {{"name", "room"}, {"primitives", Json::array({primitive(3, 4, 5, 2), primitive(3, 4, 6, 3)})}}});
    j["cameras"] = Json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"aspectRatio", 4.0 / 3}, {"znear", 0.1}}}}});
    j["extensions"]["KHR_lights_punctual"]["lights"] = Json::array(
        {{{"type", "point"}, {"name", "bulb"}, {"color", {1, 0.9, 0.8}}, {"intensity", 40}},
         {{"type", "spot"}, {"name", "spot"}, {"intensity", 80}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
         {{"type", "directional"}, {"name", "sun"}, {"color", {0.9, 0.95, 1}}, {"intensity", 2}}});
    auto rotation = [](double degrees, glm::dvec3 axis) {
        glm::dquat q = glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
        return Json{q.x, q.y, q.z, q.w};
    };
    auto light = [](int index) { return Json{{"KHR_lights_punctual", {{"light", index}}}}; };
    j["nodes"] = Json::array(
        {{{"name", "world"}, {"rotation", rotation(15, {0, 1, 0})}, {"children", {1, 2, 3, 4}}},
         {{"name", "chrome"}, {"translation", {-0.7, 0.5, 0}}, {"mesh", 0}},
         {{"name", "small chrome"}, {"translation", {0.9, 0.25, 0.8}}, {"scale", {0.5, 0.5, 0.5}}, {"mesh", 0}},
         {{"name", "glass"}, {"translation", {0.5, 0.5, -0.2}}, {"scale", {-1, 1, 1}}, {"mesh", 1}},
         {{"name", "room"}, {"mesh", 2}},
         {{"name", "rig"}, {"translation", {0, 1.2, 4}}, {"rotation", rotation(-12, {1, 0, 0})}, {"scale", {2, 2, 2}}, {"children", {6}}},
         {{"name", "eye"}, {"camera", 0}},
         {{"translation", {1.5, 2.5, 1.5}}, {"extensions", light(0)}},
         {{"translation", {-1, 3, 1}}, {"rotation", rotation(-80, {1, 0, 0.3})}, {"extensions", light(1)}},
         {{"rotation", rotation(-60, {1, 0.5, 0})}, {"extensions", light(2)}}});
    j["scenes"] = Json::array({{{"nodes", {0, 5, 7, 8, 9}}}});
    j["scene"] = 0;
    fs::path path = dir / "authored.gltf";
    std::ofstream(path) << j.dump(1);
    return path;
}

// Every input kind the renderer takes: scene files (textures, csg, mirrors,
// glass), model files through their quick look (OBJ, PLY) and authored
// scenes (glTF with a texture of its own, a generated glTF with camera,
// lights, metal and glass, a generated OBJ/MTL with illum 2, 3, 5, 6, 7,
// and spider.obj with its textures).
std::vector<fs::path> inputs(const fs::path& generated) {
    const fs::path scenes = sourceDir() / "scenes", meshes = sourceDir() / "tests" / "meshes";
    return {scenes / "showcase.xml", scenes / "several_mirrors.xml", meshes / "pyramid.obj",
            meshes / "uv_sphere_12x24.obj", meshes / "pyramid.ply",
            assimpTestModel("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"), writeAuthoredGltf(generated),
            writeIlluminationObj(generated), assimpTestModel("OBJ/spider.obj")};
}

TEST(Convert, ConvertedSceneRendersBitIdentically) {
    fs::path dir = freshOutputDir("convert", "identical");
    fs::path generated = dir / "generated";
    fs::create_directories(generated);
    int n = 0;
    for (const fs::path& input : inputs(generated)) {
        ASSERT_TRUE(fs::exists(input)) << input << " (assimp-testmodels: tools/install_deps.sh --all)";
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
        // Authored meshes are written as the parts of their file they are
        // (<file part="...">), not as inline triangles.
        if (n > 5) {
            EXPECT_NE(bytes(xml).find("<file part=\""), std::string::npos) << input;
            EXPECT_EQ(bytes(xml).find("<polygons>"), std::string::npos) << input;
        }
        // Converting the converted scene changes nothing more.
        fs::path again = dir / (stem + ".again.xml");
        ASSERT_EQ(whitted("convert " + xml.string() + " -o " + again.string(), dir).status, 0);
        EXPECT_EQ(bytes(again), bytes(xml)) << input;
    }
}

// <file part="..."> that the file does not have: status 2 at the line of
// the <file>, naming what the file has.
TEST(Convert, MissingFilePartIsRefusedAtItsLine) {
    fs::path dir = freshOutputDir("convert", "missing_part");
    fs::path gltf = writeAuthoredGltf(dir), obj = writeIlluminationObj(dir);
    auto scene = [&](const std::string& file, const std::string& part) {
        std::ofstream(dir / "scene.xml")
            << "<scene>\n<camera><position x=\"0\" y=\"1\" z=\"5\"/><window_position x=\"0\" y=\"1\" z=\"4\"/></camera>\n"
               "<lights><light><position x=\"0\" y=\"5\" z=\"5\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>\n"
               "<objects><object><diffuse_color r=\"1\" g=\"1\" b=\"1\"/><properties><type>mesh</type>\n"
               "<file part=\""
            << part << "\">" << file << "</file>\n</properties></object></objects></scene>\n";
        return whitted("render scene.xml -q --width 16 --height 16 -o out.png", dir);
    };
    struct Case {
        std::string file, part, message;
    };
    for (const Case& c : {Case{gltf.filename().string(), "mesh 0 primitive 1", "mesh 0 has 1 primitive"},
                          Case{gltf.filename().string(), "mesh 7 primitive 0", "the file has no mesh 7 (it has 3 meshes"},
                          Case{gltf.filename().string(), "mesh room primitive 2", "mesh room has 2 primitives"},
                          Case{gltf.filename().string(), "material chrome", "names no glTF primitive"},
                          Case{obj.filename().string(), "material brass", "the file has no material \"brass\" (it has "},
                          Case{obj.filename().string(), "mesh 0 primitive 0", "expected part=\"material NAME\""}}) {
        CommandRun run = scene(c.file, c.part);
        EXPECT_EQ(run.status, 2) << c.part << ": " << run.output;
        EXPECT_NE(run.output.find("scene.xml:5: mesh file \"" + c.file + "\""), std::string::npos) << run.output;
        EXPECT_NE(run.output.find(c.message), std::string::npos) << run.output;
    }
    EXPECT_FALSE(fs::exists(dir / "out.png"));
    // The parts that exist, by index and by the mesh's name, load.
    EXPECT_EQ(scene(gltf.filename().string(), "mesh room primitive 1").status, 0);
    EXPECT_EQ(scene(obj.filename().string(), "material glass").status, 0);
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

// glTF and GLB files that are wrong in one way each (scenes/README.md
// "Limits"): refused with the file and the JSON path, never a crash, an
// unbounded walk or an allocation the file cannot back; node trees at the
// depth limit still load, in the file's order.
#include "io/gltf_file.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/authored_scene.h"
#include "scene/mesh_objects.h"
#include "gltf_documents.h"
#include "test_support.h"

#include <cstring>
#include <fstream>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return freshOutputDir("gltf_hardening", name); }

// The loader's message for `file`, or "" when it loads.
std::string refusal(const fs::path& file) {
    try {
        loadGltfScene(file);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// A chain at the depth limit loads, its transform the product of every
// level's; one level more is refused at the node past the limit, as are
// chains of 5,000 and 200,000 (the walk that once recursed per level and
// crashed at 5,000).
TEST(GltfHardening, NodeChainsUpToTheDepthLimitLoadDeeperAreRefused) {
    fs::path dir = scratch("chains");
    Scene scene = loadGltfScene(writeJson(dir / "limit.gltf", chain(kMaxGltfNodeDepth))).scene;
    ASSERT_EQ(scene.objects.size(), 1u);
    const auto& mesh = std::get<Mesh>(scene.objects[0].shape);
    ASSERT_FALSE(mesh.triangles.empty());
    EXPECT_NEAR(mesh.triangles[0].v0.x, -1 + 0.001 * double(kMaxGltfNodeDepth), 1e-9);
    for (size_t depth : {kMaxGltfNodeDepth + 1, size_t(5000), size_t(200000)}) {
        fs::path file = writeJson(dir / ("chain" + std::to_string(depth) + ".gltf"), chain(depth));
        EXPECT_EQ(refusal(file), file.string() + ": /nodes/" + std::to_string(kMaxGltfNodeDepth) + ": is more than " +
                                     std::to_string(kMaxGltfNodeDepth) +
                                     " levels deep in the node tree; whitted reads trees up to that depth")
            << depth;
    }
}

// A .gltf larger than the JSON limit is refused by its size before it is
// read (a 10-million-node chain is about 190 MB of JSON).
TEST(GltfHardening, JsonBeyondItsLimitIsRefusedUnread) {
    fs::path file = writeJson(scratch("size") / "huge.gltf", squareDocument());
    fs::resize_file(file, kMaxGltfJsonBytes + 1);  // sparse: no 64 MiB written
    EXPECT_EQ(refusal(file), file.string() + ": is " + std::to_string(kMaxGltfJsonBytes + 1) +
                                 " bytes of JSON; whitted reads glTF JSON up to " + std::to_string(kMaxGltfJsonBytes) +
                                 " bytes (keep large buffers in .bin files or a .glb)");
}

TEST(GltfHardening, CyclesDuplicateRootsAndSecondParentsAreRefused) {
    fs::path dir = scratch("trees");
    Json j = squareDocument();
    // 0 is a root; 1 -> 2 -> 3 -> 1 is a cycle no root reaches.
    j["nodes"] = Json::array({{{"mesh", 0}}, {{"children", {2}}}, {{"children", {3}}}, {{"children", {1}}}});
    fs::path cycle = writeJson(dir / "cycle.gltf", j);
    EXPECT_EQ(refusal(cycle), cycle.string() + ": /nodes/1: is its own ancestor (the node tree has a cycle)");

    j = squareDocument();
    j["nodes"] = Json::array({{{"mesh", 0}}, {{"mesh", 0}}});
    j["scenes"] = Json::array({{{"nodes", {0, 1, 0}}}});
    fs::path twice = writeJson(dir / "roots.gltf", j);
    EXPECT_EQ(refusal(twice), twice.string() + ": /scenes/0/nodes: lists root node 0 twice");

    j["nodes"] = Json::array({{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}});
    j["scenes"] = Json::array({{{"nodes", {0, 1}}}});
    fs::path parents = writeJson(dir / "parents.gltf", j);
    EXPECT_EQ(refusal(parents),
              parents.string() + ": /nodes/1/children: makes node 2 a child twice (a node has at most one parent)");
}

// Index accessors of signed or float types (where -1 once passed the bound
// check and became a vertex index), and normalised ones, are refused.
TEST(GltfHardening, IndexAccessorsAreUnsignedIntegers) {
    fs::path dir = scratch("indices");
    for (auto [type, normalized] : {std::pair{5120, false}, {5122, false}, {5126, false}, {5123, true}}) {
        Json j = squareDocument();
        j["accessors"][1]["componentType"] = type;
        if (normalized) j["accessors"][1]["normalized"] = true;
        fs::path file = writeJson(dir / ("type" + std::to_string(type) + ".gltf"), j);
        EXPECT_EQ(refusal(file), file.string() + ": /accessors/1/componentType: is " + std::to_string(type) +
                                     (normalized ? " normalized" : "") +
                                     "; indices must be UNSIGNED_BYTE (5121), UNSIGNED_SHORT (5123) or UNSIGNED_INT (5125)");
    }
}

// Accessors and views whose sizes the file cannot back are refused before
// anything is allocated for them.
TEST(GltfHardening, AccessorAndViewSizesAreCheckedFirst) {
    fs::path dir = scratch("sizes");
    auto refused = [&](const std::string& name, const Json& j) { return refusal(writeJson(dir / name, j)); };

    Json j = squareDocument();
    j["accessors"][0]["count"] = 1000000000;  // 24 GB of doubles, had it been allocated
    EXPECT_EQ(refused("count.gltf", j), (dir / "count.gltf").string() + ": /accessors/0: runs past the end of its bufferView");

    j = squareDocument();
    j["accessors"][0].erase("bufferView");
    j["accessors"][0]["count"] = 1000000000;
    EXPECT_EQ(refused("zeros.gltf", j),
              (dir / "zeros.gltf").string() + ": /accessors/0/count: is 1000000000 for an accessor without a bufferView; "
                                              "whitted reads such an accessor (all zeros) up to 65536 elements");

    j = squareDocument();
    j["buffers"][0].erase("byteLength");
    EXPECT_EQ(refused("length.gltf", j), (dir / "length.gltf").string() + ": /buffers/0: has no byteLength");

    j = squareDocument();
    j["bufferViews"][0]["byteStride"] = 6;
    EXPECT_EQ(refused("stride6.gltf", j),
              (dir / "stride6.gltf").string() + ": /bufferViews/0/byteStride: is 6; it must be a multiple of 4");
    j["bufferViews"][0]["byteStride"] = 8;  // a VEC3 of floats is 12 bytes
    EXPECT_EQ(refused("stride8.gltf", j), (dir / "stride8.gltf").string() +
                                              ": /accessors/0: has elements of 12 bytes, more than its bufferView's "
                                              "byteStride 8");

    // A NaN vertex coordinate in the buffer.
    std::vector<unsigned char> bytes = squareBytes();
    float nan = std::nanf("");
    std::memcpy(bytes.data() + 4, &nan, 4);
    j = squareDocument();
    j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bytes);
    EXPECT_EQ(refused("nan.gltf", j),
              (dir / "nan.gltf").string() + ": /accessors/0: holds a value that is not finite (element 0)");
}

TEST(GltfHardening, CameraPlanesFollowTheSpecification) {
    fs::path dir = scratch("cameras");
    auto withCamera = [&](const std::string& name, const Json& camera) {
        Json j = squareDocument();
        j["cameras"] = Json::array({camera});
        j["nodes"] = Json::array({{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 0, 5}}}});
        return refusal(writeJson(dir / name, j));
    };
    auto at = [&](const std::string& name) { return (dir / name).string() + ": /cameras/0/"; };
    Json p = {{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", -1}}}};
    EXPECT_EQ(withCamera("znear.gltf", p), at("znear.gltf") + "perspective/znear: is -1; it must be > 0");
    p["perspective"]["znear"] = 0;
    EXPECT_EQ(withCamera("zero.gltf", p), at("zero.gltf") + "perspective/znear: is 0; it must be > 0");
    p["perspective"]["znear"] = 2;
    p["perspective"]["zfar"] = 1;
    EXPECT_EQ(withCamera("zfar.gltf", p), at("zfar.gltf") + "perspective/zfar: is 1; it must be > znear, 2");
    p["perspective"].erase("znear");
    EXPECT_EQ(withCamera("noznear.gltf", p), (dir / "noznear.gltf").string() + ": /cameras/0/perspective: has no znear");
    Json o = {{"type", "orthographic"}, {"orthographic", {{"xmag", 0}, {"ymag", 1}, {"znear", 0}, {"zfar", 10}}}};
    EXPECT_EQ(withCamera("xmag.gltf", o), at("xmag.gltf") + "orthographic/xmag: is 0; it must be in [1e-09, 1e+12]");
    o["orthographic"]["xmag"] = 1;
    o["orthographic"]["zfar"] = 0;
    EXPECT_EQ(withCamera("ortho.gltf", o), at("ortho.gltf") + "orthographic/zfar: is 0; it must be > znear, 0");
    o["orthographic"]["zfar"] = 10;
    EXPECT_EQ(withCamera("good.gltf", o), "");
}

// A .glb whose header length is not the file's, and the file cut at every
// chunk boundary and inside each chunk: refused, never read past its end.
TEST(GltfHardening, GlbLengthsAndTruncations) {
    fs::path dir = scratch("glb");
    const std::vector<unsigned char> good = glbBytes(squareDocument(false), squareBytes());
    EXPECT_EQ(refusal(writeBytes(dir / "good.glb", good)), "");

    std::vector<unsigned char> longer = good;
    const uint32_t claimed = uint32_t(good.size() + 1000);
    std::memcpy(longer.data() + 8, &claimed, 4);
    fs::path header = writeBytes(dir / "header.glb", longer);
    EXPECT_EQ(refusal(header), header.string() + ": is a binary glTF whose header gives its length as " +
                                   std::to_string(claimed) + " bytes, but the file has " + std::to_string(good.size()));

    for (size_t cut : glbCuts(good)) {
        fs::path file = writeBytes(dir / ("cut" + std::to_string(cut) + ".glb"), glbCutAt(good, cut));
        std::string message = refusal(file);
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << cut << ": " << message;
    }
}

// Degenerate triangles in several nodes make one warning with the totals;
// each node's line is a detail (Scene::warningDetails: `whitted render -v`
// prints them, the render record keeps them). A single node keeps its own
// line as the warning (MeshesAreCheckedWherePlaced).
TEST(GltfHardening, DegenerateTrianglesOfSeveralNodesAreOneWarning) {
    fs::path dir = scratch("several_flat");
    fs::path file = writeJson(dir / "flat.gltf", flattenedNodesDocument());
    AuthoredScene loaded = loadGltfScene(file);
    EXPECT_EQ(loaded.scene.objects.size(), 1u);
    EXPECT_EQ(loaded.scene.warnings,
              std::vector<std::string>{file.string() + ": 4 degenerate triangles skipped in 2 nodes"});
    EXPECT_EQ(loaded.scene.warningDetails,
              (std::vector<std::string>{file.string() + ": node \"node 0\": 2 degenerate triangles skipped",
                                        file.string() + ": node \"flat\": 2 degenerate triangles skipped"}));
}

// The counts in these warnings, as a person reads them.
TEST(GltfHardening, SkippedTrianglesAreCountedWithThousandsGrouped) {
    EXPECT_EQ(skippedTriangles(1), "1 degenerate triangle skipped");
    EXPECT_EQ(skippedTriangles(2345), "2,345 degenerate triangles skipped");
    EXPECT_EQ(withThousands(0), "0");
    EXPECT_EQ(withThousands(999), "999");
    EXPECT_EQ(withThousands(1000), "1,000");
    EXPECT_EQ(withThousands(1234567), "1,234,567");
}

// Node transforms multiply, so where a mesh lands is checked once placed
// (the glTF fuzzer's finding: a scale of 1e-200 flattened a square to
// triangles of zero area, and chained translations carried it past the
// scene's ±1e6). A flattened triangle is dropped with a warning, a primitive
// left empty is dropped, and a vertex placed beyond ±1e6 is refused.
TEST(GltfHardening, MeshesAreCheckedWherePlaced) {
    fs::path dir = scratch("placed");
    Json flat = squareDocument();
    flat["nodes"] = Json::array({{{"mesh", 0}, {"scale", {1, 1e-200, 1}}}, {{"mesh", 0}, {"scale", {1, 1, 1}}}});
    flat["scenes"] = Json::array({{{"nodes", {0, 1}}}});
    fs::path flatFile = writeJson(dir / "flat.gltf", flat);
    AuthoredScene loaded = loadGltfScene(flatFile);
    ASSERT_EQ(loaded.scene.objects.size(), 1u);  // node 0's square is gone, node 1's stays whole
    EXPECT_EQ(std::get<Mesh>(loaded.scene.objects[0].shape).triangles.size(), 2u);
    EXPECT_EQ(loaded.scene.warnings,
              std::vector<std::string>{flatFile.string() + ": node \"node 0\": 2 degenerate triangles skipped"});

    Json far = squareDocument();
    far["nodes"] = Json::array({{{"translation", {1e6, 0, 0}}, {"children", {1}}}, {{"translation", {1e6, 0, 0}}, {"mesh", 0}}});
    fs::path farFile = writeJson(dir / "far.gltf", far);
    EXPECT_EQ(refusal(farFile), farFile.string() + ": node \"node 1\": a vertex is placed beyond ±1e6");

    Json farLight = squareDocument();
    farLight["extensionsUsed"] = Json::array({"KHR_lights_punctual"});
    farLight["extensions"] = {{"KHR_lights_punctual", {{"lights", Json::array({{{"type", "point"}}})}}}};
    farLight["nodes"] = Json::array({{{"mesh", 0}},
                                     {{"translation", {1e6, 0, 0}}, {"children", {2}}},
                                     {{"translation", {1e6, 0, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}});
    farLight["scenes"] = Json::array({{{"nodes", {0, 1}}}});
    fs::path lightFile = writeJson(dir / "far_light.gltf", farLight);
    EXPECT_EQ(refusal(lightFile), lightFile.string() + ": node \"node 2\": its light is placed beyond ±1e6");

    Json farCamera = squareDocument();
    farCamera["cameras"] = Json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}});
    farCamera["nodes"] = Json::array({{{"mesh", 0}},
                                      {{"translation", {0, 1e6, 0}}, {"children", {2}}},
                                      {{"translation", {0, 1e6, 0}}, {"camera", 0}}});
    farCamera["scenes"] = Json::array({{{"nodes", {0, 1}}}});
    fs::path cameraFile = writeJson(dir / "far_camera.gltf", farCamera);
    EXPECT_EQ(refusal(cameraFile), cameraFile.string() + ": node \"node 2\": its camera is placed beyond ±1e6");
}

}  // namespace
}  // namespace whitted::test

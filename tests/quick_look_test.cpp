// Quick looks (host/scene/quick_look.*): a model file given where a scene is
// expected is framed by a generated camera, lit and put on a floor; the
// scene written for it references the model and renders the same image.
#include "test_support.h"

#include "scene/quick_look.h"
#include "io/image_io.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "view/editor_panel.h"

#include <fstream>
#include <sstream>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

fs::path scratchDir(const std::string& name) { return freshOutputDir("quick_look", name); }

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

CommandRun runWhitted(const std::string& args, const fs::path& cwd) {
    return runCommand("'" WHITTED_EXECUTABLE "' " + args, cwd);
}

TEST(QuickLook, SceneFilesAreTheXmlOnes) {
    EXPECT_TRUE(isSceneFile("a/room.xml"));
    EXPECT_TRUE(isSceneFile("ROOM.XML"));
    EXPECT_FALSE(isSceneFile("bunny.obj"));
    EXPECT_FALSE(isSceneFile("model.glb"));
    EXPECT_FALSE(isSceneFile("noextension"));
    EXPECT_EQ(quickLookScenePath("m/bunny.obj"), fs::path("m/bunny.obj.whitted.xml"));
}

// The model alone (floor left out), 160x120: its pixels are a reasonable
// central part of the image and touch no border. Our test meshes, and glTF
// binaries (y up) from Debian's assimp-testmodels (tools/install_deps.sh --all).
TEST(QuickLook, ModelIsInFrame) {
    const fs::path meshes = sourceDir() / "tests" / "meshes", gltf = assimpTestModel("glTF2");
    for (fs::path model : {meshes / "pyramid.obj", meshes / "pyramid.ply", meshes / "uv_sphere_12x24.obj",
                           gltf / "BoxTextured-glTF-Binary" / "BoxTextured.glb",
                           gltf / "2CylinderEngine-glTF-Binary" / "2CylinderEngine.glb"}) {
        SCOPED_TRACE(model.string());
        ASSERT_TRUE(fs::exists(model)) << "missing: install assimp-testmodels (tools/install_deps.sh --all)";
        Scene scene = quickLookScene(model);
        // The model (one object per material of a file with its own
        // materials, scenes/README.md "Model files"), then the floor.
        ASSERT_GE(scene.objects.size(), 2u);
        for (size_t i = 0; i + 1 < scene.objects.size(); ++i)
            ASSERT_TRUE(std::holds_alternative<Mesh>(scene.objects[i].shape));
        ASSERT_TRUE(std::holds_alternative<Plane>(scene.objects.back().shape));
        EXPECT_EQ(scene.lights.size(), 2u);
        if (model.extension() != ".glb") {
            EXPECT_TRUE(scene.warnings.empty());  // the engine has degenerate triangles
            // No colour of its own and none in the file: the material an XML
            // mesh without <diffuse_color> gets.
            ASSERT_EQ(scene.objects.size(), 2u);
            EXPECT_EQ(scene.objects[0].material.diffuseColor, Material{}.diffuseColor);
            EXPECT_EQ(scene.objects[0].material.specularColor, Material{}.specularColor);
        }
        scene.objects.pop_back();
        RenderResult r = renderScene(scene, {.width = 160, .height = 120, .samplesPerPixel = 1, .maxDepth = 2,
                                             .auxiliary = true});
        int hits = 0;
        double cx = 0, cy = 0;
        for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x) {
                if (pixel(r, gpu::kAovCoefs1, x, y).w == 0) continue;
                ++hits, cx += x + 0.5, cy += y + 0.5;
                EXPECT_TRUE(x > 0 && y > 0 && x < 159 && y < 119)
                    << "the model touches the border at " << x << "," << y;
            }
        double share = hits / (160.0 * 120.0);
        EXPECT_GT(share, 0.05);
        EXPECT_LT(share, 0.6);
        EXPECT_NEAR(cx / hits, 80, 20);
        EXPECT_NEAR(cy / hits, 60, 20);
    }
}

// The scene written for a quick look references the model (no inline
// triangles) and renders exactly the same image, smooth normals included.
TEST(QuickLook, WrittenSceneRendersTheSameImage) {
    fs::path dir = scratchDir("written");
    fs::copy_file(sourceDir() / "tests" / "meshes" / "uv_sphere_12x24.obj", dir / "sphere.obj");
    Scene scene = quickLookScene(dir / "sphere.obj");
    EXPECT_EQ(scene.sourcePath, dir / "sphere.obj.whitted.xml");
    writeSceneFile(scene, dir / "sphere.obj.whitted.xml");
    std::string text = readText(dir / "sphere.obj.whitted.xml");
    EXPECT_NE(text.find("<file>sphere.obj</file>"), std::string::npos) << text;
    EXPECT_EQ(text.find("<polygons>"), std::string::npos);
    Scene loaded = loadScene(dir / "sphere.obj.whitted.xml");
    RenderSettings s{.width = 80, .height = 60, .samplesPerPixel = 2, .maxDepth = 4, .auxiliary = true};
    RenderResult a = renderScene(scene, s), b = renderScene(loaded, s);
    for (uint32_t l = 0; l < gpu::kAovCount; ++l) EXPECT_TRUE(a.layers[l] == b.layers[l]) << "layer " << l;

    // Edited as the window's panel does (moved, a checker switched on): the
    // file keeps the reference, and the placement and checker survive.
    ASSERT_FALSE(setObjectField(scene, 0, "y", 0.25));
    ASSERT_FALSE(setObjectField(scene, 0, "checker_size", 0.3));
    ASSERT_FALSE(setObjectField(scene, 0, "checker_r", 0.2));
    writeSceneFile(scene, dir / "edited.xml");
    EXPECT_NE(readText(dir / "edited.xml").find("<file>sphere.obj</file>"), std::string::npos);
    Scene edited = loadScene(dir / "edited.xml");
    EXPECT_EQ(edited.objects[0].material.checkerOrigin, scene.objects[0].material.checkerOrigin);
    RenderResult c = renderScene(scene, s), d = renderScene(edited, s);
    EXPECT_FALSE(c.layers[gpu::kAovColor] == a.layers[gpu::kAovColor]) << "the edits changed nothing";
    for (uint32_t l = 0; l < gpu::kAovCount; ++l) {
        ASSERT_EQ(c.layers[l].size(), d.layers[l].size());
        for (size_t i = 0; i < c.layers[l].size(); ++i)  // moved: vertices re-placed from the file, within rounding
            ASSERT_NEAR(c.layers[l][i], d.layers[l][i], 1e-3f) << "layer " << l << " value " << i;
    }
}

// A model with materials of its own (BoxTextured.glb: a base-colour texture)
// is split into one object per material in memory; the written scene names
// the file once, without a colour, so loading it brings the file's
// materials back: the same objects and the same image.
TEST(QuickLook, WrittenSceneKeepsTheModelsMaterials) {
    fs::path dir = scratchDir("materials");
    const fs::path model = assimpTestModel("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
    ASSERT_TRUE(fs::exists(model)) << "missing: install assimp-testmodels (tools/install_deps.sh --all)";
    fs::copy_file(model, dir / "box.glb");
    Scene scene = quickLookScene(dir / "box.glb");
    ASSERT_TRUE(scene.objects[0].material.diffuseTexture) << "the file's texture is not used";
    writeSceneFile(scene, dir / "box.glb.whitted.xml");
    std::string text = readText(dir / "box.glb.whitted.xml");
    size_t file = text.find("<file>box.glb</file>");
    ASSERT_NE(file, std::string::npos) << text;
    EXPECT_EQ(text.find("<file>", file + 1), std::string::npos) << "the model is written more than once";
    Scene loaded = loadScene(dir / "box.glb.whitted.xml");
    ASSERT_EQ(loaded.objects.size(), scene.objects.size());
    EXPECT_TRUE(loaded.objects[0].material.diffuseTexture);
    RenderSettings s{.width = 80, .height = 60, .samplesPerPixel = 1, .maxDepth = 2};
    RenderResult a = renderScene(scene, s), b = renderScene(loaded, s);
    EXPECT_TRUE(a.layers[gpu::kAovColor] == b.layers[gpu::kAovColor]);
}

// The parts of a model split by its materials move and change together:
// an edit of one part (as the panel or the script makes it) is applied to
// all, so the written scene, which names the file once, reloads as shown.
TEST(QuickLook, PartsOfOneModelAreEditedTogether) {
    fs::path dir = scratchDir("parts");
    const fs::path model = assimpTestModel("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    ASSERT_TRUE(fs::exists(model)) << "missing: install assimp-testmodels (tools/install_deps.sh --all)";
    fs::copy_file(model, dir / "engine.glb");
    Scene scene = quickLookScene(dir / "engine.glb");
    size_t parts = scene.objects.size() - 1;  // the floor last
    ASSERT_GT(parts, 2u);
    const glm::dvec3 before = shapeReferencePoint(scene.objects[0].shape);
    ASSERT_FALSE(setObjectField(scene, 2, "y", shapeReferencePoint(scene.objects[2].shape).y + 0.5));
    ASSERT_FALSE(setObjectField(scene, 1, "kd", 0.3));
    for (size_t i = 0; i < parts; ++i) {
        EXPECT_EQ(scene.objects[i].material.diffuse, 0.3) << "part " << i;
        EXPECT_NEAR(std::get<Mesh>(scene.objects[i].shape).source->position.y,
                    std::get<Mesh>(scene.objects[2].shape).source->position.y, 1e-12);
    }
    EXPECT_NEAR(shapeReferencePoint(scene.objects[0].shape).y - before.y, 0.5, 1e-9);
    writeSceneFile(scene, dir / "edited.xml");
    Scene loaded = loadScene(dir / "edited.xml");
    ASSERT_EQ(loaded.objects.size(), scene.objects.size());
    RenderSettings s{.width = 80, .height = 60, .samplesPerPixel = 1, .maxDepth = 2};
    RenderResult a = renderScene(scene, s), b = renderScene(loaded, s);
    ASSERT_EQ(a.layers[gpu::kAovColor].size(), b.layers[gpu::kAovColor].size());
    for (size_t i = 0; i < a.layers[gpu::kAovColor].size(); ++i)  // vertices re-placed from the file, within rounding
        ASSERT_NEAR(a.layers[gpu::kAovColor][i], b.layers[gpu::kAovColor][i], 2e-3f) << "value " << i;
}

// The command line: a model renders (into -o or a history folder whose
// scene.xml is the generated scene), bad models exit 2 with the reason.
TEST(QuickLook, CommandLine) {
    fs::path dir = scratchDir("cli");
    fs::copy_file(sourceDir() / "tests" / "meshes" / "pyramid.ply", dir / "pyramid.ply");
    const std::string size = " --width 64 --height 48 --validate";
    CommandRun r = runWhitted("render pyramid.ply -o out.png --aov depth" + size, dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out.png"));
    EXPECT_TRUE(fs::exists(dir / "out.depth.png"));
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;

    r = runWhitted("render pyramid.ply --aov none" + size, dir);
    ASSERT_EQ(r.status, 0) << r.output;
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(dir / "renders")) entries.push_back(e.path());
    ASSERT_EQ(entries.size(), 1u);
    Scene copy = loadScene(entries[0] / "scene.xml");  // the generated scene, the model found from there
    EXPECT_EQ(copy.objects.size(), 2u);
    EXPECT_NE(readText(entries[0] / "scene.xml").find("<file>../../pyramid.ply</file>"), std::string::npos);

    fs::path meshes = sourceDir() / "tests" / "meshes";
    r = runWhitted("render '" + (meshes / "garbage.ply").string() + "' -o bad.png" + size, dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find((meshes / "garbage.ply").string() +
                            ": mesh file \"garbage.ply\" could not be read: Invalid .ply file: Incorrect magic number "
                            "(expected 'ply' or 'PLY')."),
              std::string::npos)
        << r.output;
    r = runWhitted("render missing.obj -o bad.png" + size, dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("missing.obj: cannot read file: it does not exist"), std::string::npos) << r.output;
    r = runWhitted("render '" + (meshes / "lines_only.obj").string() + "' -o bad.png" + size, dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("lines_only.obj: mesh file \"lines_only.obj\""), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
    // The window refuses it before opening (no X server needed).
    r = runWhitted("view '" + (meshes / "truncated.ply").string() + "'", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("truncated.ply: mesh file \"truncated.ply\" could not be read"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(meshes / "truncated.ply.whitted.xml"));
}

}  // namespace
}  // namespace whitted::test

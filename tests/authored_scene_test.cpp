// Authored scenes (scenes/README.md "Authored scenes"): glTF 2.0 files
// written here with their JSON and a base64 buffer, Debian's Cameras.gltf
// and spider.obj, a generated OBJ/MTL; the orthographic camera, --camera and
// --exposure.
#include "scene/quick_look.h"
#include "io/gltf_file.h"
#include "io/image_io.h"
#include "io/mtl_file.h"
#include "scene/authored_scene.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <tuple>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
constexpr double kPi = 3.14159265358979323846;

fs::path scratch(const std::string& name) { return freshOutputDir("authored", name); }

CommandRun runWhitted(const std::string& args, const fs::path& cwd) {
    return runCommand("'" WHITTED_EXECUTABLE "' " + args, cwd);
}

// A glTF document with one mesh: a square of side `side` in the xy plane
// centred on the origin, facing +z (two triangles, positions only).
Json squareGltf(float side) {
    float h = side / 2;
    std::vector<float> positions = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
    std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
    std::vector<unsigned char> bytes(positions.size() * 4 + indices.size() * 2);
    std::memcpy(bytes.data(), positions.data(), positions.size() * 4);
    std::memcpy(bytes.data() + positions.size() * 4, indices.data(), indices.size() * 2);
    Json j;
    j["asset"] = {{"version", "2.0"}};
    j["buffers"] = Json::array({{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}});
    j["bufferViews"] = Json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                                    {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}});
    j["accessors"] = Json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                                  {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}});
    j["meshes"] = Json::array({{{"primitives", Json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}})}}});
    return j;
}

fs::path writeJson(const fs::path& path, const Json& j) {
    std::ofstream(path) << j.dump(1);
    return path;
}

// Centroid (pixel units) and count of the pixels whose centre ray hit anything.
struct Coverage {
    double x = 0, y = 0;
    int hits = 0;
    int minX = 1 << 30, maxX = -1, minY = 1 << 30, maxY = -1;
};
Coverage coverage(const RenderResult& r) {
    Coverage c;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            if (pixel(r, gpu::kAovCoefs1, x, y).w > 0) {
                c.x += x + 0.5, c.y += y + 0.5, ++c.hits;
                c.minX = std::min(c.minX, x), c.maxX = std::max(c.maxX, x);
                c.minY = std::min(c.minY, y), c.maxY = std::max(c.maxY, y);
            }
    if (c.hits) c.x /= c.hits, c.y /= c.hits;
    return c;
}

// A camera placed through a parent node that rotates and scales and a child
// that translates: the camera's frame is the node's world transform, and
// a small square's image lands where the projection computed here puts it.
TEST(AuthoredGltf, CameraThroughNodeHierarchy) {
    fs::path dir = scratch("hierarchy");
    Json j = squareGltf(0.2f);
    // Parent: 30 degrees about y, scale 2; child: translation (0, 0.5, 4) in
    // the parent's frame, so the camera sits at R (2 (0, 0.5, 4)).
    glm::dquat q = glm::angleAxis(glm::radians(30.0), glm::dvec3(0, 1, 0));
    j["nodes"] = Json::array({{{"name", "rig"}, {"rotation", {q.x, q.y, q.z, q.w}}, {"scale", {2, 2, 2}}, {"children", {1}}},
                              {{"name", "eye"}, {"translation", {0, 0.5, 4}}, {"camera", 0}},
                              {{"name", "target"}, {"translation", {1.0, 0.4, 0.5}}, {"mesh", 0}}});
    j["scenes"] = Json::array({{{"nodes", {0, 2}}}});
    j["cameras"] = Json::array({{{"type", "perspective"}, {"name", "main"},
                                 {"perspective", {{"yfov", 0.6}, {"aspectRatio", 4.0 / 3.0}, {"znear", 0.1}}}}});
    fs::path file = writeJson(dir / "hierarchy.gltf", j);
    Scene scene = loadSceneOrModel(file);
    glm::dmat3 r = glm::mat3_cast(q);
    glm::dvec3 eye = r * (2.0 * glm::dvec3(0, 0.5, 4)), forward = r * glm::dvec3(0, 0, -1), up = r * glm::dvec3(0, 1, 0);
    EXPECT_NEAR(glm::length(scene.camera.eye - eye), 0, 1e-12);
    EXPECT_NEAR(glm::length(scene.camera.windowCenter - (eye + forward)), 0, 1e-12);
    EXPECT_NEAR(glm::length(scene.camera.up - up), 0, 1e-12);
    EXPECT_NEAR(scene.camera.verticalFovDegrees, glm::degrees(0.6), 1e-12);
    EXPECT_EQ(scene.camera.width, 640);
    EXPECT_EQ(scene.camera.height, 480);
    EXPECT_EQ(scene.ambientLight, glm::dvec3(0));
    EXPECT_EQ(scene.lights.size(), 2u);  // none authored: the quick look's
    scene.objects.pop_back();            // and its floor, left out here
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].name, "target");

    // The projection of the square's centre (1, 0.4, 0.5).
    glm::dvec3 d = glm::dvec3(1.0, 0.4, 0.5) - eye;
    glm::dvec3 right = glm::normalize(glm::cross(forward, up));
    double t = std::tan(0.3);
    double ndcX = glm::dot(d, right) / glm::dot(d, forward) / (t * 4.0 / 3.0);
    double ndcY = glm::dot(d, up) / glm::dot(d, forward) / t;
    RenderResult result = renderScene(scene, {.width = 160, .height = 120, .samplesPerPixel = 1, .maxDepth = 0});
    Coverage c = coverage(result);
    ASSERT_GT(c.hits, 10);
    EXPECT_NEAR(c.x, (ndcX + 1) / 2 * 160, 0.75);
    EXPECT_NEAR(c.y, (1 - ndcY) / 2 * 120, 0.75);
}

// ClearCoatTest.gltf (assimp-testmodels) writes its labels as emissive
// textures: each object of a material with an emissiveTexture carries it as
// its emission texture, with the material's emissiveFactor as emission.
TEST(AuthoredGltf, RealFileEmissiveTexturesAreMapped) {
    fs::path model = assimpTestModel("glTF2/ClearCoat-glTF/ClearCoatTest.gltf");
    ASSERT_TRUE(fs::exists(model)) << "missing: install assimp-testmodels (tools/install_deps.sh --all)";
    Json j = Json::parse(std::ifstream(model));
    std::vector<glm::dvec3> factors;
    for (const Json& m : j["materials"])
        if (m.contains("emissiveTexture")) {
            std::vector<double> f = m.value("emissiveFactor", std::vector<double>{0, 0, 0});
            factors.push_back({f[0], f[1], f[2]});
        }
    ASSERT_FALSE(factors.empty());
    Scene scene = loadSceneOrModel(model);
    int textured = 0;
    for (const Object& o : scene.objects)
        if (o.material.emissionTexture) {
            ++textured;
            EXPECT_NE(std::find(factors.begin(), factors.end(), o.material.emission), factors.end()) << o.name;
        }
    EXPECT_GT(textured, 0);
}

// Cameras.gltf (assimp-testmodels): its perspective camera by default, its
// orthographic one by --camera 1; the orthographic image of the unit square
// (turned 45 degrees about x) spans exactly its projection.
TEST(AuthoredGltf, CamerasGltfRendersThroughItsOwnCameras) {
    fs::path model = assimpTestModel("glTF2/cameras/Cameras.gltf");
    ASSERT_TRUE(fs::exists(model)) << "missing: install assimp-testmodels (tools/install_deps.sh --all)";
    Scene perspective = loadSceneOrModel(model);
    EXPECT_EQ(perspective.camera.projection, Camera::Projection::Perspective);
    EXPECT_EQ(perspective.camera.eye, glm::dvec3(0.5, 0.5, 3.0));
    EXPECT_EQ(perspective.camera.windowCenter, glm::dvec3(0.5, 0.5, 2.0));
    EXPECT_NEAR(perspective.camera.verticalFovDegrees, glm::degrees(0.7), 1e-12);
    EXPECT_EQ(perspective.camera.width, 640);
    EXPECT_EQ(perspective.camera.height, 640);  // aspectRatio 1
    Scene ortho = loadSceneOrModel(model, "1");
    EXPECT_EQ(ortho.camera.projection, Camera::Projection::Orthographic);
    EXPECT_EQ(ortho.camera.windowHeight, 2.0);  // 2 ymag
    EXPECT_EQ(ortho.camera.height, 640);        // xmag / ymag = 1

    ortho.objects.pop_back();  // the quick look's floor (the file has no lights)
    RenderResult r = renderScene(ortho, {.width = 64, .height = 64, .samplesPerPixel = 1, .maxDepth = 0});
    Coverage c = coverage(r);
    // x in [0, 1] of a window [-0.5, 1.5]: columns 16 .. 47. The square's
    // far edge rises to y = cos(45 deg) (the file's quaternion, 0.92375 w).
    EXPECT_EQ(c.minX, 16);
    EXPECT_EQ(c.maxX, 47);
    double top = glm::mat3_cast(glm::normalize(glm::dquat(0.92375, -0.383, 0, 0)))[1][1];  // y of (0, 1, 0)
    EXPECT_EQ(c.maxY, 47);                                 // y = 0 at row 48
    EXPECT_EQ(c.minY, int(std::ceil((1.5 - top) / 2 * 64 - 0.5)));
    // The perspective camera sees it smaller (3 units away, 0.7 rad).
    perspective.objects.pop_back();
    Coverage p = coverage(renderScene(perspective, {.width = 64, .height = 64, .samplesPerPixel = 1, .maxDepth = 0}));
    double halfWidth = std::tan(0.35) * 3.0;  // the window at the square's distance
    EXPECT_NEAR(p.maxX + 1 - p.minX, 64 * 1.0 / (2 * halfWidth), 2.0);

    // The command line, with a --camera that names none.
    fs::path dir = scratch("cameras_cli");
    CommandRun run = runWhitted("render '" + model.string() + "' --camera 1 -o ortho.png --width 64 --height 64 -q --validate", dir);
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(fs::exists(dir / "ortho.png"));
    run = runWhitted("render '" + model.string() + "' --camera side -o bad.png -q", dir);
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find(model.string() + ": --camera side names no camera; the file has 0 \"node 1\", 1 \"node 2\""),
              std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

// Each KHR_lights_punctual type, placed by its node: intensity / pi,
// inverse-square falloff for point and spot, angles in degrees, the
// direction of the node's -Z. Authored lights: no quick-look lights or floor.
TEST(AuthoredGltf, EachLightTypeIsMapped) {
    fs::path dir = scratch("lights");
    Json j = squareGltf(1);
    j["extensionsUsed"] = {"KHR_lights_punctual"};
    j["extensions"]["KHR_lights_punctual"]["lights"] = Json::array(
        {{{"type", "point"}, {"name", "bulb"}, {"color", {1, 0.5, 0.25}}, {"intensity", 10}},
         {{"type", "spot"}, {"intensity", 20}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
         {{"type", "directional"}, {"name", "sun"}, {"intensity", 3}}});
    glm::dquat down = glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0));  // -Z -> -Y
    j["nodes"] = Json::array({{{"mesh", 0}},
                              {{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                              {{"name", "spot node"}, {"translation", {0, 4, 0}}, {"rotation", {down.x, down.y, down.z, down.w}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
                              {{"rotation", {down.x, down.y, down.z, down.w}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}}});
    j["scenes"] = Json::array({{{"nodes", {0, 1, 2, 3}}}});
    Scene scene = loadSceneOrModel(writeJson(dir / "lights.gltf", j));
    ASSERT_EQ(scene.lights.size(), 3u);
    EXPECT_EQ(scene.objects.size(), 1u);  // no floor
    const Light& point = scene.lights[0];
    EXPECT_EQ(point.type, Light::Type::Point);
    EXPECT_EQ(point.name, "bulb");
    EXPECT_EQ(point.position, glm::dvec3(1, 2, 3));
    EXPECT_EQ(point.color, glm::dvec3(1, 0.5, 0.25));
    EXPECT_DOUBLE_EQ(point.intensity, 10 / kPi);
    EXPECT_EQ(point.falloff, Light::Falloff::InverseSquare);
    const Light& spot = scene.lights[1];
    EXPECT_EQ(spot.type, Light::Type::Spot);
    EXPECT_EQ(spot.name, "spot node");
    EXPECT_EQ(spot.position, glm::dvec3(0, 4, 0));
    EXPECT_NEAR(glm::length(spot.direction - glm::dvec3(0, -1, 0)), 0, 1e-12);
    EXPECT_DOUBLE_EQ(spot.innerAngleDegrees, glm::degrees(0.2));
    EXPECT_DOUBLE_EQ(spot.outerAngleDegrees, glm::degrees(0.5));
    EXPECT_DOUBLE_EQ(spot.intensity, 20 / kPi);
    EXPECT_EQ(spot.falloff, Light::Falloff::InverseSquare);
    const Light& sun = scene.lights[2];
    EXPECT_EQ(sun.type, Light::Type::Directional);
    EXPECT_NEAR(glm::length(sun.direction - glm::dvec3(0, -1, 0)), 0, 1e-12);
    EXPECT_DOUBLE_EQ(sun.intensity, 3 / kPi);
    EXPECT_EQ(sun.falloff, Light::Falloff::None);

    // A spot whose outer angle is below its inner one: the file and the JSON path.
    j["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["outerConeAngle"] = 0.1;
    try {
        loadSceneOrModel(writeJson(dir / "bad_spot.gltf", j));
        FAIL() << "accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "bad_spot.gltf").string() +
                                             ": /extensions/KHR_lights_punctual/lights/1/spot: innerConeAngle must be "
                                             "below outerConeAngle");
    }
}

GltfMaterial gltfMaterial(glm::dvec3 b, double m, double r, double t = 0, double ior = 1.5) {
    GltfMaterial g;
    g.baseColorFactor = glm::dvec4(b, 1);
    g.metallicFactor = m;
    g.roughnessFactor = r;
    g.transmissionFactor = t;
    g.ior = ior;
    return g;
}

// The three anchor cases of the material mapping, exactly.
TEST(AuthoredGltf, MaterialAnchorCases) {
    const glm::dvec3 b(0.9, 0.6, 0.3);
    Material mirror = materialFromGltf(gltfMaterial(b, 1, 0));  // a mirror of colour b, no diffuse
    EXPECT_EQ(mirror.diffuse, 0.0);
    EXPECT_EQ(mirror.reflection, 1.0);
    EXPECT_EQ(mirror.specularColor, b);
    EXPECT_EQ(mirror.transmission, 0.0);
    EXPECT_EQ(mirror.ambient, 0.0);

    Material glass = materialFromGltf(gltfMaterial(glm::dvec3(1), 0, 0, 1, 1.6));  // clear glass of index 1.6
    EXPECT_EQ(glass.diffuse, 0.0);
    EXPECT_EQ(glass.transmission, 1.0);
    EXPECT_EQ(glass.ior, 1.6);
    EXPECT_TRUE(glass.fresnel);
    EXPECT_DOUBLE_EQ(glass.reflection, std::pow(0.6 / 2.6, 2));  // F0
    EXPECT_EQ(glass.specularColor, glm::dvec3(1));
    EXPECT_EQ(glass.transmissionColor, glm::dvec3(1));

    Material lambert = materialFromGltf(gltfMaterial(b, 0, 1));  // pure Lambert b
    EXPECT_EQ(lambert.diffuse, 1.0);
    EXPECT_EQ(lambert.diffuseColor, b);
    EXPECT_EQ(lambert.reflection, 0.0);
    EXPECT_EQ(lambert.specular, 0.0);
    EXPECT_EQ(lambert.transmission, 0.0);
    EXPECT_FALSE(lambert.fresnel);
    EXPECT_EQ(lambert.roughness, 0.0);  // an opaque dielectric's reflection fades instead

    // Metals and glass keep their reflection and take the roughness as their glossy lobe's.
    Material brushed = materialFromGltf(gltfMaterial(b, 1, 0.3));
    EXPECT_EQ(brushed.reflection, 1.0);
    EXPECT_EQ(brushed.roughness, 0.3);
    Material frosted = materialFromGltf(gltfMaterial(glm::dvec3(1), 0, 0.5, 1, 1.5));
    EXPECT_EQ(frosted.roughness, 0.5);
    EXPECT_TRUE(frosted.fresnel);
    EXPECT_DOUBLE_EQ(frosted.reflection, 0.04);

    // Volume: sigma = -ln(attenuationColor) / attenuationDistance; a thin
    // wall (thicknessFactor 0) does not bend.
    GltfMaterial v = gltfMaterial(glm::dvec3(1), 0, 0, 1, 1.5);
    v.hasVolume = true;
    v.thicknessFactor = 0.5;
    v.attenuationColor = {0.5, 0.25, 1.0};
    v.attenuationDistance = 2;
    Material volume = materialFromGltf(v);
    EXPECT_DOUBLE_EQ(volume.absorption.r, -std::log(0.5) / 2);
    EXPECT_DOUBLE_EQ(volume.absorption.g, -std::log(0.25) / 2);
    EXPECT_EQ(volume.absorption.b, 0.0);
    EXPECT_EQ(volume.ior, 1.5);
    v.thicknessFactor = 0;
    Material thin = materialFromGltf(v);
    EXPECT_EQ(thin.ior, 1.0);
    EXPECT_EQ(thin.absorption, glm::dvec3(0));

    // Emission: emissiveFactor times emissiveStrength, times the
    // emissiveTexture (the emission texture).
    GltfMaterial e = gltfMaterial(b, 0, 1);
    e.emissiveFactor = {0.5, 0.25, 1.0};
    e.emissiveStrength = 2;
    e.emissiveTexture = std::make_shared<TextureData>();
    Material emissive = materialFromGltf(e);
    EXPECT_EQ(emissive.emission, glm::dvec3(1.0, 0.5, 2.0));
    EXPECT_EQ(emissive.emissionTexture.data, e.emissiveTexture);
    EXPECT_FALSE(lambert.emissionTexture);

    // metallicRoughnessTexture: its green channel times roughnessFactor is
    // the roughness (the <roughness_texture>), where the roughness is the
    // glossy lobe's: metals and glass, not an opaque dielectric.
    auto roughTextured = [](GltfMaterial g) {
        g.metallicRoughnessTexture = std::make_shared<TextureData>();
        return std::pair(materialFromGltf(g), g.metallicRoughnessTexture);
    };
    auto [metal, metalTexture] = roughTextured(gltfMaterial(b, 1, 0.6));
    EXPECT_EQ(metal.roughness, 0.6);
    EXPECT_EQ(metal.roughnessTexture.data, metalTexture);
    auto [frostedTextured, frostedTexture] = roughTextured(gltfMaterial(glm::dvec3(1), 0, 0.5, 1, 1.5));
    EXPECT_EQ(frostedTextured.roughnessTexture.data, frostedTexture);
    EXPECT_FALSE(roughTextured(gltfMaterial(b, 0, 1)).first.roughnessTexture);  // dielectric: no lobe
    EXPECT_FALSE(roughTextured(gltfMaterial(b, 1, 0)).first.roughnessTexture);  // roughnessFactor 0: a mirror
}

// Volume attenuation rendered: an orthographic view through a slab of
// absorbing glass that does not bend (ior 1), thickness d, in front of an
// emissive-free white Lambert square lit head-on; behind the slab the
// square's light is scaled by exp(-sigma d) per channel.
TEST(AuthoredGltf, VolumeAttenuationIsExpMinusSigmaD) {
    const double d = 0.5, sigmaSource = 2.0;  // attenuationDistance
    const glm::dvec3 colour(0.5, 0.8, 1.0);
    // The slab is a whitted box (a glTF mesh of two squares would not be
    // closed); its material is the glTF mapping's.
    GltfMaterial g = gltfMaterial(glm::dvec3(1), 0, 0, 1, 1.0);
    g.hasVolume = true;
    g.thicknessFactor = d;
    g.attenuationColor = colour;
    g.attenuationDistance = sigmaSource;
    Material glass = materialFromGltf(g);
    EXPECT_EQ(glass.ior, 1.0);
    EXPECT_TRUE(glass.fresnel);  // F0 0 (index 1): no reflection head-on
    EXPECT_EQ(glass.reflection, 0.0);
    EXPECT_EQ(glass.roughness, 0.0);
    Scene scene;
    scene.ambientLight = glm::dvec3(1);
    scene.camera.eye = {0, 0, 5};
    scene.camera.windowCenter = {0, 0, 4};
    scene.camera.projection = Camera::Projection::Orthographic;
    scene.camera.windowHeight = 2;
    Object back;  // white, ambient only: exactly 1 where seen directly
    back.shape = Plane{{0, 0, -1}, {0, 0, 1}};
    back.material.ambient = 1;
    back.material.diffuse = 0;
    scene.objects.push_back(back);
    Object slab;
    slab.shape = Box{{-2, 0, 0}, {2, 2, d}};  // covers the upper half of the image
    slab.material = glass;
    scene.objects.push_back(slab);
    RenderResult r = renderScene(scene, {.width = 32, .height = 32, .samplesPerPixel = 1, .maxDepth = 4});
    glm::vec4 seen = pixel(r, gpu::kAovColor, 16, 8), direct = pixel(r, gpu::kAovColor, 16, 24);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(direct[c], 1.0, 1e-5);
        EXPECT_NEAR(seen[c], std::exp(-(-std::log(colour[c]) / sigmaSource) * d), 1e-4) << "channel " << c;
    }
}

// One mesh used by two nodes renders at each.
TEST(AuthoredGltf, MeshInstancedByTwoNodes) {
    fs::path dir = scratch("instances");
    Json j = squareGltf(1);
    j["nodes"] = Json::array({{{"name", "left"}, {"translation", {-1, 0, 0}}, {"mesh", 0}},
                              {{"name", "right"}, {"translation", {2, 0, 0}}, {"scale", {1, 2, 1}}, {"mesh", 0}}});
    Scene scene = loadSceneOrModel(writeJson(dir / "instances.gltf", j));
    ASSERT_EQ(scene.objects.size(), 3u);  // two instances and the floor
    EXPECT_EQ(scene.objects[0].name, "left");
    EXPECT_EQ(scene.objects[1].name, "right");
    const Mesh& left = std::get<Mesh>(scene.objects[0].shape);
    const Mesh& right = std::get<Mesh>(scene.objects[1].shape);
    ASSERT_EQ(left.triangles.size(), 2u);
    ASSERT_EQ(right.triangles.size(), 2u);
    EXPECT_EQ(left.triangles[0].v0, glm::dvec3(-1.5, -0.5, 0));
    EXPECT_EQ(right.triangles[0].v0, glm::dvec3(1.5, -1, 0));
    EXPECT_EQ(right.triangles[0].v2, glm::dvec3(2.5, 1, 0));
    scene.objects.pop_back();
    RenderResult r = renderScene(scene, {.width = 96, .height = 64, .samplesPerPixel = 1, .maxDepth = 0});
    int leftHits = 0, rightHits = 0;
    Coverage c = coverage(r);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x)
            if (pixel(r, gpu::kAovCoefs1, x, y).w > 0) (x < 48 ? leftHits : rightHits)++;
    EXPECT_GT(leftHits, 20);
    EXPECT_GT(rightHits, 2 * leftHits * 0.8);  // twice as tall
    EXPECT_GT(c.hits, 0);
}

// A glTF error names the file and the JSON path; a missing buffer file too.
TEST(AuthoredGltf, BadFilesNameTheJsonPath) {
    fs::path dir = scratch("bad");
    Json j = squareGltf(1);
    j["nodes"] = Json::array({{{"mesh", 0}}});
    j["materials"] = Json::array({{{"pbrMetallicRoughness", {{"metallicFactor", 2}}}}});
    CommandRun run = runWhitted("render '" + writeJson(dir / "metal.gltf", j).string() + "' -o out.png -q", dir);
    EXPECT_EQ(run.status, 2);
    EXPECT_NE(run.output.find("metal.gltf: /materials/0/pbrMetallicRoughness/metallicFactor: is 2; it must be in [0, 1]"),
              std::string::npos) << run.output;
    j.erase("materials");
    j["buffers"][0]["uri"] = "missing.bin";
    run = runWhitted("render '" + writeJson(dir / "buffer.gltf", j).string() + "' -o out.png -q", dir);
    EXPECT_EQ(run.status, 2);
    EXPECT_NE(run.output.find("buffer.gltf: /buffers/0/uri: names \"missing.bin\", which does not exist"), std::string::npos)
        << run.output;
    EXPECT_FALSE(fs::exists(dir / "out.png"));
}

// ---- OBJ / MTL ----

// Rendered glTF lights: a Lambert floor (albedo rho, m = 0, r = 1) of the
// square mesh turned to face +y, seen straight down by an orthographic
// camera (pixel (x, y) sees the floor point (-2 + 4 (x + 0.5) / 64, 0,
// -2 + 4 (y + 0.5) / 64)), ambient 0. `lights` are KHR_lights_punctual
// lights, `lightNodes` their nodes; `plate` adds a 1 x 1 square at y = 1
// above the origin.
RenderResult renderGltfFloor(const fs::path& path, const Json& lights, const Json& lightNodes, bool plate, double rho) {
    Json j = squareGltf(1);
    j["extensionsUsed"] = {"KHR_lights_punctual"};
    j["extensions"]["KHR_lights_punctual"]["lights"] = lights;
    j["materials"] = Json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {rho, rho, rho, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}}});
    j["meshes"][0]["primitives"][0]["material"] = 0;
    glm::dquat faceUp = glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0));  // +z -> +y, -z -> -y
    Json rotation = {faceUp.x, faceUp.y, faceUp.z, faceUp.w};
    j["cameras"] = Json::array({{{"type", "orthographic"}, {"orthographic", {{"xmag", 2}, {"ymag", 2}, {"znear", 0.1}, {"zfar", 100}}}}});
    j["nodes"] = Json::array({{{"name", "floor"}, {"mesh", 0}, {"scale", {4, 4, 4}}, {"rotation", rotation}},
                              {{"name", "eye"}, {"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", rotation}}});
    Json roots = {0, 1};
    if (plate) {
        j["nodes"].push_back({{"name", "plate"}, {"mesh", 0}, {"translation", {0, 1, 0}}, {"rotation", rotation}});
        roots.push_back(2);
    }
    for (const Json& node : lightNodes) {
        roots.push_back(j["nodes"].size());
        j["nodes"].push_back(node);
    }
    j["scenes"] = Json::array({{{"nodes", roots}}});
    Scene scene = loadSceneOrModel(writeJson(path, j));
    return renderScene(scene, {.width = 64, .height = 64, .samplesPerPixel = 1, .maxDepth = 2,
                               .antiAliasing = AntiAliasing::Uniform});
}

glm::dvec3 floorPoint(int x, int y) { return {-2 + 4 * (x + 0.5) / 64, 0, -2 + 4 * (y + 0.5) / 64}; }

// A glTF spot light of I candela straight down from height h over the
// floor: radiance rho / pi * E, E = I cos(incidence) / d^2 times the cone's
// saturate((cos theta - cos outer) / (cos inner - cos outer))^2 (the
// specification's formulas, whitted's intensity being I / pi); right under
// it rho / pi * I / h^2.
TEST(AuthoredGltfRender, SpotConeAndRadianceRhoOverPiE) {
    const double rho = 0.5, candela = 6, inner = 0.3, outer = 0.6;
    const glm::dvec3 light(0.3, 2, -0.2);
    glm::dquat down = glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0));  // -Z -> -Y
    Json lights = Json::array({{{"type", "spot"}, {"intensity", candela}, {"spot", {{"innerConeAngle", inner}, {"outerConeAngle", outer}}}}});
    Json nodes = Json::array({{{"translation", {light.x, light.y, light.z}}, {"rotation", {down.x, down.y, down.z, down.w}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}});
    RenderResult r = renderGltfFloor(scratch("spot_render") / "spot.gltf", lights, nodes, false, rho);
    ASSERT_EQ(r.width, 64);
    int inside = 0, ramp = 0, outside = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            glm::dvec3 toLight = light - floorPoint(x, y);
            double d = glm::length(toLight), cosTheta = toLight.y / d;  // the spot's axis is -y, the floor's normal +y
            double s = std::clamp((cosTheta - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0, 1.0);
            double expected = rho / kPi * candela * cosTheta / (d * d) * s * s;
            glm::vec4 got = pixel(r, gpu::kAovColor, x, y);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected, 2e-4 * std::max(1.0, expected)) << x << "," << y;
            (s >= 1 ? inside : s <= 0 ? outside : ramp) += 1;
        }
    EXPECT_GT(inside, 100);
    EXPECT_GT(ramp, 300);
    EXPECT_GT(outside, 300);
    // Under the light (pixel (37, 28) sees (0.34375, 0, -0.1875), 0.046 off the axis: cos 0.9997, d^2 4.002).
    EXPECT_NEAR(pixel(r, gpu::kAovColor, 37, 28).g, rho / kPi * candela / (light.y * light.y), 1e-3);
}

// A glTF directional light of E lux travelling along t: the floor shows
// rho / pi * E * cos(incidence) except in the plate's shadow, the plate
// (|x|, |z| <= 0.5 at y = 1) moved along t to the floor: exactly the points
// whose ray towards the light meets it. Pixels within 1e-3 of the outline
// are too close to call; pixels that see the plate are left out.
TEST(AuthoredGltfRender, DirectionalShadowHasThePlatesProjectedOutline) {
    const double rho = 0.8, lux = 2;
    const glm::dvec3 travel = glm::normalize(glm::dvec3(0.45, -1, 0.3));
    // The node's rotation takes -Z to `travel`: about the axis -Z x travel.
    glm::dvec3 axis = glm::cross(glm::dvec3(0, 0, -1), travel);
    glm::dquat q = glm::angleAxis(std::acos(glm::dot(glm::dvec3(0, 0, -1), travel)), glm::normalize(axis));
    Json lights = Json::array({{{"type", "directional"}, {"intensity", lux}}});
    Json nodes = Json::array({{{"rotation", {q.x, q.y, q.z, q.w}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}});
    RenderResult r = renderGltfFloor(scratch("sun_render") / "sun.gltf", lights, nodes, true, rho);
    ASSERT_EQ(r.width, 64);
    int shadowed = 0, lit = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            glm::dvec3 p = floorPoint(x, y);
            if (std::abs(p.x) <= 0.5 + 1e-3 && std::abs(p.z) <= 0.5 + 1e-3) continue;  // sees the plate
            glm::dvec3 atPlate = p - travel * (1.0 / -travel.y);  // towards the light, up to y = 1
            double margin = std::max(std::abs(atPlate.x), std::abs(atPlate.z)) - 0.5;  // < 0: through the plate
            if (std::abs(margin) < 1e-3) continue;
            double expected = margin < 0 ? 0.0 : rho / kPi * lux * -travel.y;
            EXPECT_NEAR(pixel(r, gpu::kAovColor, x, y).r, expected, 2e-4) << x << "," << y;
            (margin < 0 ? shadowed : lit) += 1;
        }
    EXPECT_GT(shadowed, 100);
    EXPECT_GT(lit, 1500);
}

// A generated OBJ/MTL with illum 2, 3, 5, 6 and 7 objects: the mapped
// values, the mirror showing the object in front of it, the glass bending.
TEST(AuthoredObj, IlluminationModelsAreMapped) {
    fs::path dir = scratch("illum");
    writeIlluminationObj(dir);  // plastic, mirror, fresnel_mirror, glass, fresnel_glass
    Scene scene = loadSceneOrModel(dir / "scene.obj");
    ASSERT_EQ(scene.objects.size(), 6u);  // five materials and the floor
    auto find = [&](const std::string& name) -> const Material& {
        for (const Object& o : scene.objects)
            if (o.name == name) return o.material;
        throw std::runtime_error("no object " + name);
    };
    const Material& plastic = find("plastic");
    EXPECT_EQ(plastic.diffuseColor, glm::dvec3(0.8, 0.2, 0.2));
    EXPECT_EQ(plastic.specular, 1.0);
    EXPECT_EQ(plastic.specularColor, glm::dvec3(0.5));
    EXPECT_EQ(plastic.shininess, 50.0);
    EXPECT_EQ(plastic.reflection, 0.0);
    EXPECT_EQ(plastic.ambient, 0.1);
    EXPECT_EQ(plastic.ambientColor, glm::dvec3(1));
    const Material& mirror = find("mirror");
    EXPECT_EQ(mirror.reflection, 1.0);
    EXPECT_EQ(mirror.specularColor, glm::dvec3(0.9));
    EXPECT_FALSE(mirror.fresnel);
    const Material& fm = find("fresnel_mirror");
    EXPECT_TRUE(fm.fresnel);
    EXPECT_DOUBLE_EQ(fm.reflection, 1.0 / 9.0);  // ((2 - 1) / (2 + 1))^2
    EXPECT_EQ(fm.transmission, 0.0);
    const Material& glass = find("glass");
    EXPECT_EQ(glass.transmission, 1.0);
    EXPECT_EQ(glass.ior, 1.5);
    EXPECT_FALSE(glass.fresnel);
    EXPECT_EQ(glass.reflection, 1.0);
    EXPECT_NEAR(glm::length(glass.transmissionColor - glm::dvec3(0.9, 0.81, 0.72)), 0, 1e-12);  // (1 - Ks) Tf
    const Material& fg = find("fresnel_glass");
    EXPECT_TRUE(fg.fresnel);
    EXPECT_EQ(fg.ior, 1.33);
    EXPECT_DOUBLE_EQ(fg.reflection, std::pow(0.33 / 2.33, 2));
    EXPECT_TRUE(fg.diffuseTexture) << "a path with a space and a backslash";
}

// <file>scene.obj</file> in a scene file, without a colour of its own,
// takes the MTL's materials exactly as `whitted render scene.obj` maps them
// (one object per material, illum models included), and so does spider.obj,
// whose Windows texture paths Assimp alone refuses.
TEST(AuthoredObj, FileInASceneTakesTheMtlMaterials) {
    fs::path dir = scratch("file_mtl");
    fs::path obj = writeIlluminationObj(dir);
    for (const fs::path& model : {obj, assimpTestModel("OBJ/spider.obj")}) {
        std::ofstream(dir / "s.xml") << "<scene><camera><position x=\"0\" y=\"0\" z=\"5\"/><window_position x=\"0\" "
                                        "y=\"0\" z=\"4\"/></camera><lights/><objects><object><properties><type>mesh</type>"
                                        "<file>" << model.string() << "</file></properties></object></objects></scene>";
        Scene xml = loadScene(dir / "s.xml");
        Scene authored = loadSceneOrModel(model);
        std::vector<const Object*> meshes;
        for (const Object& o : authored.objects)
            if (std::holds_alternative<Mesh>(o.shape)) meshes.push_back(&o);
        ASSERT_EQ(xml.objects.size(), meshes.size()) << model;
        for (size_t k = 0; k < meshes.size(); ++k) {
            const Material &a = xml.objects[k].material, &b = meshes[k]->material;
            EXPECT_EQ(xml.objects[k].name, meshes[k]->name);
            EXPECT_EQ(a.diffuseColor, b.diffuseColor) << meshes[k]->name;
            EXPECT_EQ(a.specularColor, b.specularColor) << meshes[k]->name;
            EXPECT_EQ(std::tie(a.ambient, a.diffuse, a.specular, a.shininess, a.reflection, a.transmission, a.ior, a.fresnel),
                      std::tie(b.ambient, b.diffuse, b.specular, b.shininess, b.reflection, b.transmission, b.ior, b.fresnel))
                << meshes[k]->name;
            EXPECT_EQ(a.transmissionColor, b.transmissionColor) << meshes[k]->name;
            EXPECT_EQ(bool(a.diffuseTexture), bool(b.diffuseTexture)) << meshes[k]->name;
            EXPECT_EQ(std::get<Mesh>(xml.objects[k].shape).triangles.size(), std::get<Mesh>(meshes[k]->shape).triangles.size());
        }
    }
}

// Rendered: a red square in front of an illum 3 mirror is seen in it; a
// stripe behind an illum 6 glass sphere appears displaced.
TEST(AuthoredObj, MirrorShowsTheObjectInFrontAndGlassRefracts) {
    fs::path dir = scratch("mirror");
    std::ofstream(dir / "m.mtl") << "newmtl red\nKa 1 0 0\nKd 1 0 0\nillum 1\n"
                                    "newmtl mirror\nKa 0 0 0\nKd 0 0 0\nKs 1 1 1\nillum 3\n";
    // The mirror: the plane z = 0 (x, y in [-2, 2]); the red square at z = 2,
    // small, off the camera's axis so that the camera sees it only in the mirror.
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\nusemtl mirror\n"
                                    "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nf 1 2 3 4\n"
                                    "usemtl red\nv -0.3 -0.3 2\nv 0.3 -0.3 2\nv 0.3 0.3 2\nv -0.3 0.3 2\nf 5 6 7 8\n";
    Scene scene = loadSceneOrModel(dir / "m.obj");
    scene.objects.pop_back();  // no floor
    scene.lights = {Light{.position = {0, 0, 3}, .color = glm::dvec3(1)}};
    // The camera off the axis: it sees the square itself (ambient Ka red,
    // both sides) and, nearer the middle, its mirror image at z = -2.
    scene.camera.eye = {1.2, 0, 6};
    scene.camera.windowCenter = {1.2, 0, 5};
    scene.camera.up = {0, 1, 0};
    scene.camera.verticalFovDegrees = 40;
    RenderResult r = renderScene(scene, {.width = 64, .height = 64, .samplesPerPixel = 1, .maxDepth = 2, .auxiliary = true});
    // The reflection of the square's centre: the mirror image (0, 0, -2)
    // seen from (1.2, 0, 6): ndc x = (0 - 1.2) / 8 / tan 20.
    int rx = int(32 + (-1.2 / 8.0) / std::tan(glm::radians(20.0)) * 32);
    glm::vec4 reflected = pixel(r, gpu::kAovReflection, rx, 32);
    EXPECT_GT(reflected.r, 0.2) << "the mirror does not show the red square";
    EXPECT_LT(reflected.g, 0.01);
    // The square itself sits at ndc x = (0 - 1.2) / 4 / tan 20, further out.
    int sx = int(32 + (-1.2 / 4.0) / std::tan(glm::radians(20.0)) * 32);
    EXPECT_GT(pixel(r, gpu::kAovAmbient, sx, 32).r, 0.5);
    EXPECT_NE(sx, rx);

    // Glass (illum 6, Ni 1.5) bends: the same slab with ior 1 lets the
    // camera see through straight; with 1.5 the transmission differs.
    std::ofstream(dir / "g.mtl") << "newmtl back\nKa 0 0 0\nKd 1 1 1\nillum 1\nmap_Kd quad.png\n"
                                    "newmtl glass\nKa 0 0 0\nKd 0 0 0\nKs 0 0 0\nNi 1.5\nillum 6\n";
    writeQuadrantTexture(dir / "quad.png");
    std::ofstream(dir / "g.obj") << "mtllib g.mtl\nusemtl back\n"
                                    "v -2 -2 -1\nv 2 -2 -1\nv 2 2 -1\nv -2 2 -1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                    "f 1/1 2/2 3/3 4/4\nusemtl glass\n"
                                    "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0.8\nv -0.5 0.5 0.8\nf 5 6 7 8\n";
    Scene g = loadSceneOrModel(dir / "g.obj");
    g.objects.pop_back();
    g.lights = {Light{.position = {0, 0, 5}, .color = glm::dvec3(1)}};
    g.camera = scene.camera;
    g.camera.eye = {0, 0, 6};
    g.camera.windowCenter = {0, 0, 5};
    RenderSettings s{.width = 64, .height = 64, .samplesPerPixel = 1, .maxDepth = 3, .auxiliary = true};
    RenderResult bent = renderScene(g, s);
    for (Object& o : g.objects)
        if (o.name == "glass") o.material.ior = 1.0;
    RenderResult straight = renderScene(g, s);
    int differ = 0;
    for (int y = 20; y < 44; ++y)
        for (int x = 20; x < 44; ++x)
            differ += glm::length(pixel(bent, gpu::kAovTransmission, x, y) - pixel(straight, gpu::kAovTransmission, x, y)) > 0.05f;
    EXPECT_GT(differ, 20) << "the glass does not refract";
}

// spider.obj (assimp-testmodels): its MTL writes Windows paths; it renders
// with its textures.
TEST(AuthoredObj, SpiderRendersTextured) {
    fs::path model = assimpTestModel("OBJ/spider.obj");
    ASSERT_TRUE(fs::exists(model)) << "missing: install assimp-testmodels (tools/install_deps.sh --all)";
    Scene scene = loadSceneOrModel(model);
    ASSERT_GE(scene.objects.size(), 5u);  // its parts (one per material used) and the floor
    for (size_t i = 0; i + 1 < scene.objects.size(); ++i) {
        EXPECT_TRUE(scene.objects[i].material.diffuseTexture) << scene.objects[i].name;
        EXPECT_FALSE(std::get<Mesh>(scene.objects[i].shape).uvs.empty()) << scene.objects[i].name;
    }
    fs::path dir = scratch("spider");
    CommandRun run = runWhitted("render '" + model.string() + "' -o spider.png --width 160 --height 120 -q --validate", dir);
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(fs::exists(dir / "spider.png"));
}

// A texture that really is missing: the MTL's file and line, exit 2.
TEST(AuthoredObj, MissingTextureNamesItsLine) {
    fs::path dir = scratch("missing_texture");
    std::ofstream(dir / "t.mtl") << "newmtl a\nKd 1 1 1\nmap_Kd .\\nowhere.png\n";
    std::ofstream(dir / "t.obj") << "mtllib t.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CommandRun run = runWhitted("render t.obj -o out.png -q", dir);
    EXPECT_EQ(run.status, 2);
    EXPECT_NE(run.output.find("t.mtl:3: texture \".\\nowhere.png\" does not exist"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(dir / "out.png"));
    run = runWhitted("render t.obj --camera 0 -o out.png -q", dir);
    EXPECT_EQ(run.status, 2);
}

// ---- cameras in XML, exposure ----

const char* kOrthoXml = R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
  <projection>orthographic</projection><window_height>4</window_height><width>40</width><height>40</height></camera>
  <lights><light><position x="0" y="0" z="10"/><color r="1" g="1" b="1"/></light></lights>
  <objects><object><position x="0" y="0" z="-20"/><properties><type>sphere</type><radius>1</radius>
  <ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object></objects></scene>)";

// An orthographic XML camera: a unit sphere far away still covers a disc of
// radius 1 in a window 4 high (10 pixels per unit of 40), as no perspective would.
TEST(AuthoredCamera, OrthographicXmlCamera) {
    Scene scene = loadSceneFromString(kOrthoXml, "ortho.xml");
    EXPECT_EQ(scene.camera.projection, Camera::Projection::Orthographic);
    EXPECT_EQ(scene.camera.windowHeight, 4.0);
    RenderResult r = renderScene(scene, {.samplesPerPixel = 1, .maxDepth = 0});
    Coverage c = coverage(r);
    EXPECT_EQ(c.minX, 10);
    EXPECT_EQ(c.maxX, 29);
    EXPECT_NEAR(c.hits, kPi * 100, 12);
    std::string bad = kOrthoXml;
    bad.replace(bad.find("orthographic"), 12, "fisheye");
    try {
        loadSceneFromString(bad, "bad.xml");
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()), "bad.xml:2: <projection> must be perspective or orthographic, got \"fisheye\"");
    }
}

// --exposure scales the image and the colour components alike, in EXR
// files too, so that they still add up; coefficients are not scaled.
TEST(AuthoredCamera, ExposureScalesColourImages) {
    fs::path dir = scratch("exposure");
    std::ofstream(dir / "s.xml") << kOrthoXml;
    for (const char* ev : {"0", "1.5"}) {
        CommandRun run = runWhitted(std::string("render s.xml --exposure ") + ev + " -o e" + ev +
                                        ".exr --aov ambient,ambient_coef --spp 1 -q", dir);
        ASSERT_EQ(run.status, 0) << run.output;
    }
    auto read = [&](const std::string& name) {
        std::vector<float> v;
        int w = 0, h = 0, c = 0;
        readImageInto(dir / name, w, h, c, v);
        return v;
    };
    std::vector<float> a = read("e0.exr"), b = read("e1.5.exr"), aa = read("e0.ambient.exr"), ba = read("e1.5.ambient.exr");
    std::vector<float> ak = read("e0.ambient_coef.exr"), bk = read("e1.5.ambient_coef.exr");
    float scale = std::exp2(1.5f);
    int lit = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(b[i], a[i] * scale);
        EXPECT_EQ(ba[i], aa[i] * scale);
        lit += a[i] > 0;
    }
    EXPECT_GT(lit, 100);
    EXPECT_EQ(ak, bk);
    // The record beside each image keeps the exposure (and the --camera choice).
    for (const auto& [name, ev] : {std::pair{"e0.json", 0.0}, std::pair{"e1.5.json", 1.5}}) {
        Json record = Json::parse(std::ifstream(dir / name));
        EXPECT_EQ(record["settings"]["exposure"], ev) << name;
        EXPECT_EQ(record["settings"]["camera"], "") << name;
    }
    ASSERT_EQ(runWhitted("render s.xml --camera 0 --exposure -2 -o c.png --spp 1 -q", dir).status, 0);
    Json record = Json::parse(std::ifstream(dir / "c.json"));
    EXPECT_EQ(record["settings"]["exposure"], -2.0);
    EXPECT_EQ(record["settings"]["camera"], "0");
}

}  // namespace
}  // namespace whitted::test

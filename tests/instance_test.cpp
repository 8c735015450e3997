// Instances (scenes/README.md "Instances"): the loader and writer of
// <prototypes> and <instances>, and renders of instances against the same
// scene with each instance flattened into a world-space mesh object.
#include "render/renderer.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"

#include <glm/gtc/matrix_transform.hpp>

#include <bit>
#include <cmath>
#include <iostream>
#include <set>
#include <string>

namespace whitted {
namespace {

using test::renderScene;

// ---- The scene format ----

const std::string kHead =
    "<scene>\n<camera><position x=\"0\" y=\"0\" z=\"5\"/><window_position x=\"0\" y=\"0\" z=\"4\"/></camera>\n"
    "<lights/>\n<objects/>\n";  // lines 1-4
const std::string kPrototype =
    "<prototypes><prototype><name>tri</name><objects><object><properties><type>triangle</type>"
    "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/>"
    "</properties></object></objects></prototype></prototypes>\n";  // line 5

std::string errorOf(const std::string& xml) {
    try {
        loadSceneFromString(xml, "t.xml");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

TEST(InstanceLoader, ReadsPrototypesAndInstancesAndWritesThemBack) {
    Scene scene = loadSceneFromString(kHead + kPrototype +
                                          "<instances>\n"
                                          "<instance><prototype>tri</prototype><name>a</name>"
                                          "<position x=\"1\" y=\"2\" z=\"3\"/>"
                                          "<scale x=\"2\" y=\"1\" z=\"1\"/></instance>\n"
                                          "<instance><prototype>tri</prototype>"
                                          "<matrix>-1 0 0 0  0 1 0 0  0 0 1 0.5</matrix>"
                                          "<diffuse_color r=\"1\" g=\"0\" b=\"0\"/><properties>"
                                          "<transmission_coef>0.5</transmission_coef></properties></instance>\n"
                                          "</instances></scene>",
                                      "t.xml");
    ASSERT_EQ(scene.prototypes.size(), 1u);
    EXPECT_EQ(scene.prototypes[0].name, "tri");
    ASSERT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.instances[0].name, "a");
    EXPECT_EQ(scene.instances[0].worldFromObject * glm::dvec4(1, 1, 0, 1), glm::dvec4(3, 3, 3, 1));
    EXPECT_FALSE(scene.instances[0].material);
    EXPECT_EQ(scene.instances[1].worldFromObject * glm::dvec4(1, 1, 0, 1), glm::dvec4(-1, 1, 0.5, 1));
    ASSERT_TRUE(scene.instances[1].material);
    EXPECT_EQ(scene.instances[1].material->diffuseColor, glm::dvec3(1, 0, 0));
    EXPECT_EQ(scene.instances[1].material->transmission, 0.5);
    // Instances count as objects: no "scene has no objects" warning.
    for (const std::string& w : scene.warnings) EXPECT_EQ(w.find("no objects"), std::string::npos) << w;

    // The writer's text loads back to the same instances and writes the same text again.
    std::string xml = sceneXml(scene);
    Scene again = loadSceneFromString(xml, "again.xml");
    ASSERT_EQ(again.instances.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(again.instances[i].worldFromObject, scene.instances[i].worldFromObject);
        EXPECT_EQ(again.instances[i].name, scene.instances[i].name);
        EXPECT_EQ(bool(again.instances[i].material), bool(scene.instances[i].material));
    }
    EXPECT_EQ(sceneXml(again), xml);
}

struct BadCase {
    const char* name;
    std::string body;  // from line 5
    std::string message;
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class InstanceLoaderError : public ::testing::TestWithParam<BadCase> {};

TEST_P(InstanceLoaderError, GivesFileLineAndWhat) {
    EXPECT_EQ(errorOf(kHead + GetParam().body + "</scene>"), GetParam().message);
}

const std::string kTriangle =
    "<object><properties><type>triangle</type><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/>"
    "<vertex x=\"0\" y=\"1\" z=\"0\"/></properties></object>";

INSTANTIATE_TEST_SUITE_P(
    Cases, InstanceLoaderError,
    ::testing::Values(
        BadCase{"UnknownPrototype",
                kPrototype + "<instances>\n<instance>\n<prototype>tree</prototype></instance></instances>",
                "t.xml:8: <prototype> \"tree\" is not one of the scene's <prototypes>"},
        BadCase{"InstanceWithoutPrototypes", "<instances>\n<instance><prototype>tri</prototype></instance></instances>",
                "t.xml:6: <prototype> \"tri\" is not one of the scene's <prototypes>"},
        BadCase{"SingularMatrix",
                kPrototype + "<instances>\n<instance><prototype>tri</prototype>\n"
                             "<matrix>1 0 0 0 0 0 0 0 0 0 1 0</matrix></instance></instances>",
                "t.xml:8: <matrix> is singular: its 3×3 part has determinant 0"},
        BadCase{"MatrixAndScale",
                kPrototype + "<instances>\n<instance><prototype>tri</prototype><matrix>1 0 0 0 0 1 0 0 0 0 1 0</matrix>"
                             "\n<scale>2</scale></instance></instances>",
                "t.xml:8: <instance> has both <matrix> and <scale>; an instance takes one"},
        BadCase{"SphereInPrototype",
                "<prototypes><prototype><name>s</name><objects>\n<object><position x=\"0\" y=\"0\" z=\"0\"/>"
                "<properties><type>sphere</type><radius>1</radius></properties></object></objects></prototype>"
                "</prototypes>",
                "t.xml:6: a <prototype> holds meshes and triangles only, got type sphere"},
        BadCase{"DuplicatePrototype",
                "<prototypes><prototype><name>a</name><objects>" + kTriangle +
                    "</objects></prototype>\n<prototype><name>a</name><objects>" + kTriangle +
                    "</objects></prototype></prototypes>",
                "t.xml:6: a second <prototype> named \"a\" (the first on line 5)"},
        BadCase{"EmptyPrototype", "<prototypes><prototype><name>a</name>\n<objects/></prototype></prototypes>",
                "t.xml:6: <objects> of a <prototype> holds no <object>; it needs at least one"},
        BadCase{"ShapeInInstanceProperties",
                kPrototype + "<instances><instance><prototype>tri</prototype><properties>\n<radius>1</radius>"
                             "</properties></instance></instances>",
                "t.xml:7: <radius> does not apply to an <instance>; only material elements do"},
        BadCase{"ColourWithoutProperties",
                kPrototype + "<instances><instance><prototype>tri</prototype>\n<diffuse_color r=\"1\" g=\"0\" b=\"0\"/>"
                             "</instance></instances>",
                "t.xml:7: <diffuse_color> of an <instance> needs <properties> beside it (its own material)"},
        BadCase{"UnknownElement",
                kPrototype + "<instances><instance><prototype>tri</prototype>\n<colour/></instance></instances>",
                "t.xml:7: unknown element <colour> in <instance>; expected one of: prototype, name, position, matrix, "
                "scale, rotation, diffuse_color, specular_color, properties"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

// ---- Instances equal flattened copies ----

// A closed mesh with vertex normals: an octahedron's eight faces each split
// into four (32 triangles), vertices pushed out towards a sphere so the
// vertex normals differ from the faces'.
Mesh gem() {
    const glm::dvec3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    Mesh mesh;
    auto push = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
        glm::dvec3 p[3] = {glm::normalize(a), glm::normalize(b), glm::normalize(c)};
        mesh.triangles.push_back({0.8 * p[0] + 0.2 * a, 0.8 * p[1] + 0.2 * b, 0.8 * p[2] + 0.2 * c});
        mesh.normals.push_back({p[0], p[1], p[2]});
    };
    for (const auto& f : faces) {
        glm::dvec3 a = v[f[0]], b = v[f[1]], c = v[f[2]];
        glm::dvec3 ab = (a + b) / 2.0, bc = (b + c) / 2.0, ca = (c + a) / 2.0;
        push(a, ab, ca);
        push(ab, b, bc);
        push(ca, bc, c);
        push(ab, bc, ca);
    }
    return mesh;
}

// The prototype's mesh placed as the loader places a mesh under a <matrix>:
// vertices through M, normals through its inverse transpose, the winding
// turned over where M mirrors.
Mesh flattened(const Mesh& mesh, const glm::dmat4& m) {
    glm::dmat3 linear(m), normalLinear = glm::transpose(glm::inverse(linear));
    bool flip = glm::determinant(linear) < 0;
    Mesh out;
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        const Triangle& t = mesh.triangles[i];
        auto point = [&](const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); };
        Triangle w{point(t.v0), point(t.v1), point(t.v2)};
        std::array<glm::dvec3, 3> n;
        for (int k = 0; k < 3; ++k) n[size_t(k)] = glm::normalize(normalLinear * mesh.normals[i][size_t(k)]);
        if (flip) {
            std::swap(w.v1, w.v2);
            std::swap(n[1], n[2]);
        }
        out.triangles.push_back(w);
        out.normals.push_back(n);
    }
    return out;
}

glm::dmat4 placement(glm::dvec3 position, glm::dvec3 degrees, glm::dvec3 scale) {
    glm::dmat4 m(1.0);
    m = glm::translate(m, position);
    m = glm::rotate(m, glm::radians(degrees.z), glm::dvec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(degrees.y), glm::dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(degrees.x), glm::dvec3(1, 0, 0));
    return glm::scale(m, scale);
}

// A floor and four instances of the gem: rotated, scaled non-uniformly,
// mirrored (a negative determinant), and one of glass with absorption (its
// own material); `flat` writes each instance as a mesh object instead.
Scene gemScene(bool flat) {
    Scene scene;
    scene.camera.eye = {0, 2.2, 5.5};
    scene.camera.windowCenter = {0, 1.7, 4.6};
    scene.ambientLight = {0.3, 0.3, 0.3};
    scene.lights.push_back({.position = {3, 6, 5}});
    scene.lights.push_back({.position = {-4, 5, 2}, .color = {0.5, 0.5, 0.6}});
    Material floor;
    floor.diffuseColor = {0.6, 0.6, 0.6};
    floor.ambient = 0.2;
    scene.objects.push_back({.shape = Plane{{0, -0.6, 0}, {0, 1, 0}}, .material = floor});
    const Material copper{.diffuseColor = {0.8, 0.4, 0.2}, .ambient = 0.1, .diffuse = 0.7, .specular = 0.4,
                          .reflection = 0.2};
    const Material glass{.diffuseColor = {0.9, 0.95, 1.0}, .diffuse = 0.1, .specular = 0.3, .transmission = 0.9,
                         .ior = 1.5, .absorption = {0.3, 0.1, 0.0}};
    const glm::dmat4 placements[4] = {placement({-1.7, 0.4, 0}, {0, 0, 0}, {0.8, 0.8, 0.8}),
                                      placement({0, 0.5, -0.5}, {30, 45, 10}, {1.2, 0.5, 0.8}),
                                      placement({1.7, 0.5, 0}, {0, 20, 0}, {-0.8, 0.8, 0.8}),
                                      placement({0.2, 0.3, 1.3}, {10, 0, 30}, {0.6, 0.6, 0.6})};
    Mesh mesh = gem();
    if (!flat) scene.prototypes.push_back({.name = "gem", .objects = {{.shape = mesh, .material = copper}}});
    for (int i = 0; i < 4; ++i) {
        const Material& m = i == 3 ? glass : copper;
        if (flat) {
            scene.objects.push_back({.shape = flattened(mesh, placements[i]), .material = m});
        } else {
            scene.instances.push_back({.prototype = 0, .worldFromObject = placements[i]});
            if (i == 3) scene.instances.back().material = glass;
        }
    }
    return scene;
}

double psnr(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (i % 4 == 3) continue;  // the sample count
        double d = std::min(1.0, double(a[i])) - std::min(1.0, double(b[i]));
        sum += d * d;
        ++n;
    }
    return sum == 0 ? 1e9 : 10.0 * std::log10(1.0 / (sum / double(n)));
}

// Instance i has object id objects.size() + i, the flattened copy i the
// index 1 + i: the same ids, so the object masks must agree pixel for pixel.
void expectInstancesEqualCopies(TracePath trace) {
    RenderSettings settings{.width = 96, .height = 72, .samplesPerPixel = 1, .maxDepth = 6, .auxiliary = true};
    settings.ids = true;
    settings.trace = trace;
    RenderResult instanced = renderScene(gemScene(false), settings);
    RenderResult flat = renderScene(gemScene(true), settings);
    ASSERT_EQ(instanced.trace, trace);
    double colour = psnr(instanced.layers[gpu::kAovColor], flat.layers[gpu::kAovColor]);
    EXPECT_GE(colour, 60.0);
    EXPECT_GE(psnr(instanced.layers[gpu::kAovNormal], flat.layers[gpu::kAovNormal]), 60.0);
    const std::vector<float>& a = instanced.layers[instanced.layout.idLayer()];
    const std::vector<float>& b = flat.layers[flat.layout.idLayer()];
    ASSERT_EQ(a.size(), b.size());
    size_t differing = 0;
    std::set<uint32_t> seen;
    for (size_t i = 0; i < a.size(); i += 4) {
        uint32_t id = std::bit_cast<uint32_t>(a[i]);
        differing += id != std::bit_cast<uint32_t>(b[i]);
        seen.insert(id);
    }
    EXPECT_EQ(differing, 0u);
    // The floor and every instance are in view.
    for (uint32_t id : {0u, 1u, 2u, 3u, 4u}) EXPECT_TRUE(seen.count(id)) << "object " << id;
    std::cout << "instances against flattened copies: colour PSNR " << colour << " dB\n";
}

TEST(InstanceRender, InstancesEqualFlattenedCopiesOnTheBvhPath) { expectInstancesEqualCopies(TracePath::Bvh); }

TEST(InstanceRender, InstancesEqualFlattenedCopiesOnTheRayQueryPath) {
    if (!test::testContext().deviceInfo().rayQuery)
        GTEST_SKIP() << "device '" << test::testContext().deviceInfo().name << "' lacks VK_KHR_ray_query";
    expectInstancesEqualCopies(TracePath::RayQuery);
}

}  // namespace
}  // namespace whitted

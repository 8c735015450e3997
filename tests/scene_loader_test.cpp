// The XML scene loader: the seed's schema loads unchanged, each extension
// lands in the scene model, and every way a file can be wrong is refused
// with its exact "FILE:LINE: message" (Mitsuba's test_parser.py style).
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

namespace whitted::test {
namespace {

// The seed's own element form with one of each of its object types. The
// line numbers in the comments are checked below.
constexpr const char* kSeedScene = R"(<?xml version="1.0" encoding="utf-8"?>
<scene>
  <camera>
    <position><x>0</x><y>1</y><z>5</z></position>
    <window_position><x>0</x><y>1</y><z>4</z></window_position>
  </camera>
  <lights>
    <light>
      <position><x>1</x><y>4</y><z>2</z></position>
      <color><r>0.5</r><g>0.6</g><b>0.7</b><a>1</a></color>
    </light>
    <light>
      <position><x>-1</x><y>4</y><z>2</z></position>
      <color><r>2</r><g>2</g><b>2</b><a>1</a></color>
    </light>
  </lights>
  <objects>
    <object> <!-- line 18 -->
      <position><x>0</x><y>1</y><z>0</z></position>
      <diffuse_color><r>1</r><g>0</g><b>0</b><a>1</a></diffuse_color>
      <specular_color><r>0.5</r><g>0.25</g><b>0.125</b><a>1</a></specular_color>
      <properties>
        <type>sphere</type>
        <refraction_coef>1.5</refraction_coef>
        <transmission_coef>0.2</transmission_coef>
        <specular_coef>0.4</specular_coef>
        <diffuse_coef>0.6</diffuse_coef>
        <ambiente_coef>0.1</ambiente_coef>
        <reflective>true</reflective>
        <radius>0.75</radius>
      </properties>
    </object>
    <object> <!-- line 33 -->
      <position><x>2</x><y>0</y><z>-1</z></position>
      <diffuse_color><r>0</r><g>0</g><b>1</b><a>1</a></diffuse_color>
      <specular_color><r>1</r><g>1</g><b>1</b><a>1</a></specular_color>
      <properties>
        <type>cylinder</type>
        <refraction_coef>1</refraction_coef>
        <transmission_coef>0</transmission_coef>
        <specular_coef>0.3</specular_coef>
        <diffuse_coef>1</diffuse_coef>
        <ambiente_coef>0</ambiente_coef>
        <reflective>false</reflective>
        <radius>0.5</radius>
        <height>2</height>
      </properties>
    </object>
    <object> <!-- line 49 -->
      <position><x>0</x><y>-1</y><z>0</z></position>
      <diffuse_color><r>1</r><g>1</g><b>1</b><a>1</a></diffuse_color>
      <specular_color><r>1</r><g>1</g><b>1</b><a>1</a></specular_color>
      <properties>
        <type>mesh</type>
        <refraction_coef>1</refraction_coef>
        <transmission_coef>0</transmission_coef>
        <specular_coef>0</specular_coef>
        <diffuse_coef>1</diffuse_coef>
        <ambiente_coef>0</ambiente_coef>
        <reflective>false</reflective>
        <polygons>
          <polygon>
            <vertex><x>-1</x><y>0</y><z>1</z></vertex>
            <vertex><x>1</x><y>0</y><z>1</z></vertex>
            <vertex><x>1</x><y>0</y><z>-1</z></vertex>
          </polygon>
          <polygon>
            <vertex><x>-1</x><y>0</y><z>1</z></vertex>
            <vertex><x>1</x><y>0</y><z>-1</z></vertex>
            <vertex><x>-1</x><y>0</y><z>-1</z></vertex>
          </polygon>
        </polygons>
      </properties>
    </object>
  </objects>
</scene>
)";

Scene load(const std::string& xml) {
    return loadSceneFromString(xml, "t.xml");
}

// The what() of the SceneError that `xml` gives, or "" if it loads.
std::string errorOf(const std::string& xml) {
    try {
        load(xml);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// A valid scene around an <objects> body, laid out so that messages have
// known lines: 1 <scene>, 2 <camera>, 3 its <position>, 4 its
// <window_position>, 5 `cameraExtra` (one line) and </camera>, 6 <lights>,
// 7 <objects>, and the objects from line 8.
std::string sceneWith(const std::string& objects, const std::string& cameraExtra = "") {
    return "<scene>\n"
           "<camera>\n"
           "<position x=\"0\" y=\"0\" z=\"5\"/>\n"
           "<window_position x=\"0\" y=\"0\" z=\"4\"/>\n" +
           cameraExtra + "</camera>\n" +
           "<lights><light><position x=\"0\" y=\"5\" z=\"0\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>\n"
           "<objects>\n" +
           objects + "</objects>\n</scene>\n";
}

// One object laid out for sceneWith(): 8 <object>, 9 `head` (its position
// and colours; may be empty), 10 <properties>, 11 <type>, 12 `properties`
// (may span lines).
std::string objectOf(const std::string& type, const std::string& properties,
                     const std::string& head = "<position x=\"0\" y=\"0\" z=\"0\"/>") {
    return "<object>\n" + head + "\n<properties>\n<type>" + type + "</type>\n" + properties +
           "\n</properties>\n</object>\n";
}

std::string sphereWith(const std::string& properties) {
    return sceneWith(objectOf("sphere", properties));
}

// A scene whose camera has `cameraExtra` on line 5.
std::string cameraWith(const std::string& cameraExtra) {
    return sceneWith(objectOf("sphere", "<radius>1</radius>"), cameraExtra);
}

const std::string kVertices =
    "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/>";

// ---- What loads --------------------------------------------------------------

TEST(SceneLoaderTest, ReadsTheSeedSchema) {
    Scene s = load(kSeedScene);
    EXPECT_EQ(s.sourcePath, std::filesystem::path("t.xml"));
    EXPECT_TRUE(s.warnings.empty());

    EXPECT_EQ(s.camera.eye, glm::dvec3(0, 1, 5));
    EXPECT_EQ(s.camera.windowCenter, glm::dvec3(0, 1, 4));
    EXPECT_EQ(s.camera.up, glm::dvec3(0, 1, 0));
    EXPECT_EQ(s.camera.verticalFovDegrees, 60.0);
    EXPECT_EQ(s.camera.width, 640);
    EXPECT_EQ(s.camera.height, 480);
    EXPECT_EQ(s.ambientLight, glm::dvec3(1, 1, 1));

    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].position, glm::dvec3(1, 4, 2));
    EXPECT_EQ(s.lights[0].color, glm::dvec3(0.5, 0.6, 0.7));
    EXPECT_EQ(s.lights[1].position, glm::dvec3(-1, 4, 2));
    EXPECT_EQ(s.lights[1].color, glm::dvec3(2, 2, 2)) << "light colours may exceed 1";

    ASSERT_EQ(s.objects.size(), 3u);
    const Object& sphere = s.objects[0];
    EXPECT_EQ(sphere.sourceLine, 18);
    ASSERT_TRUE(std::holds_alternative<Sphere>(sphere.shape));
    EXPECT_EQ(std::get<Sphere>(sphere.shape).center, glm::dvec3(0, 1, 0));
    EXPECT_EQ(std::get<Sphere>(sphere.shape).radius, 0.75);
    EXPECT_EQ(sphere.material.diffuseColor, glm::dvec3(1, 0, 0));
    EXPECT_EQ(sphere.material.specularColor, glm::dvec3(0.5, 0.25, 0.125));
    EXPECT_EQ(sphere.material.ior, 1.5);
    EXPECT_EQ(sphere.material.transmission, 0.2);
    EXPECT_EQ(sphere.material.specular, 0.4);
    EXPECT_EQ(sphere.material.diffuse, 0.6);
    EXPECT_EQ(sphere.material.ambient, 0.1);
    EXPECT_EQ(sphere.material.reflection, 0.4) << "reflective: kr = ks";
    EXPECT_EQ(sphere.material.shininess, 32.0);

    const Object& cylinder = s.objects[1];
    EXPECT_EQ(cylinder.sourceLine, 33);
    ASSERT_TRUE(std::holds_alternative<Cylinder>(cylinder.shape));
    const Cylinder& c = std::get<Cylinder>(cylinder.shape);
    EXPECT_EQ(c.base, glm::dvec3(2, 0, -1));
    EXPECT_EQ(c.axis, glm::dvec3(0, 1, 0));
    EXPECT_EQ(c.radius, 0.5);
    EXPECT_EQ(c.height, 2.0);
    EXPECT_EQ(cylinder.material.diffuseColor, glm::dvec3(0, 0, 1));
    EXPECT_EQ(cylinder.material.specular, 0.3);
    EXPECT_EQ(cylinder.material.reflection, 0.0) << "not reflective: kr = 0 whatever ks is";

    const Object& mesh = s.objects[2];
    EXPECT_EQ(mesh.sourceLine, 49);
    ASSERT_TRUE(std::holds_alternative<Mesh>(mesh.shape));
    const Mesh& m = std::get<Mesh>(mesh.shape);
    ASSERT_EQ(m.triangles.size(), 2u);
    // Vertices are relative to the object's position (0, -1, 0).
    EXPECT_EQ(m.triangles[0].v0, glm::dvec3(-1, -1, 1));
    EXPECT_EQ(m.triangles[0].v1, glm::dvec3(1, -1, 1));
    EXPECT_EQ(m.triangles[0].v2, glm::dvec3(1, -1, -1));
    EXPECT_EQ(m.triangles[1].v0, glm::dvec3(-1, -1, 1));
    EXPECT_EQ(m.triangles[1].v1, glm::dvec3(1, -1, -1));
    EXPECT_EQ(m.triangles[1].v2, glm::dvec3(-1, -1, -1));
}

TEST(SceneLoaderTest, ReadsTheAttributeForm) {
    Scene s = load(sceneWith(objectOf("sphere", "<radius>1</radius>",
                                      "<position x=\"1\" y=\"2\" z=\"3\"/>"
                                      "<diffuse_color r=\"0.1\" g=\"0.2\" b=\"0.3\" a=\"1\"/>"
                                      "<specular_color r=\"0.4\" g=\"0.5\" b=\"0.6\"/>")));
    EXPECT_EQ(s.camera.eye, glm::dvec3(0, 0, 5));
    EXPECT_EQ(s.camera.windowCenter, glm::dvec3(0, 0, 4));
    EXPECT_EQ(s.lights[0].position, glm::dvec3(0, 5, 0));
    EXPECT_EQ(s.lights[0].color, glm::dvec3(1, 1, 1));
    EXPECT_EQ(std::get<Sphere>(s.objects[0].shape).center, glm::dvec3(1, 2, 3));
    EXPECT_EQ(s.objects[0].material.diffuseColor, glm::dvec3(0.1, 0.2, 0.3));
    EXPECT_EQ(s.objects[0].material.specularColor, glm::dvec3(0.4, 0.5, 0.6)) << "alpha is optional";
    EXPECT_EQ(s.objects[0].sourceLine, 8);
}

TEST(SceneLoaderTest, TakesWhitespaceCommentsAndBooleanSpellings) {
    Scene s = load(sceneWith(objectOf("sphere",
                                      "<radius>\n  2.5 <!-- metres -->\n</radius>"
                                      "<specular_coef> +0.25 </specular_coef>"
                                      "<reflective> TRUE </reflective>",
                                      "<position><x> 1e-400 </x><y>\t-2</y><z>3e-1\n</z></position>")));
    EXPECT_EQ(std::get<Sphere>(s.objects[0].shape).radius, 2.5);
    EXPECT_EQ(std::get<Sphere>(s.objects[0].shape).center, glm::dvec3(0, -2, 0.3)) << "underflow reads as 0";
    EXPECT_EQ(s.objects[0].material.reflection, 0.25);

    auto reflection = [](const std::string& reflective) {
        return load(sphereWith("<radius>1</radius><specular_coef>0.5</specular_coef><reflective>" + reflective +
                               "</reflective>"))
            .objects[0]
            .material.reflection;
    };
    EXPECT_EQ(reflection("true"), 0.5);
    EXPECT_EQ(reflection("1"), 0.5);
    EXPECT_EQ(reflection("True"), 0.5);
    EXPECT_EQ(reflection("false"), 0.0);
    EXPECT_EQ(reflection("0"), 0.0);
    EXPECT_EQ(reflection("FALSE"), 0.0);
}

TEST(SceneLoaderTest, MaterialDefaults) {
    Material m = load(sphereWith("<radius>1</radius>")).objects[0].material;
    EXPECT_EQ(m.diffuseColor, glm::dvec3(1, 1, 1));
    EXPECT_EQ(m.specularColor, glm::dvec3(1, 1, 1));
    EXPECT_EQ(m.ambient, 0.0);
    EXPECT_EQ(m.diffuse, 1.0);
    EXPECT_EQ(m.specular, 0.0);
    EXPECT_EQ(m.shininess, 32.0);
    EXPECT_EQ(m.reflection, 0.0);
    EXPECT_EQ(m.transmission, 0.0);
    EXPECT_EQ(m.ior, 1.0);
}

TEST(SceneLoaderTest, AcceptsChildrenInAnyOrder) {
    Scene s = load(
        "<scene><objects><object><properties><radius>2</radius><type>sphere</type></properties>"
        "<position x=\"1\" y=\"0\" z=\"0\"/></object></objects>"
        "<ambient_light r=\"0.5\" g=\"0.5\" b=\"0.5\"/>"
        "<lights><light><color r=\"1\" g=\"1\" b=\"1\"/><position x=\"0\" y=\"1\" z=\"0\"/></light></lights>"
        "<camera><height>10</height><window_position x=\"0\" y=\"0\" z=\"0\"/><position x=\"0\" y=\"0\" z=\"1\"/>"
        "</camera></scene>");
    EXPECT_EQ(std::get<Sphere>(s.objects[0].shape).radius, 2.0);
    EXPECT_EQ(s.lights[0].position, glm::dvec3(0, 1, 0));
    EXPECT_EQ(s.camera.eye, glm::dvec3(0, 0, 1));
    EXPECT_EQ(s.camera.height, 10);
    EXPECT_EQ(s.ambientLight, glm::dvec3(0.5, 0.5, 0.5));
}

TEST(SceneLoaderTest, CameraFovUpAndImageSize) {
    Scene s = load(cameraWith("<fov>45</fov><up x=\"2\" y=\"0\" z=\"0\"/><width>320</width><height>200</height>"));
    EXPECT_EQ(s.camera.verticalFovDegrees, 45.0);
    EXPECT_EQ(s.camera.up, glm::dvec3(1, 0, 0)) << "up is normalised";
    EXPECT_EQ(s.camera.width, 320);
    EXPECT_EQ(s.camera.height, 200);

    Scene limits = load(cameraWith("<width> +1 </width><height>16384</height>"));
    EXPECT_EQ(limits.camera.width, 1);
    EXPECT_EQ(limits.camera.height, 16384);
}

TEST(SceneLoaderTest, WindowHeightGivesTheFov) {
    // The window is 1 unit from the eye: a window 2 units high spans 90 degrees.
    EXPECT_NEAR(load(cameraWith("<window_height>2</window_height>")).camera.verticalFovDegrees, 90.0, 1e-12);
    // Eye-to-window distance 2, window height 1: fov = 2 atan(1/4).
    Scene s = load(
        "<scene><camera><position x=\"0\" y=\"0\" z=\"2\"/><window_position x=\"0\" y=\"0\" z=\"0\"/>"
        "<window_height>1</window_height></camera><lights/><objects/></scene>");
    EXPECT_NEAR(s.camera.verticalFovDegrees, glm::degrees(2.0 * std::atan(0.25)), 1e-12);
}

TEST(SceneLoaderTest, AmbientLight) {
    EXPECT_EQ(load(sphereWith("<radius>1</radius>")).ambientLight, glm::dvec3(1, 1, 1));
    std::string xml = sphereWith("<radius>1</radius>");
    xml.insert(xml.find("<lights>"), "<ambient_light><r>0.2</r><g>0.3</g><b>2</b></ambient_light>");
    EXPECT_EQ(load(xml).ambientLight, glm::dvec3(0.2, 0.3, 2)) << "ambient light may exceed 1";
}

TEST(SceneLoaderTest, ShininessAndReflectionCoefficient) {
    auto material = [](const std::string& properties) {
        return load(sphereWith("<radius>1</radius><specular_coef>0.3</specular_coef>" + properties))
            .objects[0]
            .material;
    };
    EXPECT_EQ(material("<shininess>200</shininess>").shininess, 200.0);
    EXPECT_EQ(material("<shininess>100000</shininess>").shininess, 1e5);
    EXPECT_EQ(material("<reflection_coef>0.8</reflection_coef>").reflection, 0.8) << "given without <reflective>";
    EXPECT_EQ(material("<reflective>true</reflective><reflection_coef>0.8</reflection_coef>").reflection, 0.8);
    EXPECT_EQ(material("<reflective>true</reflective>").reflection, 0.3) << "reflective alone: kr = ks";
    EXPECT_EQ(material("").reflection, 0.0);
    EXPECT_EQ(material("<refraction_coef>0.5</refraction_coef>").ior, 0.5) << "relative IOR below 1";
}

// The checker is anchored at the object's <position> (the origin for a mesh
// or triangle without one); absorption is per channel.
TEST(SceneLoaderTest, CheckerAndAbsorption) {
    const Material plain = load(sphereWith("<radius>1</radius>")).objects[0].material;
    EXPECT_EQ(plain.checkerSize, 0.0);
    EXPECT_EQ(plain.absorption, glm::dvec3(0));
    Scene scene =
        load(sphereWith("<radius>1</radius><checker_color r=\"0.1\" g=\"0.2\" b=\"0.3\"/>"
                        "<checker_size>0.25</checker_size><absorption r=\"0\" g=\"0.5\" b=\"2\"/>"));
    const Material& m = scene.objects[0].material;
    EXPECT_EQ(m.checkerColor, glm::dvec3(0.1, 0.2, 0.3));
    EXPECT_EQ(m.checkerSize, 0.25);
    EXPECT_EQ(m.checkerOrigin, std::get<Sphere>(scene.objects[0].shape).center);
    EXPECT_EQ(m.absorption, glm::dvec3(0, 0.5, 2));
}

TEST(SceneLoaderTest, PlaneTriangleBoxAndCylinderAxis) {
    Scene s =
        load(sceneWith(objectOf("plane", "<normal x=\"0\" y=\"2\" z=\"0\"/>", "<position x=\"0\" y=\"-1\" z=\"0\"/>") +
                       objectOf("triangle", kVertices, "<position x=\"1\" y=\"0\" z=\"0\"/>") +
                       objectOf("box", "<size x=\"1\" y=\"2\" z=\"3\"/>", "<position x=\"-1\" y=\"0\" z=\"-1\"/>") +
                       objectOf("cylinder", "<radius>1</radius><height>2</height><axis x=\"3\" y=\"0\" z=\"4\"/>")));
    ASSERT_EQ(s.objects.size(), 4u);

    const Plane& plane = std::get<Plane>(s.objects[0].shape);
    EXPECT_EQ(plane.point, glm::dvec3(0, -1, 0));
    EXPECT_EQ(plane.normal, glm::dvec3(0, 1, 0)) << "the normal is normalised";

    const Triangle& t = std::get<Triangle>(s.objects[1].shape);
    EXPECT_EQ(t.v0, glm::dvec3(1, 0, 0)) << "vertices are relative to the position";
    EXPECT_EQ(t.v1, glm::dvec3(2, 0, 0));
    EXPECT_EQ(t.v2, glm::dvec3(1, 1, 0));

    const Box& b = std::get<Box>(s.objects[2].shape);
    EXPECT_EQ(b.min, glm::dvec3(-1, 0, -1));
    EXPECT_EQ(b.max, glm::dvec3(0, 2, 2));

    const Cylinder& c = std::get<Cylinder>(s.objects[3].shape);
    EXPECT_EQ(c.axis, glm::dvec3(0.6, 0, 0.8));
    EXPECT_EQ(c.radius, 1.0);
    EXPECT_EQ(c.height, 2.0);
}

TEST(SceneLoaderTest, MeshAndTrianglePositionDefaultsToOrigin) {
    Scene s = load(sceneWith(objectOf("triangle", kVertices, "") +
                             objectOf("mesh", "<polygons><polygon>" + kVertices + "</polygon></polygons>", "")));
    EXPECT_EQ(std::get<Triangle>(s.objects[0].shape).v1, glm::dvec3(1, 0, 0));
    EXPECT_EQ(std::get<Mesh>(s.objects[1].shape).triangles[0].v2, glm::dvec3(0, 1, 0));
}

// ---- Degenerate but legal input --------------------------------------------------

TEST(SceneLoaderTest, WarnsAboutNoLightsAndNoObjects) {
    Scene s = load(
        "<scene>\n<camera><position x=\"0\" y=\"0\" z=\"1\"/><window_position x=\"0\" y=\"0\" z=\"0\"/></camera>\n"
        "<lights/>\n<objects>\n</objects>\n</scene>");
    EXPECT_TRUE(s.lights.empty());
    EXPECT_TRUE(s.objects.empty());
    ASSERT_EQ(s.warnings.size(), 2u);
    EXPECT_EQ(s.warnings[0], "t.xml:3: scene has no lights; only ambient light will show");
    EXPECT_EQ(s.warnings[1], "t.xml:4: scene has no objects; the image will be black");
}

TEST(SceneLoaderTest, SkipsDegeneratePolygonsWithAWarning) {
    Scene s = load(sceneWith(objectOf("mesh",
                                      "<polygons>\n"  // line 12
                                      "<polygon>" +
                                          kVertices +
                                          "</polygon>\n"
                                          "<polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"1\" z=\"1\"/>"
                                          "<vertex x=\"2\" y=\"2\" z=\"2\"/></polygon>\n"  // line 14: collinear
                                          "<polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"0\" z=\"0\"/>"
                                          "<vertex x=\"0\" y=\"1\" z=\"0\"/></polygon>\n"  // line 15: repeated vertex
                                          "</polygons>")));
    EXPECT_EQ(std::get<Mesh>(s.objects[0].shape).triangles.size(), 1u);
    ASSERT_EQ(s.warnings.size(), 2u);
    EXPECT_EQ(s.warnings[0], "t.xml:14: degenerate polygon skipped");
    EXPECT_EQ(s.warnings[1], "t.xml:15: degenerate polygon skipped");
}

TEST(SceneLoaderTest, TinyButProperTrianglesAreNotDegenerate) {
    Scene s = load(sceneWith(objectOf("triangle",
                                      "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1e-4\" y=\"0\" z=\"0\"/>"
                                      "<vertex x=\"0\" y=\"1e-4\" z=\"0\"/>")));
    EXPECT_EQ(std::get<Triangle>(s.objects[0].shape).v1, glm::dvec3(1e-4, 0, 0));
}

// ---- Files ---------------------------------------------------------------------------

TEST(SceneLoaderTest, LoadsAFile) {
    std::filesystem::path path = std::filesystem::temp_directory_path() / "whitted_scene_loader_test.xml";
    {
        std::ofstream out(path);
        out << kSeedScene;
    }
    Scene s = loadScene(path);
    std::filesystem::remove(path);
    EXPECT_EQ(s.sourcePath, path);
    EXPECT_EQ(s.objects.size(), 3u);
}

TEST(SceneLoaderTest, ReadsOnlyTheGivenView) {
    std::string buffer = sphereWith("<radius>1</radius>") + "<trailing junk";
    std::string_view xml(buffer.data(), buffer.find("<trailing"));
    EXPECT_EQ(loadSceneFromString(xml, "view.xml").objects.size(), 1u);
}

TEST(SceneLoaderTest, MissingFileHasNoLine) {
    try {
        loadScene("/nonexistent/scene.xml");
        FAIL() << "no exception";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.line(), 0);
        EXPECT_EQ(e.file(), "/nonexistent/scene.xml");
        EXPECT_EQ(e.message(), "cannot read file: No such file or directory");
        EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.xml: cannot read file: No such file or directory");
    }
}

TEST(SceneLoaderTest, DirectoryIsNotAFile) {
    std::filesystem::path dir = std::filesystem::temp_directory_path();
    try {
        loadScene(dir);
        FAIL() << "no exception";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.line(), 0);
        EXPECT_EQ(std::string(e.what()), dir.string() + ": cannot read file: it is a directory");
    }
}

TEST(SceneLoaderTest, ErrorCarriesFileLineAndMessage) {
    try {
        loadSceneFromString(sphereWith("<radius>-1</radius>"), "dir/scene.xml");
        FAIL() << "no exception";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file(), "dir/scene.xml");
        EXPECT_EQ(e.line(), 12);
        EXPECT_EQ(e.message(), "<radius> must be > 0, got -1");
        EXPECT_EQ(std::string(e.what()), "dir/scene.xml:12: <radius> must be > 0, got -1");
    }
}

// ---- What is refused, word for word ------------------------------------------------

struct BadCase {
    const char* name;
    std::string xml;
    std::string message;
};

void PrintTo(const BadCase& c, std::ostream* os) {
    *os << c.name;
}

class SceneLoaderErrorTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(SceneLoaderErrorTest, GivesFileLineAndWhat) {
    EXPECT_EQ(errorOf(GetParam().xml), GetParam().message);
}

std::string nested(int depth) {
    std::string s;
    for (int i = 0; i < depth; ++i) s += "<a>";
    for (int i = 0; i < depth; ++i) s += "</a>";
    return s;
}

const std::string kPropertyList =
    "type, refraction_coef, transmission_coef, specular_coef, diffuse_coef, ambiente_coef, reflective, shininess, "
    "reflection_coef, checker_color, checker_size, absorption, diffuse_texture, texture_scale, normal_map, "
    "normal_strength, fresnel, transmission_color, emission, emission_texture, ambient_color, roughness, roughness_texture, radius, height, axis, normal, size, "
    "vertex, polygons, file, scale, rotation, matrix, operation";

std::vector<BadCase> xmlCases() {
    const std::string camera =
        "<camera><position x=\"0\" y=\"0\" z=\"5\"/><window_position x=\"0\" y=\"0\" z=\"4\"/></camera>";
    return {
        {"Truncated", "<scene>\n<camera>",
         "t.xml:2: malformed XML: XML_ERROR_MISMATCHED_ELEMENT (XMLElement name=camera)"},
        {"MismatchedClose", "<scene>\n\n<camera></camra>\n</scene>",
         "t.xml:3: malformed XML: XML_ERROR_MISMATCHED_ELEMENT (XMLElement name=camera)"},
        {"Empty", "", "t.xml:1: the file is empty, expected a <scene> document"},
        {"OnlyWhitespace", "\n  \t\r\n\n", "t.xml:1: the file is empty, expected a <scene> document"},
        {"OnlyByteOrderMark", "\xEF\xBB\xBF\n", "t.xml:1: the file is empty, expected a <scene> document"},
        {"TextAfterRoot", "<scene/>\njunk", "t.xml:2: malformed XML: XML_ERROR_PARSING_TEXT"},
        {"DeepNesting", "<scene>" + nested(1000),
         "t.xml:1: malformed XML: XML_ELEMENT_DEPTH_EXCEEDED (Element nesting is too deep.)"},
        {"NoRoot", "<?xml version=\"1.0\"?>\n<!-- nothing -->", "t.xml: no root element; expected <scene>"},
        {"WrongRoot", "<?xml version=\"1.0\"?>\n<scenery/>", "t.xml:2: root element is <scenery>, expected <scene>"},
        {"TwoRoots", "<scene>" + camera + "<lights/><objects/></scene>\n<scene/>",
         "t.xml:2: second root element <scene>; a scene file holds one <scene>"},
        {"MissingCamera", "<scene>\n<lights/><objects/></scene>", "t.xml:1: <scene> is missing <camera>"},
        {"MissingLights", "<scene>" + camera + "<objects/></scene>", "t.xml:1: <scene> is missing <lights>"},
        {"MissingObjects", "<scene>" + camera + "<lights/></scene>", "t.xml:1: <scene> is missing <objects>"},
        {"TwoCameras", "<scene>" + camera + "\n" + camera + "<lights/><objects/></scene>",
         "t.xml:2: duplicate <camera> in <scene>"},
        {"UnknownTopLevel", "<scene>" + camera + "<lights/><objects/>\n<lamps/></scene>",
         "t.xml:2: unknown element <lamps> in <scene>; expected one of: camera, lights, objects, ambient_light, "
         "environment, prototypes, instances"},
        {"UnknownInLights", "<scene>" + camera + "<lights>\n<lamp/></lights><objects/></scene>",
         "t.xml:2: unknown element <lamp> in <lights>; expected light"},
        {"UnknownInObjects", sceneWith("<objet/>"), "t.xml:8: unknown element <objet> in <objects>; expected object"},
        {"AttributeOnContainer", "<scene version=\"2\">" + camera + "<lights/><objects/></scene>",
         "t.xml:1: unknown attribute \"version\" on <scene>; <scene> takes no attributes"},
        {"AttributeOnValue", sphereWith("<radius unit=\"m\">1</radius>"),
         "t.xml:12: unknown attribute \"unit\" on <radius>; <radius> takes no attributes"},
        {"StrayText", sceneWith("<object>\noops<properties><type>sphere</type></properties></object>"),
         "t.xml:9: unexpected text \"oops\" in <object>"},
        {"LongStrayText", sceneWith("<object>abcdefghijklmnopqrstuvwxyz0123456789</object>"),
         "t.xml:8: unexpected text \"abcdefghijklmnopqrstuvwxyz0123...\" in <object>"},
        {"ElementInValue", sphereWith("<radius>\n<value>1</value></radius>"),
         "t.xml:13: unknown element <value> in <radius>; <radius> holds a value, not elements"},
    };
}

std::vector<BadCase> valueCases() {
    return {
        {"NotANumber", sphereWith("<radius>abc</radius>"), "t.xml:12: <radius> must be a number, got \"abc\""},
        {"EmptyNumber", sphereWith("<radius> </radius>"), "t.xml:12: <radius> must be a number, got \"\""},
        {"TrailingGarbage", sphereWith("<radius>1.5x</radius>"), "t.xml:12: <radius> must be a number, got \"1.5x\""},
        {"TwoNumbers", sphereWith("<radius>1 2</radius>"), "t.xml:12: <radius> must be a number, got \"1 2\""},
        {"Hexadecimal", sphereWith("<radius>0x10</radius>"), "t.xml:12: <radius> must be a number, got \"0x10\""},
        {"NaN", sphereWith("<radius>nan</radius>"), "t.xml:12: <radius> must be a finite number, got \"nan\""},
        {"Infinity", sphereWith("<radius>inf</radius>"), "t.xml:12: <radius> must be a finite number, got \"inf\""},
        {"NegativeInfinity",
         sceneWith(objectOf("sphere", "<radius>1</radius>", "<position x=\"-infinity\" y=\"0\" z=\"0\"/>")),
         "t.xml:9: attribute x of <position> must be a finite number, got \"-infinity\""},
        {"Huge", sphereWith("<radius>1e9</radius>"), "t.xml:12: <radius> must be within ±1e6, got 1e9"},
        {"Overflow", sphereWith("<radius>1e999</radius>"), "t.xml:12: <radius> must be within ±1e6, got 1e999"},
        {"HugeCoordinate",
         sceneWith(objectOf("sphere", "<radius>1</radius>", "<position><x>0</x><y>-2e6</y><z>0</z></position>")),
         "t.xml:9: <y> of <position> must be within ±1e6, got -2e6"},
        {"NegativeRadius", sphereWith("<radius>-1</radius>"), "t.xml:12: <radius> must be > 0, got -1"},
        {"ZeroRadius", sphereWith("<radius>0</radius>"), "t.xml:12: <radius> must be > 0, got 0"},
        {"CoefficientAboveOne", sphereWith("<radius>1</radius>\n<diffuse_coef>1.5</diffuse_coef>"),
         "t.xml:13: <diffuse_coef> must be in [0, 1], got 1.5"},
        {"NegativeAmbient", sphereWith("<radius>1</radius>\n<ambiente_coef>-0.1</ambiente_coef>"),
         "t.xml:13: <ambiente_coef> must be in [0, 1], got -0.1"},
        {"SpecularAboveOne", sphereWith("<radius>1</radius>\n<specular_coef>2</specular_coef>"),
         "t.xml:13: <specular_coef> must be in [0, 1], got 2"},
        {"TransmissionAboveOne", sphereWith("<radius>1</radius>\n<transmission_coef>1.01</transmission_coef>"),
         "t.xml:13: <transmission_coef> must be in [0, 1], got 1.01"},
        {"ReflectionAboveOne", sphereWith("<radius>1</radius>\n<reflection_coef>3</reflection_coef>"),
         "t.xml:13: <reflection_coef> must be in [0, 1], got 3"},
        {"IorTooLow", sphereWith("<radius>1</radius>\n<refraction_coef>0.05</refraction_coef>"),
         "t.xml:13: <refraction_coef> must be in [0.1, 10], got 0.05"},
        {"IorTooHigh", sphereWith("<radius>1</radius>\n<refraction_coef>11</refraction_coef>"),
         "t.xml:13: <refraction_coef> must be in [0.1, 10], got 11"},
        {"ZeroShininess", sphereWith("<radius>1</radius>\n<shininess>0</shininess>"),
         "t.xml:13: <shininess> must be in (0, 100000], got 0"},
        {"HugeShininess", sphereWith("<radius>1</radius>\n<shininess>2e5</shininess>"),
         "t.xml:13: <shininess> must be in (0, 100000], got 2e5"},
        {"BadBoolean", sphereWith("<radius>1</radius>\n<reflective>yes</reflective>"),
         "t.xml:13: <reflective> must be true or false, got \"yes\""},
        {"ReflectionContradiction",
         sphereWith("<radius>1</radius><reflective>false</reflective>\n<reflection_coef>0.5</reflection_coef>"),
         "t.xml:13: <reflection_coef> contradicts <reflective>false</reflective>"},
    };
}

std::vector<BadCase> vectorAndColourCases() {
    auto withHead = [](const std::string& head) { return sceneWith(objectOf("sphere", "<radius>1</radius>", head)); };
    return {
        {"MixedForm", withHead("<position x=\"0\"><y>0</y><z>0</z></position>"),
         "t.xml:9: <position> mixes attributes and child elements; use one form"},
        {"UnknownAttribute", withHead("<position x=\"0\" y=\"0\" z=\"0\" w=\"1\"/>"),
         "t.xml:9: unknown attribute \"w\" on <position>; expected x, y, z"},
        {"MissingAttribute", withHead("<position x=\"0\" y=\"0\"/>"), "t.xml:9: <position> is missing attribute \"z\""},
        {"TextWithAttributes", withHead("<position x=\"0\" y=\"0\" z=\"0\">1 2 3</position>"),
         "t.xml:9: unexpected text \"1 2 3\" in <position>"},
        {"TextInsteadOfComponents", withHead("<position>1 2 3</position>"),
         "t.xml:9: unexpected text \"1 2 3\" in <position>"},
        {"MissingComponent", withHead("<position><x>0</x><y>0</y></position>"), "t.xml:9: <position> is missing <z>"},
        {"EmptyVector", withHead("<position/>"), "t.xml:9: <position> is missing <x>"},
        {"DuplicateComponent", withHead("<position><x>0</x><y>0</y><z>0</z>\n<z>1</z></position>"),
         "t.xml:10: duplicate <z> in <position>"},
        {"UnknownComponent", withHead("<position><x>0</x><y>0</y><z>0</z>\n<w>1</w></position>"),
         "t.xml:10: unknown element <w> in <position>; expected one of: x, y, z"},
        {"ComponentNotANumber", withHead("<position>\n<x>a</x><y>0</y><z>0</z></position>"),
         "t.xml:10: <x> of <position> must be a number, got \"a\""},
        {"AttributeNotANumber", withHead("<position x=\"0\" y=\"one\" z=\"0\"/>"),
         "t.xml:9: attribute y of <position> must be a number, got \"one\""},
        {"ColourAboveOne", withHead("<position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color r=\"2\" g=\"0\" b=\"0\"/>"),
         "t.xml:9: attribute r of <diffuse_color> must be in [0, 1], got 2"},
        {"NegativeColourChannel",
         withHead("<position x=\"0\" y=\"0\" z=\"0\"/><specular_color><r>0</r><g>-0.5</g><b>0</b></specular_color>"),
         "t.xml:9: <g> of <specular_color> must be in [0, 1], got -0.5"},
        {"AlphaAboveOne",
         withHead("<position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color r=\"1\" g=\"1\" b=\"1\" a=\"2\"/>"),
         "t.xml:9: attribute a of <diffuse_color> must be in [0, 1], got 2"},
        {"AlphaNotANumber",
         withHead(
             "<position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color><r>1</r><g>1</g><b>1</b><a>opaque</a></diffuse_color>"),
         "t.xml:9: <a> of <diffuse_color> must be a number, got \"opaque\""},
        {"ColourMissingBlue", withHead("<position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color r=\"1\" g=\"1\"/>"),
         "t.xml:9: <diffuse_color> is missing attribute \"b\""},
        {"ColourUnknownAttribute",
         withHead("<position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color r=\"1\" g=\"1\" b=\"1\" x=\"1\"/>"),
         "t.xml:9: unknown attribute \"x\" on <diffuse_color>; expected r, g, b, a"},
        {"DuplicateColour",
         withHead("<position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color r=\"1\" g=\"1\" b=\"1\"/>"
                  "<diffuse_color r=\"1\" g=\"1\" b=\"1\"/>"),
         "t.xml:9: duplicate <diffuse_color> in <object>"},
    };
}

std::vector<BadCase> lightAndCameraCases() {
    // <lights> on line 2; `tail` follows <objects/>.
    auto withLights = [](const std::string& lights, const std::string& tail = "") {
        return "<scene><camera><position x=\"0\" y=\"0\" z=\"5\"/><window_position x=\"0\" y=\"0\" z=\"4\"/></camera>\n"
               "<lights>" +
               lights + "</lights><objects/>" + tail + "</scene>";
    };
    auto withCamera = [](const std::string& camera) {
        return "<scene>\n<camera>" + camera + "</camera><lights/><objects/></scene>";
    };
    return {
        {"LightWithoutColour", withLights("<light>\n<position x=\"0\" y=\"0\" z=\"0\"/></light>"),
         "t.xml:2: <light> is missing <color>"},
        {"LightWithoutPosition", withLights("<light><color r=\"1\" g=\"1\" b=\"1\"/></light>"),
         "t.xml:2: <light> is missing <position>"},
        {"NegativeLight",
         withLights("<light><position x=\"0\" y=\"0\" z=\"0\"/>\n<color r=\"-1\" g=\"0\" b=\"0\"/></light>"),
         "t.xml:3: attribute r of <color> must be >= 0, got -1"},
        {"UnknownInLight",
         withLights("<light><position x=\"0\" y=\"0\" z=\"0\"/><color r=\"1\" g=\"1\" b=\"1\"/>\n"
                    "<power>2</power></light>"),
         "t.xml:3: unknown element <power> in <light>; expected one of: type, position, color, intensity, falloff, "
         "direction, inner_angle, outer_angle, radius, shadow_samples, u, v, two_sided, name"},
        {"NegativeAmbientLight", withLights("", "\n<ambient_light r=\"0\" g=\"-1\" b=\"0\"/>"),
         "t.xml:3: attribute g of <ambient_light> must be >= 0, got -1"},
        {"MissingWindow", withCamera("<position x=\"0\" y=\"0\" z=\"5\"/>"),
         "t.xml:2: <camera> is missing <window_position>"},
        {"MissingEye", withCamera("<window_position x=\"0\" y=\"0\" z=\"5\"/>"),
         "t.xml:2: <camera> is missing <position>"},
        {"UnknownInCamera", cameraWith("<lens>50</lens>"),
         "t.xml:5: unknown element <lens> in <camera>; expected one of: position, window_position, up, fov, "
         "window_height, width, height, projection, intrinsics, aperture_radius, "
         "focus_distance"},
        {"CameraAtWindow", withCamera("<position x=\"1\" y=\"1\" z=\"1\"/><window_position x=\"1\" y=\"1\" z=\"1\"/>"),
         "t.xml:2: camera <position> and <window_position> coincide"},
        {"UpParallel", cameraWith("<up x=\"0\" y=\"0\" z=\"-3\"/>"),
         "t.xml:5: camera <up> is parallel to the viewing direction"},
        {"UpZero", cameraWith("<up x=\"0\" y=\"0\" z=\"0\"/>"), "t.xml:5: <up> must not be the zero vector"},
        {"LooksStraightDown",
         withCamera("<position x=\"0\" y=\"5\" z=\"0\"/><window_position x=\"0\" y=\"4\" z=\"0\"/>"),
         "t.xml:2: camera looks along the default <up> (0, 1, 0); give an <up> not parallel to the viewing direction"},
        {"FovAndWindowHeight", cameraWith("<fov>40</fov><window_height>1</window_height>"),
         "t.xml:5: <camera> has both <fov> and <window_height>; give one"},
        {"FovTooWide", cameraWith("<fov>180</fov>"), "t.xml:5: <fov> must be in (0, 180), got 180"},
        {"FovZero", cameraWith("<fov>0</fov>"), "t.xml:5: <fov> must be in (0, 180), got 0"},
        {"WindowHeightZero", cameraWith("<window_height>0</window_height>"),
         "t.xml:5: <window_height> must be > 0, got 0"},
        {"WindowHeightTooWide",
         withCamera("<position x=\"0\" y=\"0\" z=\"1e-11\"/><window_position x=\"0\" y=\"0\" z=\"0\"/>"
                    "<window_height>1e6</window_height>"),
         "t.xml:2: <window_height> gives a field of view of 180 degrees; it must be in (0, 180)"},
        {"WidthZero", cameraWith("<width>0</width>"), "t.xml:5: <width> must be in [1, 16384], got 0"},
        {"WidthHuge", cameraWith("<width>16385</width>"), "t.xml:5: <width> must be in [1, 16384], got 16385"},
        {"WidthOverflow", cameraWith("<width>99999999999</width>"),
         "t.xml:5: <width> must be in [1, 16384], got 99999999999"},
        {"WidthFraction", cameraWith("<width>12.5</width>"), "t.xml:5: <width> must be an integer, got \"12.5\""},
        {"HeightNotANumber", cameraWith("<height>tall</height>"), "t.xml:5: <height> must be an integer, got \"tall\""},
        {"DuplicateFov", cameraWith("<fov>40</fov><fov>50</fov>"), "t.xml:5: duplicate <fov> in <camera>"},
    };
}

std::vector<BadCase> objectCases() {
    const std::string triangle3 = kVertices;
    return {
        {"UnknownProperty", sphereWith("<radius>1</radius>\n<raduis>1</raduis>"),
         "t.xml:13: unknown element <raduis> in <properties>; expected one of: " + kPropertyList},
        {"UnknownObjectChild",
         sceneWith(objectOf("sphere", "<radius>1</radius>", "<position x=\"0\" y=\"0\" z=\"0\"/><colour/>")),
         "t.xml:9: unknown element <colour> in <object>; expected one of: position, diffuse_color, specular_color, "
         "properties, objects, name"},
        {"DuplicateRadius", sphereWith("<radius>1</radius>\n<radius>2</radius>"),
         "t.xml:13: duplicate <radius> in <properties>"},
        {"MissingProperties", sceneWith("<object>\n<position x=\"0\" y=\"0\" z=\"0\"/></object>"),
         "t.xml:8: <object> is missing <properties>"},
        {"MissingType",
         sceneWith("<object><position x=\"0\" y=\"0\" z=\"0\"/>\n<properties><radius>1</radius></properties></object>"),
         "t.xml:9: <properties> is missing <type>"},
        {"UnknownType", sceneWith(objectOf("cone", "")),
         "t.xml:11: <type> must be sphere, cylinder, mesh, plane, triangle, box or csg, got \"cone\""},
        {"HeightOnSphere", sphereWith("<radius>1</radius>\n<height>2</height>"),
         "t.xml:13: <height> does not apply to type sphere"},
        {"RadiusOnBox", sceneWith(objectOf("box", "<size x=\"1\" y=\"1\" z=\"1\"/>\n<radius>1</radius>")),
         "t.xml:13: <radius> does not apply to type box"},
        {"VertexOnMesh",
         sceneWith(objectOf("mesh", "<polygons><polygon>" + triangle3 + "</polygon></polygons>\n" + kVertices)),
         "t.xml:13: <vertex> does not apply to type mesh"},
        {"PolygonsOnTriangle", sceneWith(objectOf("triangle", triangle3 + "\n<polygons/>")),
         "t.xml:13: <polygons> does not apply to type triangle"},
        {"AxisOnPlane",
         sceneWith(objectOf("plane", "<normal x=\"0\" y=\"1\" z=\"0\"/>\n<axis x=\"0\" y=\"1\" z=\"0\"/>")),
         "t.xml:13: <axis> does not apply to type plane"},
        {"MissingPosition", sceneWith(objectOf("sphere", "<radius>1</radius>", "")),
         "t.xml:8: <object> is missing <position> (required for type sphere)"},
        {"MissingRadius", sphereWith(""), "t.xml:8: <object> is missing <radius> (required for type sphere)"},
        {"CheckerColorWithoutSize", sphereWith("<radius>1</radius>\n<checker_color r=\"0\" g=\"0\" b=\"0\"/>"),
         "t.xml:13: <checker_color> needs <checker_size> beside it in <properties>"},
        {"CheckerSizeWithoutColor", sphereWith("<radius>1</radius>\n<checker_size>1</checker_size>"),
         "t.xml:13: <checker_size> needs <checker_color> beside it in <properties>"},
        {"CheckerSizeZero",
         sphereWith("<radius>1</radius><checker_color r=\"0\" g=\"0\" b=\"0\"/>\n<checker_size>0</checker_size>"),
         "t.xml:13: <checker_size> must be > 0, got 0"},
        {"CheckerColorAboveOne",
         sphereWith("<radius>1</radius>\n<checker_color r=\"2\" g=\"0\" b=\"0\"/><checker_size>1</checker_size>"),
         "t.xml:13: attribute r of <checker_color> must be in [0, 1], got 2"},
        {"NegativeAbsorption", sphereWith("<radius>1</radius>\n<absorption r=\"0\" g=\"-0.5\" b=\"0\"/>"),
         "t.xml:13: attribute g of <absorption> must be >= 0, got -0.5"},
        {"CylinderMissingHeight", sceneWith(objectOf("cylinder", "<radius>1</radius>")),
         "t.xml:8: <object> is missing <height> (required for type cylinder)"},
        {"CylinderZeroHeight", sceneWith(objectOf("cylinder", "<radius>1</radius>\n<height>0</height>")),
         "t.xml:13: <height> must be > 0, got 0"},
        {"CylinderZeroAxis",
         sceneWith(objectOf("cylinder", "<radius>1</radius><height>1</height>\n<axis x=\"0\" y=\"0\" z=\"0\"/>")),
         "t.xml:13: <axis> must not be the zero vector"},
        {"PlaneMissingNormal", sceneWith(objectOf("plane", "")),
         "t.xml:8: <object> is missing <normal> (required for type plane)"},
        {"ZeroNormal", sceneWith(objectOf("plane", "<normal x=\"0\" y=\"0\" z=\"0\"/>")),
         "t.xml:12: <normal> must not be the zero vector"},
        {"BoxMissingSize", sceneWith(objectOf("box", "")),
         "t.xml:8: <object> is missing <size> (required for type box)"},
        {"NegativeBoxSize", sceneWith(objectOf("box", "<size x=\"1\" y=\"-1\" z=\"1\"/>")),
         "t.xml:12: attribute y of <size> must be > 0, got -1"},
        {"FlatBox", sceneWith(objectOf("box", "<size>\n<x>1</x><y>1</y><z>0</z></size>")),
         "t.xml:13: <z> of <size> must be > 0, got 0"},
        {"TriangleWithoutVertices", sceneWith(objectOf("triangle", "")),
         "t.xml:8: <object> is missing <vertex> (required for type triangle)"},
        {"TriangleWithTwoVertices",
         sceneWith(objectOf("triangle", "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/>")),
         "t.xml:10: <properties> has 2 <vertex>, expected 3"},
        {"TriangleWithFourVertices", sceneWith(objectOf("triangle", triangle3 + "<vertex x=\"1\" y=\"1\" z=\"0\"/>")),
         "t.xml:10: <properties> has 4 <vertex>, expected 3"},
        {"DegenerateTriangle",
         sceneWith(objectOf("triangle",
                            "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"1\" z=\"1\"/>"
                            "<vertex x=\"3\" y=\"3\" z=\"3\"/>")),
         "t.xml:8: <object> of type triangle is degenerate: its vertices are collinear"},
        {"BadVertex",
         sceneWith(objectOf("triangle",
                            "<vertex x=\"0\" y=\"0\" z=\"0\"/>\n<vertex x=\"1\" y=\"0\"/>"
                            "<vertex x=\"0\" y=\"1\" z=\"0\"/>")),
         "t.xml:13: <vertex> is missing attribute \"z\""},
        {"MeshWithoutPolygons", sceneWith(objectOf("mesh", "")),
         "t.xml:8: <object> is missing <polygons> or <file> (required for type mesh)"},
        {"EmptyPolygons", sceneWith(objectOf("mesh", "<polygons/>")),
         "t.xml:12: <polygons> has no <polygon>; a mesh needs at least one"},
        {"UnknownInPolygons", sceneWith(objectOf("mesh", "<polygons>\n<poly/></polygons>")),
         "t.xml:13: unknown element <poly> in <polygons>; expected polygon"},
        {"UnknownInPolygon",
         sceneWith(objectOf("mesh", "<polygons><polygon>" + triangle3 + "\n<tangent/></polygon></polygons>")),
         "t.xml:13: unknown element <tangent> in <polygon>; expected one of: vertex, uv, normal"},
        {"PolygonNormalCount",
         sceneWith(objectOf("mesh", "<polygons><polygon>" + triangle3 + "\n<normal x=\"0\" y=\"0\" z=\"1\"/></polygon></polygons>")),
         "t.xml:12: <polygon> has 1 <normal>, expected 3 (one per <vertex>)"},
        {"TwoVertexPolygon",
         sceneWith(objectOf("mesh",
                            "<polygons>\n<polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/>"
                            "</polygon></polygons>")),
         "t.xml:13: <polygon> has 2 <vertex>, expected 3"},
        {"QuadPolygon",
         sceneWith(objectOf(
             "mesh", "<polygons>\n<polygon>" + triangle3 + "<vertex x=\"1\" y=\"1\" z=\"0\"/></polygon></polygons>")),
         "t.xml:13: <polygon> has 4 <vertex>, expected 3"},
        {"AllPolygonsDegenerate",
         sceneWith(objectOf("mesh",
                            "<polygons>\n<polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/>"
                            "<vertex x=\"2\" y=\"0\" z=\"0\"/></polygon></polygons>")),
         "t.xml:12: every <polygon> in <polygons> is degenerate"},
        // Model files (the file's own errors: tests/mesh_file_test.cpp).
        {"MeshFileMissing", sceneWith(objectOf("mesh", "<file>no_such_bunny.obj</file>")),
         "t.xml:12: mesh file \"no_such_bunny.obj\" does not exist"},
        {"MeshFileEmpty", sceneWith(objectOf("mesh", "<file> </file>")),
         "t.xml:12: <file> is empty; expected the path of a model file"},
        {"MeshFileAndPolygons",
         sceneWith(objectOf("mesh", "<polygons><polygon>" + triangle3 + "</polygon></polygons>\n<file>a.obj</file>")),
         "t.xml:13: <properties> has both <polygons> and <file>; a mesh takes one"},
        {"FileOnSphere", sceneWith(objectOf("sphere", "<radius>1</radius>\n<file>a.obj</file>")),
         "t.xml:13: <file> does not apply to type sphere"},
        {"ScaleOnBox", sceneWith(objectOf("box", "<size x=\"1\" y=\"1\" z=\"1\"/>\n<scale>2</scale>")),
         "t.xml:13: <scale> does not apply to type box"},
        {"RotationOnTriangle", sceneWith(objectOf("triangle", triangle3 + "\n<rotation x=\"0\" y=\"90\" z=\"0\"/>")),
         "t.xml:13: <rotation> does not apply to type triangle"},
        {"ZeroScale",
         sceneWith(objectOf("mesh", "<polygons><polygon>" + triangle3 + "</polygon></polygons>\n<scale>0</scale>")),
         "t.xml:13: <scale> must be > 0, got 0"},
        {"NegativeScaleComponent",
         sceneWith(objectOf(
             "mesh", "<polygons><polygon>" + triangle3 + "</polygon></polygons>\n<scale x=\"1\" y=\"-1\" z=\"1\"/>")),
         "t.xml:13: attribute y of <scale> must be > 0, got -1"},
        {"ScaledBeyondRange",
         sceneWith(objectOf("mesh",
                            "<polygons><polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1e6\" y=\"0\" "
                            "z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/></polygon></polygons>\n<scale>2</scale>")),
         "t.xml:12: <scale> and <rotation> take vertex (1e+06, 0, 0) beyond ±1e6 of the object's <position>"},
        {"RotatedBeyondRange",
         sceneWith(objectOf("mesh",
                            "<polygons><polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1e6\" y=\"1e6\" "
                            "z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/></polygon></polygons>\n"
                            "<rotation x=\"0\" y=\"0\" z=\"45\"/>")),
         "t.xml:12: <scale> and <rotation> take vertex (1e+06, 1e+06, 0) beyond ±1e6 of the object's <position>"},
        {"RotationMissingZ",
         sceneWith(objectOf("mesh", "<polygons><polygon>" + triangle3 +
                                        "</polygon></polygons>\n<rotation><x>1</x><y>2</y></rotation>")),
         "t.xml:13: <rotation> is missing <z>"},
    };
}

auto caseName = [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); };

INSTANTIATE_TEST_SUITE_P(Xml, SceneLoaderErrorTest, ::testing::ValuesIn(xmlCases()), caseName);
INSTANTIATE_TEST_SUITE_P(Values, SceneLoaderErrorTest, ::testing::ValuesIn(valueCases()), caseName);
INSTANTIATE_TEST_SUITE_P(VectorsAndColours, SceneLoaderErrorTest, ::testing::ValuesIn(vectorAndColourCases()),
                         caseName);
INSTANTIATE_TEST_SUITE_P(LightsAndCamera, SceneLoaderErrorTest, ::testing::ValuesIn(lightAndCameraCases()), caseName);
INSTANTIATE_TEST_SUITE_P(Objects, SceneLoaderErrorTest, ::testing::ValuesIn(objectCases()), caseName);

}  // namespace
}  // namespace whitted::test

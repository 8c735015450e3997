// The XML scene loader: the seed's schema, the extensions, and every way a
// file can be wrong, with the messages checked word for word (Mitsuba's
// test_parser.py style).
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

#include <fstream>

namespace whitted {
namespace {

// The seed's own element form: one of each of its object types.
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
  </lights>
  <objects>
    <object>
      <position><x>0</x><y>1</y><z>0</z></position>
      <diffuse_color><r>1</r><g>0</g><b>0</b><a>1</a></diffuse_color>
      <specular_color><r>0.5</r><g>0.5</g><b>0.5</b><a>1</a></specular_color>
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
    <object>
      <position><x>2</x><y>0</y><z>-1</z></position>
      <diffuse_color><r>0</r><g>0</g><b>1</b><a>1</a></diffuse_color>
      <specular_color><r>1</r><g>1</g><b>1</b><a>1</a></specular_color>
      <properties>
        <type>cylinder</type>
        <refraction_coef>1</refraction_coef>
        <transmission_coef>0</transmission_coef>
        <specular_coef>0</specular_coef>
        <diffuse_coef>1</diffuse_coef>
        <ambiente_coef>0</ambiente_coef>
        <reflective>false</reflective>
        <radius>0.5</radius>
        <height>2</height>
      </properties>
    </object>
    <object>
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

Scene load(const std::string& xml) { return loadSceneFromString(xml, "t.xml"); }

// The error message for `xml`, or "" if it loads.
std::string errorOf(const std::string& xml) {
    try {
        load(xml);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// A minimal valid scene around an <objects> body; line 1 is <scene>, the
// objects start on line 3.
std::string withObjects(const std::string& objects, const std::string& camera = "") {
    return "<scene>\n<camera><position x=\"0\" y=\"0\" z=\"5\"/><window_position x=\"0\" y=\"0\" z=\"4\"/>" + camera +
           "</camera><lights><light><position x=\"0\" y=\"5\" z=\"0\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>\n"
           "<objects>" + objects + "</objects>\n</scene>";
}

std::string sphereWith(const std::string& properties) {
    return "<object><position x=\"0\" y=\"0\" z=\"0\"/><properties><type>sphere</type>" + properties +
           "</properties></object>";
}

TEST(SceneLoader, ReadsTheSeedSchema) {
    Scene s = load(kSeedScene);
    EXPECT_EQ(s.camera.eye, glm::dvec3(0, 1, 5));
    EXPECT_EQ(s.camera.windowCenter, glm::dvec3(0, 1, 4));
    EXPECT_EQ(s.camera.verticalFovDegrees, 60.0);
    EXPECT_EQ(s.camera.width, 640);
    EXPECT_EQ(s.camera.height, 480);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].position, glm::dvec3(1, 4, 2));
    EXPECT_EQ(s.lights[0].color, glm::dvec3(0.5, 0.6, 0.7));
    ASSERT_EQ(s.objects.size(), 3u);

    const Object& sphere = s.objects[0];
    ASSERT_TRUE(std::holds_alternative<Sphere>(sphere.shape));
    EXPECT_EQ(std::get<Sphere>(sphere.shape).center, glm::dvec3(0, 1, 0));
    EXPECT_EQ(std::get<Sphere>(sphere.shape).radius, 0.75);
    EXPECT_EQ(sphere.material.diffuseColor, glm::dvec3(1, 0, 0));
    EXPECT_EQ(sphere.material.specularColor, glm::dvec3(0.5, 0.5, 0.5));
    EXPECT_EQ(sphere.material.ior, 1.5);
    EXPECT_EQ(sphere.material.transmission, 0.2);
    EXPECT_EQ(sphere.material.specular, 0.4);
    EXPECT_EQ(sphere.material.diffuse, 0.6);
    EXPECT_EQ(sphere.material.ambient, 0.1);
    EXPECT_EQ(sphere.material.reflection, 0.4) << "reflective: kr = ks";
    EXPECT_EQ(sphere.material.shininess, 32.0);
    EXPECT_EQ(sphere.sourceLine, 14);

    const Cylinder& c = std::get<Cylinder>(s.objects[1].shape);
    EXPECT_EQ(c.base, glm::dvec3(2, 0, -1));
    EXPECT_EQ(c.axis, glm::dvec3(0, 1, 0));
    EXPECT_EQ(c.radius, 0.5);
    EXPECT_EQ(c.height, 2.0);
    EXPECT_EQ(s.objects[1].material.reflection, 0.0);

    const Mesh& m = std::get<Mesh>(s.objects[2].shape);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0].v0, glm::dvec3(-1, -1, 1)) << "vertices are relative to the position";
    EXPECT_EQ(m.triangles[1].v2, glm::dvec3(-1, -1, -1));
    EXPECT_TRUE(s.warnings.empty());
}

TEST(SceneLoader, ReadsTheAttributeForm) {
    Scene s = load(withObjects(
        "<object><position x=\"1\" y=\"2\" z=\"3\"/><diffuse_color r=\"0.1\" g=\"0.2\" b=\"0.3\" a=\"1\"/>"
        "<properties><type>sphere</type><radius>1</radius></properties></object>"));
    EXPECT_EQ(std::get<Sphere>(s.objects[0].shape).center, glm::dvec3(1, 2, 3));
    EXPECT_EQ(s.objects[0].material.diffuseColor, glm::dvec3(0.1, 0.2, 0.3));
    EXPECT_EQ(s.lights[0].color, glm::dvec3(1, 1, 1));
}

TEST(SceneLoader, MaterialDefaults) {
    Material m = load(withObjects(sphereWith("<radius>1</radius>"))).objects[0].material;
    EXPECT_EQ(m.diffuseColor, glm::dvec3(1, 1, 1));
    EXPECT_EQ(m.specularColor, glm::dvec3(1, 1, 1));
    EXPECT_EQ(m.ambient, 0.0);
    EXPECT_EQ(m.diffuse, 1.0);
    EXPECT_EQ(m.specular, 0.0);
    EXPECT_EQ(m.transmission, 0.0);
    EXPECT_EQ(m.ior, 1.0);
    EXPECT_EQ(m.reflection, 0.0);
}

TEST(SceneLoader, CameraExtensions) {
    Scene s = load(withObjects("", "<fov>45</fov><up x=\"2\" y=\"0\" z=\"0\"/><width>320</width><height>200</height>"));
    EXPECT_EQ(s.camera.verticalFovDegrees, 45.0);
    EXPECT_EQ(s.camera.up, glm::dvec3(1, 0, 0));
    EXPECT_EQ(s.camera.width, 320);
    EXPECT_EQ(s.camera.height, 200);
    // The window is 1 unit from the eye: a window 2 units high spans 90 degrees.
    Scene w = load(withObjects("", "<window_height>2</window_height>"));
    EXPECT_NEAR(w.camera.verticalFovDegrees, 90.0, 1e-12);
}

TEST(SceneLoader, AmbientLightShininessAndReflectionCoefficient) {
    Scene s = load(withObjects(sphereWith("<radius>1</radius><shininess>200</shininess><specular_coef>0.3</specular_coef>"
                                          "<reflection_coef>0.8</reflection_coef>")) );
    EXPECT_EQ(s.objects[0].material.shininess, 200.0);
    EXPECT_EQ(s.objects[0].material.reflection, 0.8);
    std::string xml = withObjects("");
    xml.insert(xml.find("<lights>"), "<ambient_light r=\"0.2\" g=\"0.3\" b=\"2\"/>");
    EXPECT_EQ(load(xml).ambientLight, glm::dvec3(0.2, 0.3, 2));
}

TEST(SceneLoader, NewShapeTypes) {
    Scene s = load(withObjects(
        "<object><position x=\"0\" y=\"-1\" z=\"0\"/><properties><type>plane</type><normal x=\"0\" y=\"2\" z=\"0\"/>"
        "</properties></object>"
        "<object><position x=\"1\" y=\"0\" z=\"0\"/><properties><type>triangle</type><vertex x=\"0\" y=\"0\" z=\"0\"/>"
        "<vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/></properties></object>"
        "<object><position x=\"-1\" y=\"0\" z=\"-1\"/><properties><type>box</type><size x=\"1\" y=\"2\" z=\"3\"/>"
        "</properties></object>"
        "<object><position x=\"0\" y=\"0\" z=\"0\"/><properties><type>cylinder</type><radius>1</radius>"
        "<height>2</height><axis x=\"3\" y=\"0\" z=\"4\"/></properties></object>"));
    const Plane& plane = std::get<Plane>(s.objects[0].shape);
    EXPECT_EQ(plane.normal, glm::dvec3(0, 1, 0));
    EXPECT_EQ(plane.point, glm::dvec3(0, -1, 0));
    const Triangle& t = std::get<Triangle>(s.objects[1].shape);
    EXPECT_EQ(t.v1, glm::dvec3(2, 0, 0));
    const Box& b = std::get<Box>(s.objects[2].shape);
    EXPECT_EQ(b.min, glm::dvec3(-1, 0, -1));
    EXPECT_EQ(b.max, glm::dvec3(0, 2, 2));
    EXPECT_EQ(std::get<Cylinder>(s.objects[3].shape).axis, glm::dvec3(0.6, 0, 0.8));
}

TEST(SceneLoader, DegenerateButLegalInputWarns) {
    Scene noLights = load("<scene><camera><position x=\"0\" y=\"0\" z=\"1\"/><window_position x=\"0\" y=\"0\" z=\"0\"/>"
                          "</camera>\n<lights/><objects/></scene>");
    ASSERT_EQ(noLights.warnings.size(), 2u);
    EXPECT_EQ(noLights.warnings[0], "t.xml:2: scene has no lights; only ambient light will show");
    EXPECT_EQ(noLights.warnings[1], "t.xml:2: scene has no objects; the image will be black");

    Scene mesh = load(withObjects(
        "<object><properties><type>mesh</type><polygons>\n"
        "<polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/></polygon>\n"
        "<polygon><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"1\" z=\"1\"/><vertex x=\"2\" y=\"2\" z=\"2\"/></polygon>\n"
        "</polygons></properties></object>"));
    EXPECT_EQ(std::get<Mesh>(mesh.objects[0].shape).triangles.size(), 1u);
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_EQ(mesh.warnings[0], "t.xml:5: degenerate polygon skipped");
}

TEST(SceneLoader, FileErrors) {
    try {
        loadScene("/nonexistent/scene.xml");
        FAIL() << "no exception";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.xml: cannot read file: no such file");
        EXPECT_EQ(e.line(), 0);
    }
}

// Each bad input and its exact message.
struct BadCase {
    const char* name;
    std::string xml;
    std::string message;
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class SceneLoaderErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(SceneLoaderErrors, GivesFileLineAndWhat) { EXPECT_EQ(errorOf(GetParam().xml), GetParam().message); }

std::string nested(int depth) {
    std::string s;
    for (int i = 0; i < depth; ++i) s += "<a>";
    for (int i = 0; i < depth; ++i) s += "</a>";
    return s;
}

std::vector<BadCase> badCases() {
    const std::string cam = "<position x=\"0\" y=\"0\" z=\"5\"/><window_position x=\"0\" y=\"0\" z=\"4\"/>";
    return {
        {"Truncated", "<scene>\n<camera>", "t.xml:2: malformed XML (XML_ERROR_MISMATCHED_ELEMENT): XMLElement name=camera"},
        {"WrongRoot", "<scenery/>", "t.xml:1: root element is <scenery>, expected <scene>"},
        {"MissingCamera", "<scene>\n<lights/><objects/></scene>", "t.xml:1: <scene> is missing <camera>"},
        {"MissingLights", "<scene><camera>" + cam + "</camera><objects/></scene>", "t.xml:1: <scene> is missing <lights>"},
        {"UnknownTopLevel", "<scene><camera>" + cam + "</camera><lights/><objects/>\n<lamps/></scene>",
         "t.xml:2: unknown element <lamps> in <scene>; expected one of: camera, lights, objects, ambient_light"},
        {"UnknownProperty", withObjects(sphereWith("<raduis>1</raduis>")),
         "t.xml:3: unknown element <raduis> in <properties>; expected one of: type, refraction_coef, transmission_coef, "
         "specular_coef, diffuse_coef, ambiente_coef, reflective, shininess, reflection_coef, axis, height, normal, "
         "polygons, radius, size, vertex"},
        {"DuplicateRadius", withObjects(sphereWith("<radius>1</radius><radius>2</radius>")),
         "t.xml:3: duplicate <radius> in <properties>"},
        {"MissingRadius", withObjects(sphereWith("")), "t.xml:3: <properties> is missing <radius> (required for type sphere)"},
        {"NegativeRadius", withObjects(sphereWith("<radius>-1</radius>")), "t.xml:3: <radius> must be > 0, got -1"},
        {"ZeroRadius", withObjects(sphereWith("<radius>0</radius>")), "t.xml:3: <radius> must be > 0, got 0"},
        {"NotANumber", withObjects(sphereWith("<radius>abc</radius>")), "t.xml:3: <radius> must be a number, got \"abc\""},
        {"TrailingGarbage", withObjects(sphereWith("<radius>1.5x</radius>")),
         "t.xml:3: <radius> must be a number, got \"1.5x\""},
        {"NaN", withObjects(sphereWith("<radius>nan</radius>")), "t.xml:3: <radius> must be a finite number, got \"nan\""},
        {"Infinity", withObjects(sphereWith("<radius>inf</radius>")), "t.xml:3: <radius> must be a finite number, got \"inf\""},
        {"Huge", withObjects(sphereWith("<radius>1e9</radius>")), "t.xml:3: <radius> must be within ±1e6, got 1e9"},
        {"Overflow", withObjects(sphereWith("<radius>1e999</radius>")),
         "t.xml:3: <radius> must be a finite number, got \"1e999\""},
        {"UnknownType", withObjects("<object><position x=\"0\" y=\"0\" z=\"0\"/><properties><type>cone</type></properties></object>"),
         "t.xml:3: unknown object type \"cone\"; expected one of: sphere, cylinder, mesh, plane, triangle, box"},
        {"NotApplicable", withObjects(sphereWith("<radius>1</radius><height>2</height>")),
         "t.xml:3: <height> does not apply to type sphere"},
        {"CoefficientRange", withObjects(sphereWith("<radius>1</radius><diffuse_coef>1.5</diffuse_coef>")),
         "t.xml:3: <diffuse_coef> must be in [0, 1], got 1.5"},
        {"BadBoolean", withObjects(sphereWith("<radius>1</radius><reflective>yes</reflective>")),
         "t.xml:3: <reflective> must be true or false, got \"yes\""},
        {"ReflectionContradiction",
         withObjects(sphereWith("<radius>1</radius><reflective>false</reflective><reflection_coef>0.5</reflection_coef>")),
         "t.xml:3: <reflection_coef> contradicts <reflective>false</reflective>"},
        {"ColourRange",
         withObjects("<object><position x=\"0\" y=\"0\" z=\"0\"/><diffuse_color r=\"2\" g=\"0\" b=\"0\"/>"
                     "<properties><type>sphere</type><radius>1</radius></properties></object>"),
         "t.xml:3: <diffuse_color> channels must be in [0, 1], got 2"},
        {"MixedForm", withObjects("<object><position x=\"0\"><y>0</y><z>0</z></position><properties><type>sphere</type>"
                                  "<radius>1</radius></properties></object>"),
         "t.xml:3: <position> mixes attributes and child elements"},
        {"UnknownAttribute", withObjects("<object><position x=\"0\" y=\"0\" z=\"0\" w=\"1\"/><properties><type>sphere</type>"
                                         "<radius>1</radius></properties></object>"),
         "t.xml:3: unknown attribute \"w\" on <position>; expected x, y, z"},
        {"MissingComponent", withObjects("<object><position><x>0</x><y>0</y></position><properties><type>sphere</type>"
                                         "<radius>1</radius></properties></object>"),
         "t.xml:3: <position> is missing <z>"},
        {"MissingPosition", withObjects("<object><properties><type>sphere</type><radius>1</radius></properties></object>"),
         "t.xml:3: <object> is missing <position>"},
        {"EmptyMesh", withObjects("<object><properties><type>mesh</type><polygons/></properties></object>"),
         "t.xml:3: <polygons> has no <polygon>; a mesh needs at least one"},
        {"MeshWithoutPolygons", withObjects("<object><properties><type>mesh</type></properties></object>"),
         "t.xml:3: <properties> is missing <polygons> (required for type mesh)"},
        {"TwoVertexPolygon",
         withObjects("<object><properties><type>mesh</type><polygons><polygon><vertex x=\"0\" y=\"0\" z=\"0\"/>"
                     "<vertex x=\"1\" y=\"0\" z=\"0\"/></polygon></polygons></properties></object>"),
         "t.xml:3: <polygon> has 2 <vertex>, expected 3"},
        {"AllPolygonsDegenerate",
         withObjects("<object><properties><type>mesh</type><polygons><polygon><vertex x=\"0\" y=\"0\" z=\"0\"/>"
                     "<vertex x=\"1\" y=\"0\" z=\"0\"/><vertex x=\"2\" y=\"0\" z=\"0\"/></polygon></polygons>"
                     "</properties></object>"),
         "t.xml:3: every <polygon> of the mesh is degenerate"},
        {"DegenerateTriangle",
         withObjects("<object><properties><type>triangle</type><vertex x=\"0\" y=\"0\" z=\"0\"/>"
                     "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/></properties></object>"),
         "t.xml:3: degenerate triangle: its vertices are collinear"},
        {"ZeroNormal", withObjects("<object><position x=\"0\" y=\"0\" z=\"0\"/><properties><type>plane</type>"
                                   "<normal x=\"0\" y=\"0\" z=\"0\"/></properties></object>"),
         "t.xml:3: <normal> must not be the zero vector"},
        {"NegativeBoxSize", withObjects("<object><position x=\"0\" y=\"0\" z=\"0\"/><properties><type>box</type>"
                                        "<size x=\"1\" y=\"-1\" z=\"1\"/></properties></object>"),
         "t.xml:3: <size> components must be > 0, got 1, -1, 1"},
        {"CameraAtWindow", "<scene><camera><position x=\"1\" y=\"1\" z=\"1\"/><window_position x=\"1\" y=\"1\" z=\"1\"/>"
                           "</camera><lights/><objects/></scene>",
         "t.xml:1: camera <position> and <window_position> coincide"},
        {"UpParallel", withObjects("", "<up x=\"0\" y=\"0\" z=\"1\"/>"),
         "t.xml:2: camera <up> is parallel to the viewing direction"},
        {"FovAndWindowHeight", withObjects("", "<fov>40</fov><window_height>1</window_height>"),
         "t.xml:2: <camera> has both <fov> and <window_height>; give one"},
        {"FovRange", withObjects("", "<fov>180</fov>"), "t.xml:2: <fov> must be in (0, 180) degrees, got 180"},
        {"WidthZero", withObjects("", "<width>0</width>"), "t.xml:2: <width> must be in [1, 16384], got 0"},
        {"WidthHuge", withObjects("", "<width>100000</width>"), "t.xml:2: <width> must be in [1, 16384], got 100000"},
        {"WidthFraction", withObjects("", "<width>12.5</width>"), "t.xml:2: <width> must be an integer, got \"12.5\""},
        {"LightWithoutColour", "<scene><camera>" + cam + "</camera><lights>\n<light><position x=\"0\" y=\"0\" z=\"0\"/>"
                               "</light></lights><objects/></scene>",
         "t.xml:2: <light> is missing <color>"},
        {"NegativeLight", "<scene><camera>" + cam + "</camera><lights>\n<light><position x=\"0\" y=\"0\" z=\"0\"/>"
                          "<color r=\"-1\" g=\"0\" b=\"0\"/></light></lights><objects/></scene>",
         "t.xml:2: <color> channels must be in [0, 1e+06], got -1"},
        {"DeepNesting", "<scene>" + nested(1000),
         "t.xml:1: malformed XML (XML_ELEMENT_DEPTH_EXCEEDED): Element nesting is too deep."},
    };
}

INSTANTIATE_TEST_SUITE_P(BadInput, SceneLoaderErrors, ::testing::ValuesIn(badCases()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace whitted

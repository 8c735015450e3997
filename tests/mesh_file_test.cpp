// Meshes from model files (<file>, host/io/mesh_file.h) and the placement of
// any mesh (<scale>, <rotation>): what loads, what renders, what is refused.
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>

#include "scene/scene_loader.h"
#include "shapes/shapes.h"
#include "test_support.h"

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

fs::path meshDir() {
    return sourceDir() / "tests" / "meshes";
}

// A scene file in tests/meshes (so <file> paths are relative to that
// folder) with a camera at (0, 1.5, 4) looking at (0, 0.5, 0), a light beside
// it, and `objects`. Lines: 1 <scene>, 2 <camera>, 3 <lights>, 4 <objects>,
// objects from line 5.
Scene loadWith(const std::string& objects) {
    std::string xml =
        "<scene>\n"
        "<camera><position x=\"0\" y=\"1.5\" z=\"4\"/><window_position x=\"0\" y=\"1.25\" z=\"3\"/>"
        "<width>48</width><height>36</height><fov>40</fov></camera>\n"
        "<lights><light><position x=\"3\" y=\"4\" z=\"5\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>\n"
        "<objects>\n" +
        objects + "</objects>\n</scene>\n";
    return loadSceneFromString(xml, meshDir() / "t.xml");
}

// A mesh object: line 5 <object>, 6 <properties> and <type>, 7 `body`.
std::string meshObject(const std::string& body, const std::string& position = "x=\"0\" y=\"0\" z=\"0\"") {
    return "<object><position " + position +
           "/><diffuse_color r=\"0.9\" g=\"0.6\" b=\"0.3\"/>\n"
           "<properties><type>mesh</type><diffuse_coef>0.8</diffuse_coef><ambiente_coef>0.1</ambiente_coef>"
           "<specular_coef>0.4</specular_coef>\n" +
           body + "\n</properties></object>\n";
}

// The pyramid of tests/meshes/pyramid.obj, written inline.
std::string pyramidPolygons() {
    const char* v[] = {R"(x="-0.5" y="0" z="-0.5")", R"(x="0.5" y="0" z="-0.5")", R"(x="0.5" y="0" z="0.5")",
                       R"(x="-0.5" y="0" z="0.5")", R"(x="0" y="1" z="0")"};
    const int faces[6][3] = {{3, 2, 4}, {2, 1, 4}, {1, 0, 4}, {0, 3, 4}, {0, 1, 2}, {0, 2, 3}};
    std::string xml = "<polygons>";
    for (const auto& f : faces) {
        xml += "<polygon>";
        for (int k : f) xml += std::string("<vertex ") + v[k] + "/>";
        xml += "</polygon>";
    }
    return xml + "</polygons>";
}

const Mesh& onlyMesh(const Scene& scene) {
    EXPECT_EQ(scene.objects.size(), 1u);
    return std::get<Mesh>(scene.objects.at(0).shape);
}

void expectNear(const glm::dvec3& actual, const glm::dvec3& expected, double tolerance = 1e-12) {
    EXPECT_LE(glm::length(actual - expected), tolerance)
        << "got (" << actual.x << ", " << actual.y << ", " << actual.z << "), expected (" << expected.x << ", "
        << expected.y << ", " << expected.z << ")";
}

void expectBitIdentical(const RenderResult& a, const RenderResult& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    for (uint32_t layer = 0; layer < gpu::kAovCount; ++layer) {
        ASSERT_EQ(a.layers[layer].size(), b.layers[layer].size());
        EXPECT_EQ(std::memcmp(a.layers[layer].data(), b.layers[layer].data(), a.layers[layer].size() * sizeof(float)),
                  0)
            << "layer " << layer << " differs";
    }
}

RenderSettings small() {
    return {.width = 48, .height = 36, .samplesPerPixel = 2, .maxDepth = 2, .auxiliary = true};
}

// ---- What loads ---------------------------------------------------------------

TEST(MeshFile, ObjLoadsTheSameTrianglesAsInline) {
    Mesh file = onlyMesh(loadWith(meshObject("<file>pyramid.obj</file>")));
    Mesh inline_ = onlyMesh(loadWith(meshObject(pyramidPolygons())));
    ASSERT_EQ(file.triangles.size(), 6u);
    ASSERT_EQ(inline_.triangles.size(), 6u);
    EXPECT_TRUE(file.normals.empty()) << "pyramid.obj has no normals: flat";
    for (size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(file.triangles[i].v0, inline_.triangles[i].v0) << i;
        EXPECT_EQ(file.triangles[i].v1, inline_.triangles[i].v1) << i;
        EXPECT_EQ(file.triangles[i].v2, inline_.triangles[i].v2) << i;
    }
}

TEST(MeshFile, PlyLoadsTheSameTrianglesAsObj) {
    Mesh ply = onlyMesh(loadWith(meshObject("<file>pyramid.ply</file>")));
    Mesh obj = onlyMesh(loadWith(meshObject("<file>pyramid.obj</file>")));
    ASSERT_EQ(ply.triangles.size(), obj.triangles.size());
    EXPECT_TRUE(ply.normals.empty());
    for (size_t i = 0; i < obj.triangles.size(); ++i) {
        EXPECT_EQ(ply.triangles[i].v0, obj.triangles[i].v0) << i;
        EXPECT_EQ(ply.triangles[i].v1, obj.triangles[i].v1) << i;
        EXPECT_EQ(ply.triangles[i].v2, obj.triangles[i].v2) << i;
    }
}

// An absolute path works as well as one relative to the scene file.
TEST(MeshFile, AbsolutePath) {
    Mesh mesh = onlyMesh(loadWith(meshObject("<file>" + (meshDir() / "pyramid.obj").string() + "</file>")));
    EXPECT_EQ(mesh.triangles.size(), 6u);
}

// ---- Placement: world = position + Rz Ry Rx (S v) ------------------------------

TEST(MeshPlacement, ScaleThenRotateThenTranslateInline) {
    std::string polygon = R"(<polygons><polygon><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/>)"
                          R"(<vertex x="0" y="0" z="1"/></polygon></polygons>)";
    Mesh mesh = onlyMesh(loadWith(meshObject(polygon + R"(<scale x="2" y="3" z="4"/><rotation x="0" y="0" z="90"/>)",
                                             R"(x="10" y="20" z="30")")));
    ASSERT_EQ(mesh.triangles.size(), 1u);
    // S: (2,0,0) (0,3,0) (0,0,4); Rz(90): (x, y) -> (-y, x); then + position.
    expectNear(mesh.triangles[0].v0, {10, 22, 30});
    expectNear(mesh.triangles[0].v1, {7, 20, 30});
    expectNear(mesh.triangles[0].v2, {10, 20, 34});
}

// Rotation about x first, then y, then z (fixed axes): Rz(90) Rx(90) takes
// (x, y, z) to (z, x, y); the other order would give (-y, -z, x).
TEST(MeshPlacement, RotationOrderIsXThenYThenZ) {
    std::string polygon = R"(<polygons><polygon><vertex x="0" y="0" z="0"/><vertex x="1" y="2" z="3"/>)"
                          R"(<vertex x="-2" y="1" z="0.5"/></polygon></polygons>)";
    Mesh mesh = onlyMesh(loadWith(meshObject(polygon + "<rotation><x>90</x><y>0</y><z>90</z></rotation>")));
    ASSERT_EQ(mesh.triangles.size(), 1u);
    expectNear(mesh.triangles[0].v0, {0, 0, 0});
    expectNear(mesh.triangles[0].v1, {3, 1, 2});
    expectNear(mesh.triangles[0].v2, {0.5, -2, 1});

    // Ry alone: (x, y, z) -> (z, y, -x) for 90 degrees.
    Mesh ry = onlyMesh(loadWith(meshObject(polygon + R"(<rotation x="0" y="90" z="0"/>)")));
    expectNear(ry.triangles[0].v1, {3, 2, -1});
}

TEST(MeshPlacement, UniformScaleAndPositionOnAFile) {
    Mesh mesh = onlyMesh(loadWith(meshObject("<file>pyramid.obj</file><scale>2</scale>", R"(x="1" y="1" z="1")")));
    ASSERT_EQ(mesh.triangles.size(), 6u);
    // Face 1 is (v4, v3, v5) of the file: (-0.5,0,0.5) (0.5,0,0.5) (0,1,0).
    expectNear(mesh.triangles[0].v0, {0, 1, 2});
    expectNear(mesh.triangles[0].v1, {2, 1, 2});
    expectNear(mesh.triangles[0].v2, {1, 3, 1});
}

// Normals go through the inverse transpose R S^-1: with S = (2, 1, 1) the
// normal (1, 1, 0)/sqrt(2) becomes (1, 2, 0)/sqrt(5); then Rz(90) turns it
// to (-2, 1, 0)/sqrt(5).
TEST(MeshPlacement, NormalsUseTheInverseTranspose) {
    Mesh scaled = onlyMesh(loadWith(meshObject(R"(<file>tilted_normals.obj</file><scale x="2" y="1" z="1"/>)")));
    ASSERT_EQ(scaled.normals.size(), 1u);
    for (const glm::dvec3& n : scaled.normals[0]) expectNear(n, glm::dvec3(1, 2, 0) / std::sqrt(5.0), 1e-7);
    Mesh rotated = onlyMesh(loadWith(
        meshObject(R"(<file>tilted_normals.obj</file><scale x="2" y="1" z="1"/><rotation x="0" y="0" z="90"/>)")));
    for (const glm::dvec3& n : rotated.normals[0]) expectNear(n, glm::dvec3(-2, 1, 0) / std::sqrt(5.0), 1e-7);
}

// ---- Renders: a file and the same triangles inline are the same image ------------

TEST(MeshRender, ObjAndInlineAreBitIdentical) {
    std::string placement = R"(<scale x="1.5" y="1" z="1.25"/><rotation x="0" y="30" z="10"/>)";
    RenderResult file = renderScene(loadWith(meshObject("<file>pyramid.obj</file>" + placement)), small());
    RenderResult inline_ = renderScene(loadWith(meshObject(pyramidPolygons() + placement)), small());
    expectBitIdentical(file, inline_);
    // And the pyramid is there: a good share of the pixels are hit.
    int hits = 0;
    for (int y = 0; y < file.height; ++y)
        for (int x = 0; x < file.width; ++x) hits += pixel(file, gpu::kAovNormal, x, y).w > 0.5f;
    EXPECT_GT(hits, file.width * file.height / 10);
}

TEST(MeshRender, PlyAndInlineAreBitIdentical) {
    RenderResult file = renderScene(loadWith(meshObject("<file>pyramid.ply</file>")), small());
    RenderResult inline_ = renderScene(loadWith(meshObject(pyramidPolygons())), small());
    expectBitIdentical(file, inline_);
}

// ---- Smooth shading ---------------------------------------------------------------

// A UV sphere of unit radius about the origin: `stacks` bands of latitude,
// `slices` of longitude, triangles wound outwards; with normals (the unit
// position of each vertex) or without.
void writeUvSphereObj(const fs::path& path, int stacks, int slices, bool normals) {
    std::ofstream out(path);
    const double pi = std::numbers::pi;
    for (int i = 0; i <= stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            double theta = pi * i / stacks, phi = 2 * pi * j / slices;
            glm::dvec3 p(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
            out << "v " << p.x << " " << p.y << " " << p.z << "\n";
            if (normals) out << "vn " << p.x << " " << p.y << " " << p.z << "\n";
        }
    auto index = [&](int i, int j) { return i * slices + (j % slices) + 1; };
    auto corner = [&](int k) { return normals ? std::to_string(k) + "//" + std::to_string(k) : std::to_string(k); };
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            int a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
            if (i > 0) out << "f " << corner(a) << " " << corner(b) << " " << corner(d) << "\n";
            if (i < stacks - 1) out << "f " << corner(d) << " " << corner(b) << " " << corner(c) << "\n";
        }
}

struct SphereComparison {
    double meanNormalDegrees = 0;  // shading normal against the true sphere's
    double meanColourError = 0;    // |mesh - analytic sphere| per channel, 0..1
    int pixels = 0;                // hit by both
};

// A Lambert sphere lit from the eye (the scene of RenderAnalytic.
// LambertSphereLitFromTheEye), rendered as the analytic sphere and as
// `meshFile` placed on it, compared where both are hit.
SphereComparison compareWithAnalyticSphere(const fs::path& meshFile) {
    auto scene = [](const std::string& object) {
        return "<scene><camera><position x=\"0\" y=\"0\" z=\"0\"/><window_position x=\"0\" y=\"0\" z=\"-1\"/>"
               "<width>64</width><height>48</height></camera>"
               "<lights><light><position x=\"0\" y=\"0\" z=\"0\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>"
               "<objects><object><position x=\"0.3\" y=\"-0.2\" z=\"-4\"/><properties><type>" +
               object + "<diffuse_coef>0.8</diffuse_coef></properties></object></objects></scene>";
    };
    RenderSettings settings{.width = 64, .height = 48, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true};
    RenderResult sphere = renderXml(scene("sphere</type><radius>1.5</radius>"), settings);
    RenderResult mesh =
        renderXml(scene("mesh</type><file>" + meshFile.string() + "</file><scale>1.5</scale>"), settings);

    const glm::dvec3 center(0.3, -0.2, -4.0);
    const double tanHalf = std::tan(glm::radians(60.0) / 2.0), aspect = 64.0 / 48.0;
    SphereComparison c;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            if (pixel(sphere, gpu::kAovNormal, x, y).w < 0.5f || pixel(mesh, gpu::kAovNormal, x, y).w < 0.5f) continue;
            // The true normal where the pixel's ray meets the sphere.
            glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / 64.0 - 1.0) * tanHalf * aspect,
                                                     (1.0 - 2.0 * (y + 0.5) / 48.0) * tanHalf, -1.0));
            double b = glm::dot(-center, d), cc = glm::dot(center, center) - 1.5 * 1.5;
            double t = -b - std::sqrt(std::max(b * b - cc, 0.0));
            glm::dvec3 trueNormal = glm::normalize(t * d - center);
            glm::dvec3 n = glm::normalize(glm::dvec3(glm::vec3(pixel(mesh, gpu::kAovNormal, x, y))));
            c.meanNormalDegrees += glm::degrees(std::acos(std::clamp(glm::dot(n, trueNormal), -1.0, 1.0)));
            glm::vec4 diff = pixel(mesh, gpu::kAovColor, x, y) - pixel(sphere, gpu::kAovColor, x, y);
            c.meanColourError += (std::abs(diff.r) + std::abs(diff.g) + std::abs(diff.b)) / 3.0;
            ++c.pixels;
        }
    c.meanNormalDegrees /= std::max(c.pixels, 1);
    c.meanColourError /= std::max(c.pixels, 1);
    return c;
}

// UV spheres of k x 2k facets with and without vertex normals against the
// true sphere, at k = 12 and 24. Interpolated normals converge to the
// sphere's at second order in the facet size (the error quarters when k
// doubles: what is left is the facets lying inside the sphere), flat facets
// at first order only (the error halves). Measured on lavapipe: mean normal
// error 0.88 -> 0.22 degrees smooth, 5.5 -> 2.7 flat; mean colour error
// 0.010 -> 0.0026 smooth, 0.034 -> 0.017 flat.
TEST(MeshRender, SmoothNormalsApproachTheAnalyticSphere) {
    // c[0][*]: k = 12, c[1][*]: k = 24; c[*][0]: smooth, c[*][1]: flat.
    SphereComparison c[2][2];
    for (int level = 0; level < 2; ++level)
        for (int flat = 0; flat < 2; ++flat) {
            int k = 12 << level;
            fs::path file = outputDir() / ("uv_sphere_" + std::to_string(k) + (flat ? "_flat" : "_smooth") + ".obj");
            writeUvSphereObj(file, k, 2 * k, !flat);
            SphereComparison& r = c[level][flat];
            r = compareWithAnalyticSphere(file);
            ASSERT_GT(r.pixels, 800) << file;
            std::printf("%d x %d %s: mean normal error %.3f deg, mean colour error %.4f over %d pixels\n", k, 2 * k,
                        flat ? "flat" : "smooth", r.meanNormalDegrees, r.meanColourError, r.pixels);
        }
    const SphereComparison &smooth12 = c[0][0], &smooth24 = c[1][0], &flat12 = c[0][1], &flat24 = c[1][1];
    // Orders of convergence.
    EXPECT_GT(smooth12.meanNormalDegrees / smooth24.meanNormalDegrees, 3.0);
    EXPECT_GT(flat12.meanNormalDegrees / flat24.meanNormalDegrees, 1.6);
    EXPECT_LT(flat12.meanNormalDegrees / flat24.meanNormalDegrees, 2.5);
    // Close to the sphere smooth, not flat.
    EXPECT_LT(smooth24.meanNormalDegrees, 0.5);
    EXPECT_GT(flat24.meanNormalDegrees, 2.0);
    EXPECT_LT(smooth24.meanColourError, 0.005);
    EXPECT_GT(flat24.meanColourError, 4 * smooth24.meanColourError);
    EXPECT_GT(flat12.meanColourError, 2 * smooth12.meanColourError);
}

// ---- Errors: SCENE:LINE at the <file> element, word for word ----------------------

std::string errorOf(const std::string& body) {
    try {
        loadWith(meshObject(body));
    } catch (const SceneError& e) {
        return e.what();
    }
    return "(loaded)";
}

std::string at7(const std::string& message) {
    return (meshDir() / "t.xml").string() + ":7: " + message;
}

TEST(MeshFileError, MissingFile) {
    EXPECT_EQ(errorOf("<file>no_such_model.obj</file>"), at7("mesh file \"no_such_model.obj\" does not exist"));
}

TEST(MeshFileError, Directory) {
    EXPECT_EQ(errorOf("<file>.</file>"), at7("mesh file \".\" is a directory, expected a model file"));
}

TEST(MeshFileError, UnknownExtension) {
    EXPECT_EQ(errorOf("<file>unknown.xyz</file>"),
              at7("mesh file \"unknown.xyz\" has unknown extension \".xyz\"; expected a model format Assimp reads, "
                  "such as .obj, .ply, .stl, .off, .gltf or .glb"));
}

TEST(MeshFileError, GarbageFileGivesAssimpsMessage) {
    EXPECT_EQ(errorOf("<file>garbage.ply</file>"), at7("mesh file \"garbage.ply\" could not be read: Invalid .ply "
                                                       "file: Incorrect magic number (expected 'ply' or 'PLY')."));
}

TEST(MeshFileError, TruncatedFileGivesAssimpsMessage) {
    EXPECT_EQ(errorOf("<file>truncated.ply</file>"),
              at7("mesh file \"truncated.ply\" could not be read: Validation failed: Mesh  contains no faces"));
}

TEST(MeshFileError, NoTriangles) {
    EXPECT_EQ(errorOf("<file>lines_only.obj</file>"), at7("mesh file \"lines_only.obj\" has no triangles"));
}

TEST(MeshFileError, EveryTriangleDegenerate) {
    EXPECT_EQ(errorOf("<file>all_degenerate.obj</file>"),
              at7("every triangle in mesh file \"all_degenerate.obj\" is degenerate"));
}

TEST(MeshFileError, VertexOutOfRange) {
    EXPECT_EQ(errorOf("<file>huge_vertex.obj</file>"),
              at7("mesh file \"huge_vertex.obj\" has a vertex beyond ±1e6 or not finite: (0, 2e+07, 0)"));
}

TEST(MeshFileError, ScaledBeyondRange) {
    // (0, 1, 1) turned 45 degrees about x is (0, 0, 1.41) before the scale of 1e6.
    EXPECT_EQ(errorOf(R"(<file>tilted_normals.obj</file><scale>1e6</scale><rotation x="45" y="0" z="0"/>)"),
              at7("mesh file \"tilted_normals.obj\": <scale> and <rotation> take vertex (0, 1, 1) beyond ±1e6 of the "
                  "object's <position>"));
}

TEST(MeshFileError, DegenerateTrianglesLoadWithOneWarning) {
    Scene scene = loadWith(meshObject("<file>one_degenerate.obj</file>"));
    EXPECT_EQ(onlyMesh(scene).triangles.size(), 1u);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_EQ(scene.warnings[0], at7("mesh file \"one_degenerate.obj\": 2 degenerate triangles skipped"));
}

// Each triangle of a mesh counts as one primitive against the device's limit
// on one scene array (maxMemoryAllocationSize, maxBufferSize), which is
// checked on these counts before anything is packed or uploaded. The limit
// is made up here: a mesh over lavapipe's 2 GiB would take gigabytes to build
// (RenderLimits.* in render_test.cpp renders 2^21 + 1 spheres, past the old
// storage-buffer range).
TEST(MeshRender, TrianglesCountAgainstTheBufferLimit) {
    Scene scene = loadWith(meshObject("<file>pyramid.obj</file>"));
    uint64_t triangles = std::get<Mesh>(scene.objects[0].shape).triangles.size();
    SceneArrayCounts counts = countSceneArrays(scene);
    EXPECT_EQ(counts.primitives, triangles);
    uint64_t bytes = triangles * sizeof(gpu::Primitive);
    // The BVH's nodes (80 bytes, at most one fewer than the triangles) must fit too.
    uint64_t fits = std::max<uint64_t>(bytes, counts.bvhNodes * sizeof(gpu::BvhNode));
    EXPECT_EQ(sceneArraysTooLarge(counts, {.maxBufferSize = UINT64_MAX, .maxAllocationSize = fits}), std::nullopt);
    EXPECT_EQ(sceneArraysTooLarge(counts, {.maxBufferSize = UINT64_MAX, .maxAllocationSize = bytes - 1}),
              "the scene's " + std::to_string(triangles) + " primitives (triangles count one each) need " +
                  std::to_string(bytes) + " bytes (0 MiB) in one buffer, more than this device's "
                  "maxMemoryAllocationSize of " + std::to_string(bytes - 1) + " bytes (0 MiB, " +
                  std::to_string(triangles - 1) + " of them)");
}

}  // namespace
}  // namespace whitted::test

// Tracing through the device's acceleration structures (VK_KHR_ray_query,
// shaders/ray_query.glsl) against our BVH: the same images, the same shadows
// through glass. Skipped, saying why, on a device without ray queries
// (lavapipe before Mesa 24.1); CI's Mesa 25 lavapipe runs them.
#include "output/aov_output.h"
#include "io/image_io.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

#define SKIP_WITHOUT_RAY_QUERY()                                                                          \
    if (!testContext().deviceInfo().rayQuery)                                                             \
    GTEST_SKIP() << "device '" << testContext().deviceInfo().name << "' (" << testContext().deviceInfo().driver \
                 << ") lacks VK_KHR_ray_query / VK_KHR_acceleration_structure"

std::vector<std::string> sceneNames() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(sourceDir() / "scenes"))
        if (entry.path().extension() == ".xml") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Every shipped scene at the golden tests' size and sampling, compared with
// their metric (tests/golden_test.cpp): mean absolute difference of the
// 8-bit sRGB values <= 0.5 levels, at most 0.2% of pixels off by > 16 levels
// (the driver's triangle test and ours may round an edge differently).
class RayQueryMatchesBvh : public ::testing::TestWithParam<std::string> {};

TEST_P(RayQueryMatchesBvh, SameImage) {
    SKIP_WITHOUT_RAY_QUERY();
    const std::string name = GetParam();
    Scene scene = loadScene(sourceDir() / "scenes" / (name + ".xml"));
    RenderSettings s{.width = 160, .height = 120, .samplesPerPixel = 4, .maxDepth = 6, .auxiliary = false,
                     .trace = TracePath::Bvh, .antiAliasing = AntiAliasing::Uniform};
    RenderResult bvh = renderScene(scene, s);
    s.trace = TracePath::RayQuery;
    RenderResult rq = renderScene(scene, s);
    EXPECT_EQ(bvh.trace, TracePath::Bvh);
    EXPECT_EQ(rq.trace, TracePath::RayQuery);
    EXPECT_EQ(bvh.rays.primary, rq.rays.primary);

    // Quantised exactly as PNG files are.
    fs::path bvhPath = outputDir() / (name + ".bvh.png"), rqPath = outputDir() / (name + ".rayquery.png");
    writeRenderImages(bvh, bvhPath, {}, Tonemap::Clamp);
    writeRenderImages(rq, rqPath, {}, Tonemap::Clamp);
    expectGoldenMatch(rqPath, bvhPath, outputDir() / (name + ".rayquery.diff.png"), name + " (ray query against BVH)");
}

INSTANTIATE_TEST_SUITE_P(Scenes, RayQueryMatchesBvh, ::testing::ValuesIn(sceneNames()),
                         [](const auto& info) { return info.param; });

// A floor lit from above through two glass spheres, one over the other, of
// different colours (kt 0.8, kd 0.5): where a shadow ray crosses both, the
// light is filtered four times, kt * mix(white, Cd, kd) per crossing. Both
// paths must give every floor pixel the diffuse term predicted in double
// precision (as RenderAnalytic.ShadowThroughGlassTakesItsColour does for one
// sphere), so the ray-query candidates count each crossing once.
TEST(RayQuery, ShadowThroughTwoGlassSpheresFiltersAsTheBvh) {
    SKIP_WITHOUT_RAY_QUERY();
    const int w = 64, h = 48;
    const glm::dvec3 light(0, 4, -4);
    struct Ball {
        glm::dvec3 center, cd;
    };
    const Ball balls[] = {{{0, 0.2, -4}, {1.0, 0.2, 0.4}}, {{0, 1.6, -4}, {0.3, 1.0, 0.5}}};
    const double radius = 0.5;
    std::string objects = R"(<object><position x="0" y="-1" z="0"/><properties><type>plane</type>)"
                          R"(<normal x="0" y="1" z="0"/></properties></object>)";
    for (const Ball& b : balls) {
        std::ostringstream o;
        o << "<object><position x=\"" << b.center.x << "\" y=\"" << b.center.y << "\" z=\"" << b.center.z
          << "\"/><diffuse_color r=\"" << b.cd.r << "\" g=\"" << b.cd.g << "\" b=\"" << b.cd.b
          << "\"/><properties><type>sphere</type><radius>" << radius
          << "</radius><diffuse_coef>0.5</diffuse_coef><transmission_coef>0.8</transmission_coef>"
             "<refraction_coef>1.5</refraction_coef></properties></object>";
        objects += o.str();
    }
    std::string xml = R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
                      R"(<width>32</width><height>24</height></camera><lights>)"
                      R"(<light><position x="0" y="4" z="-4"/><color r="1" g="1" b="1"/></light></lights><objects>)" +
                      objects + "</objects></scene>";
    RenderSettings s{.width = w, .height = h, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true,
                     .trace = TracePath::Bvh};
    RenderResult bvh = renderXml(xml, s);
    s.trace = TracePath::RayQuery;
    RenderResult rq = renderXml(xml, s);
    ASSERT_EQ(rq.trace, TracePath::RayQuery);

    const double tanHalf = std::tan(glm::radians(60.0) / 2.0), aspect = double(w) / h;
    int fourCrossings = 0, checked = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / w - 1.0) * tanHalf * aspect,
                                                     (1.0 - 2.0 * (y + 0.5) / h) * tanHalf, -1.0));
            if (d.y >= -1e-3) continue;  // above the horizon
            glm::dvec3 p = d * (-1.0 / d.y);
            glm::dvec3 l = glm::normalize(light - p);
            glm::dvec3 expected(glm::dot(l, glm::dvec3(0, 1, 0)));
            bool unclear = false;
            int crossings = 0;
            for (const Ball& b : balls) {
                // The camera ray must miss the ball; the shadow ray crosses it twice or not at all.
                double bs = glm::dot(-b.center, d), cs = glm::dot(b.center, b.center) - radius * radius;
                if (bs * bs - cs > -1e-3) unclear = true;
                double bl = glm::dot(p - b.center, l), cl = glm::dot(p - b.center, p - b.center) - radius * radius;
                double disc = bl * bl - cl;
                if (std::abs(disc) < 1e-3) unclear = true;
                if (disc > 0 && -bl - std::sqrt(disc) > 0) {
                    glm::dvec3 filter = 0.8 * glm::mix(glm::dvec3(1.0), b.cd, 0.5);
                    expected *= filter * filter;
                    crossings += 2;
                }
            }
            if (unclear) continue;
            ++checked;
            if (crossings == 4) ++fourCrossings;
            glm::vec4 fromBvh = pixel(bvh, gpu::kAovDiffuse, x, y), fromRq = pixel(rq, gpu::kAovDiffuse, x, y);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(fromBvh[c], expected[c], 1e-4) << "BVH, pixel " << x << "," << y << " channel " << c;
                EXPECT_NEAR(fromRq[c], expected[c], 1e-4) << "ray query, pixel " << x << "," << y << " channel " << c;
            }
        }
    EXPECT_GT(fourCrossings, 10) << "the shadow of both spheres must cover floor pixels, or this test proves nothing";
    EXPECT_GT(checked, 500);
}

// The record names the path taken; ray queries and --no-bvh exclude each other.
TEST(RayQuery, RecordNamesThePathTaken) {
    fs::path dir = outputDir() / "cli" / "trace";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string scene = (sourceDir() / "scenes" / "room.xml").string();
    auto run = [&](const std::string& args) {
        return runCommand("'" WHITTED_EXECUTABLE "' render '" + scene + "' --width 32 --height 24 --spp 1 -q " + args,
                          dir);
    };
    auto record = [&](const std::string& name) {
        std::ifstream in(dir / name);
        std::stringstream text;
        text << in.rdbuf();
        return text.str();
    };
    CommandRun bvh = run("--trace bvh -o bvh.png");
    ASSERT_EQ(bvh.status, 0) << bvh.output;
    EXPECT_NE(record("bvh.json").find("\"trace\": \"bvh\""), std::string::npos);
    CommandRun both = run("--trace rayquery --no-bvh -o both.png");
    EXPECT_EQ(both.status, 2);
    EXPECT_NE(both.output.find("whitted: --no-bvh and --trace rayquery exclude each other"), std::string::npos)
        << both.output;
    CommandRun rq = run("--trace rayquery -o rq.png");
    if (!testContext().deviceInfo().rayQuery) {
        EXPECT_EQ(rq.status, 1);
        EXPECT_NE(rq.output.find("--trace rayquery: device '"), std::string::npos) << rq.output;
        EXPECT_FALSE(fs::exists(dir / "rq.png"));
        return;
    }
    ASSERT_EQ(rq.status, 0) << rq.output;
    EXPECT_NE(record("rq.json").find("\"trace\": \"rayquery\""), std::string::npos);
}

}  // namespace
}  // namespace whitted::test

namespace whitted::test {
namespace {

// CSG objects (shaders/shapes/csg.glsl) in the AABB structure: the nested
// opaque CSG of the POV-Ray cross-check, and a glass csg object (a sphere
// with a box cut out of it, a glass cylinder inside the cut) whose shadow
// rays cross it up to four times over a checker floor, compared with the
// BVH path by the golden metric as above.
TEST(RayQuery, CsgScenesMatchTheBvh) {
    SKIP_WITHOUT_RAY_QUERY();
    const std::string glass = R"(<scene><camera><position x="0" y="2" z="4"/><window_position x="0" y="1.6" z="3.1"/>
      </camera><lights><light><position x="-2" y="5" z="2"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="0" y="0" z="0"/><diffuse_color r="0.9" g="0.9" b="0.9"/><properties><type>plane</type>
        <normal x="0" y="1" z="0"/><checker_color r="0.2" g="0.3" b="0.6"/><checker_size>0.5</checker_size></properties></object>
      <object><position x="0" y="0.9" z="0"/><diffuse_color r="0.9" g="0.5" b="0.3"/>
        <properties><type>csg</type><operation>union</operation><transmission_coef>0.8</transmission_coef>
          <refraction_coef>1.4</refraction_coef><diffuse_coef>0.3</diffuse_coef><specular_coef>0.5</specular_coef>
          <absorption r="0.3" g="0.1" b="0.05"/></properties>
        <objects>
          <object><properties><type>csg</type><operation>difference</operation></properties><objects>
            <object><position x="0" y="0" z="0"/><properties><type>sphere</type><radius>0.8</radius></properties></object>
            <object><position x="-1" y="0.1" z="-0.3"/><properties><type>box</type><size x="2" y="1" z="0.6"/></properties></object>
          </objects></object>
          <object><position x="-0.6" y="0.3" z="0"/><diffuse_color r="0.3" g="0.8" b="0.4"/>
            <properties><type>cylinder</type><radius>0.15</radius><height>1.2</height><axis x="1" y="0" z="0"/>
              <transmission_coef>0.7</transmission_coef><refraction_coef>1.2</refraction_coef><diffuse_coef>0.5</diffuse_coef></properties></object>
        </objects></object>
      </objects></scene>)";
    const std::pair<std::string, Scene> scenes[] = {
        {"csg", loadScene(sourceDir() / "tests" / "povray_scenes" / "csg.xml")},
        {"csg_glass", loadSceneFromString(glass, "csg_glass.xml")}};
    for (const auto& [name, scene] : scenes) {
        RenderSettings s{.width = 160,
                         .height = 120,
                         .samplesPerPixel = 4,
                         .maxDepth = 6,
                         .auxiliary = false,
                         .trace = TracePath::Bvh,
                         .antiAliasing = AntiAliasing::Uniform};
        RenderResult bvh = renderScene(scene, s);
        s.trace = TracePath::RayQuery;
        RenderResult rq = renderScene(scene, s);
        ASSERT_EQ(rq.trace, TracePath::RayQuery);
        fs::path bvhPath = outputDir() / (name + ".bvh.png"), rqPath = outputDir() / (name + ".rayquery.png");
        writeRenderImages(bvh, bvhPath, {}, Tonemap::Clamp);
        writeRenderImages(rq, rqPath, {}, Tonemap::Clamp);
        expectGoldenMatch(rqPath, bvhPath, outputDir() / (name + ".rayquery.diff.png"),
                          name + " (ray query against BVH)");
    }
}

}  // namespace
}  // namespace whitted::test

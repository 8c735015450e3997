// The environment (scenes/README.md "Environment"): the mapping's convention, the writer's round trip, the
// importance-sampling distribution, and the environment light's normalisation against a directional light.
#include "io/image_io.h"
#include "render/gpu_environment.h"
#include "scene/environment.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numeric>

namespace whitted::test {
namespace {

void expectNear(const glm::dvec3& got, const glm::dvec3& want) {
    EXPECT_NEAR(got.x, want.x, 1e-12);
    EXPECT_NEAR(got.y, want.y, 1e-12);
    EXPECT_NEAR(got.z, want.z, 1e-12);
}

// The README's words, one by one: the image's centre looks along -z, u = 3/4 along +x, the top row along
// +y, the bottom one along -y; a rotation of 90 degrees turns the centre to -x.
TEST(Environment, MappingConvention) {
    expectNear(environmentDirection(0.5, 0.5, 0), {0, 0, -1});
    expectNear(environmentDirection(0.75, 0.5, 0), {1, 0, 0});
    expectNear(environmentDirection(0.25, 0.5, 0), {-1, 0, 0});
    expectNear(environmentDirection(0.3, 0.0, 0), {0, 1, 0});
    expectNear(environmentDirection(0.3, 1.0, 0), {0, -1, 0});
    expectNear(environmentDirection(0.5, 0.5, 90), {-1, 0, 0});
    // environmentUv inverts it, rotation included.
    for (double rotation : {0.0, 30.0, -135.0})
        for (double u : {0.1, 0.5, 0.9})
            for (double t : {0.2, 0.5, 0.7}) {
                glm::dvec2 uv = environmentUv(environmentDirection(u, t, rotation), rotation);
                EXPECT_NEAR(uv.x, u, 1e-12);
                EXPECT_NEAR(uv.y, t, 1e-12);
            }
}

constexpr const char* kGradientScene = R"(<scene>
  <camera><position x="0" y="1" z="5"/><window_position x="0" y="1" z="4"/></camera>
  <environment>
    <gradient><zenith r="0.1" g="0.2" b="3"/><horizon r="1" g="1" b="1"/><ground r="0.3" g="0.25" b="0.2"/></gradient>
    <rotation>12.5</rotation><intensity>0.75</intensity><visible>false</visible><shadow_samples>7</shadow_samples>
  </environment>
  <lights></lights>
  <objects>
    <object><position x="0" y="1" z="0"/><properties><type>sphere</type><radius>1</radius></properties></object>
  </objects>
</scene>)";

TEST(Environment, WriterRoundTrip) {
    Scene scene = loadSceneFromString(kGradientScene, "gradient.xml");
    ASSERT_TRUE(scene.environment);
    const Environment& e = *scene.environment;
    EXPECT_EQ(e.kind, Environment::Kind::Gradient);
    EXPECT_EQ(e.zenith, glm::dvec3(0.1, 0.2, 3));
    EXPECT_EQ(e.rotationDegrees, 12.5);
    EXPECT_EQ(e.intensity, 0.75);
    EXPECT_FALSE(e.visible);
    EXPECT_EQ(e.shadowSamples, 7);
    Scene again = loadSceneFromString(sceneXml(scene), "again.xml");
    ASSERT_TRUE(again.environment);
    const Environment& a = *again.environment;
    EXPECT_EQ(a.kind, e.kind);
    EXPECT_EQ(a.zenith, e.zenith);
    EXPECT_EQ(a.horizon, e.horizon);
    EXPECT_EQ(a.ground, e.ground);
    EXPECT_EQ(a.rotationDegrees, e.rotationDegrees);
    EXPECT_EQ(a.intensity, e.intensity);
    EXPECT_EQ(a.visible, e.visible);
    EXPECT_EQ(a.shadowSamples, e.shadowSamples);
    // Written for a file elsewhere (the paths of images made relative to it), the same.
    Scene elsewhere = loadSceneFromString(sceneXml(scene, outputDir() / "elsewhere.xml"), "elsewhere.xml");
    ASSERT_TRUE(elsewhere.environment);
    EXPECT_EQ(elsewhere.environment->ground, e.ground);
    // Without one, nothing is written.
    Scene none = loadSceneFromString(sceneXml(loadScene(sourceDir() / "scenes" / "room.xml")), "room.xml");
    EXPECT_FALSE(none.environment);
}

// pbrt-v4's piecewise-constant 2D distribution over luminance x sin theta, each texel's weight the largest
// of its 3x3 neighbourhood: the CDFs run from 0 to 1, a lone bright texel and its neighbours take nearly all
// the probability, and a black image gives the uniform distribution.
TEST(Environment, DistributionFollowsLuminanceTimesSinTheta) {
    const int w = 16, h = 8;
    std::vector<float> lum(w * h, 0.0f);
    lum[3 * w + 5] = 1000.0f;  // row 3, column 5
    std::vector<float> d = environmentDistribution(w, h, lum);
    ASSERT_EQ(d.size(), size_t((h + 1) + h * (w + 1)));
    EXPECT_EQ(d[0], 0.0f);
    EXPECT_EQ(d[h], 1.0f);
    // Rows 2..4 hold all of it; row 3's columns 4..6 all of that row's.
    EXPECT_FLOAT_EQ(d[2], 0.0f);
    EXPECT_FLOAT_EQ(d[5], 1.0f);
    const float* row3 = &d[(h + 1) + 3 * (w + 1)];
    EXPECT_FLOAT_EQ(row3[4], 0.0f);
    EXPECT_FLOAT_EQ(row3[7], 1.0f);
    EXPECT_NEAR(row3[5] - row3[4], 1.0f / 3.0f, 1e-6);
    // Each row weighs the sine of its centre's polar angle: row k of 8 is at theta = (k + 1/2) pi / 8.
    double s2 = std::sin(M_PI * 2.5 / 8), s3 = std::sin(M_PI * 3.5 / 8), s4 = std::sin(M_PI * 4.5 / 8);
    EXPECT_NEAR(d[3] - d[2], s2 / (s2 + s3 + s4), 1e-6);
    std::vector<float> black = environmentDistribution(w, h, std::vector<float>(w * h, 0.0f));
    for (int y = 0; y <= h; ++y) EXPECT_NEAR(black[y], float(y) / h, 1e-6);
}

// The command line: --background transparent writes the coverage as the EXR's fourth channel (1 on the
// sphere, 0 around it, fractional at its edge; the background's colour black, premultiplied) and the depth of
// the background as infinity; --environment FILE replaces the scene's environment, and a file that does not
// exist exits 2 naming it, writing nothing.
TEST(Environment, CommandLineTransparentBackgroundAndEnvironmentFile) {
    std::filesystem::path dir = freshOutputDir("environment", "cli");
    std::string scene = std::string(kGradientScene);
    std::ofstream(dir / "gradient.xml") << scene;
    CommandRun run = runCommand("'" WHITTED_EXECUTABLE "' render gradient.xml --width 40 --height 30 --spp 16 "
                                "--aa uniform --aov depth --background transparent -q -o out.exr", dir);
    ASSERT_EQ(run.status, 0) << run.output;
    int w = 0, h = 0, channels = 0;
    std::vector<float> storage, depthStorage;
    std::span<const float> image = readImageInto(dir / "out.exr", w, h, channels, storage);
    ASSERT_EQ(channels, 4);
    auto alpha = [&](int x, int y) { return image[(size_t(y) * w + x) * 4 + 3]; };
    EXPECT_EQ(alpha(20, 15), 1.0f);  // the sphere fills the centre
    EXPECT_EQ(alpha(0, 0), 0.0f);
    EXPECT_EQ(image[0], 0.0f);  // the background not seen: black, the colour premultiplied
    int fractional = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) fractional += alpha(x, y) > 0.0f && alpha(x, y) < 1.0f ? 1 : 0;
    EXPECT_GT(fractional, 8);
    std::span<const float> depth = readImageInto(dir / "out.depth.exr", w, h, channels, depthStorage);
    EXPECT_TRUE(std::isinf(depth[0]));
    EXPECT_NEAR(depth[(size_t(15) * w + 20) * channels], 4.0f, 0.05f);

    CommandRun missing = runCommand("'" WHITTED_EXECUTABLE "' render gradient.xml --environment no_such.exr -q "
                                    "-o missing.png", dir);
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.output.find("no_such.exr: environment image does not exist"), std::string::npos)
        << missing.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "missing.png"));
}

}  // namespace
}  // namespace whitted::test

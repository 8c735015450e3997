// Reflection and transmission split by ray-tree depth (--aov-bounces): what
// each split image holds, that they add up to the totals per pixel whatever
// the sampling, banding or region, and that the layers exist only when asked.
#include "test_support.h"

#include "output/aov_output.h"
#include "io/image_io.h"
#include "scene/scene_loader.h"

#include <fstream>
#include <sstream>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

uint32_t reflectionLayer(int /*bounces*/, int k) { return gpu::kAovCount + uint32_t(k) - 1; }
uint32_t transmissionLayer(int bounces, int k) { return gpu::kAovCount + uint32_t(bounces + k) - 1; }

// Camera at the origin looking down -z, 32x24, no lights (ambient light 1).
std::string sceneXml(const std::string& objects) {
    return R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
           R"(<width>32</width><height>24</height></camera><lights/><objects>)" +
           objects + "</objects></scene>";
}

// Two mirrors facing each other across the eye (z = -3 and z = +3), each
// ka = 0.2 and kr = 1 with specular colour 0.5: the ray through the image
// centre sees 0.2 at the first hit and 0.2 * 0.5^d at ray depth d.
std::string facingMirrors() {
    auto mirror = [](const char* z, const char* nz) {
        return std::string(R"(<object><position x="0" y="0" z=")") + z +
               R"("/><specular_color r="0.5" g="0.5" b="0.5"/><properties><type>plane</type><normal x="0" y="0" z=")" +
               nz + R"("/><ambiente_coef>0.2</ambiente_coef><diffuse_coef>0</diffuse_coef>)"
                    R"(<reflection_coef>1</reflection_coef></properties></object>)";
    };
    return sceneXml(mirror("-3", "1") + mirror("3", "-1"));
}

RenderSettings small(int bounces, int maxDepth = 6) {
    return {.width = 32, .height = 24, .samplesPerPixel = 1, .maxDepth = maxDepth, .auxiliary = true,
            .aovBounces = bounces};
}

// reflection.k = light of the rays at depth k of the reflected subtree; the
// last split image holds depth B and everything deeper.
TEST(AovSplit, FacingMirrorsSplitByDepth) {
    const float kTol = 1e-6f;
    RenderResult r = renderXml(facingMirrors(), small(3));
    ASSERT_EQ(r.layers.size(), gpu::kAovCount + 6);
    EXPECT_NEAR(pixel(r, gpu::kAovAmbient, 16, 12).r, 0.2f, kTol);
    EXPECT_NEAR(pixel(r, reflectionLayer(3, 1), 16, 12).r, 0.1f, kTol);
    EXPECT_NEAR(pixel(r, reflectionLayer(3, 2), 16, 12).r, 0.05f, kTol);
    // Depths 3..6 (--max-depth 6): 0.2 * (1/8 + 1/16 + 1/32 + 1/64).
    EXPECT_NEAR(pixel(r, reflectionLayer(3, 3), 16, 12).r, 0.046875f, kTol);
    EXPECT_NEAR(pixel(r, gpu::kAovReflection, 16, 12).r, 0.196875f, kTol);
    for (int k = 1; k <= 3; ++k) EXPECT_EQ(pixel(r, transmissionLayer(3, k), 16, 12), glm::vec4(0, 0, 0, 1));

    // More split images than bounces traced: the ones past --max-depth are black.
    RenderResult deep = renderXml(facingMirrors(), small(8));
    for (int k = 1; k <= 6; ++k)
        EXPECT_NEAR(pixel(deep, reflectionLayer(8, k), 16, 12).r, 0.2f * std::pow(0.5f, float(k)), kTol) << k;
    for (int k = 7; k <= 8; ++k) EXPECT_EQ(pixel(deep, reflectionLayer(8, k), 16, 12).r, 0.0f) << k;
}

// A clear pane (a box, IOR 1, kt 0.5, no other term) in front of an
// ambient-lit wall: the ray enters (depth 0), crosses the back face (depth
// 1, which adds nothing) and reaches the wall at depth 2 with weight kt^2.
TEST(AovSplit, LightThroughAPaneArrivesAtDepthTwo) {
    std::string pane = R"(<object><position x="-50" y="-50" z="-3"/><properties><type>box</type>)"
                       R"(<size x="100" y="100" z="1"/><transmission_coef>0.5</transmission_coef>)"
                       R"(<diffuse_coef>0</diffuse_coef></properties></object>)";
    std::string wall = R"(<object><position x="0" y="0" z="-6"/><properties><type>plane</type>)"
                       R"(<normal x="0" y="0" z="1"/><ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef>)"
                       R"(</properties></object>)";
    RenderResult r = renderXml(sceneXml(pane + wall), small(2));
    EXPECT_EQ(pixel(r, transmissionLayer(2, 1), 16, 12).g, 0.0f);
    EXPECT_NEAR(pixel(r, transmissionLayer(2, 2), 16, 12).g, 0.25f, 1e-6f);
    EXPECT_NEAR(pixel(r, gpu::kAovTransmission, 16, 12).g, 0.25f, 1e-6f);
    RenderResult one = renderXml(sceneXml(pane + wall), small(1));
    EXPECT_NEAR(pixel(one, transmissionLayer(1, 1), 16, 12).g, 0.25f, 1e-6f) << "one split image holds every depth";
}

void expectSplitsAddUp(const RenderResult& r, int bounces) {
    ASSERT_EQ(r.layers.size(), gpu::kAovCount + 2 * size_t(bounces));
    size_t pixels = r.sampleCounts.size();
    for (int part = 0; part < 2; ++part) {
        uint32_t total = part == 0 ? gpu::kAovReflection : gpu::kAovTransmission;
        std::vector<bool> lit(size_t(bounces), false);
        for (size_t i = 0; i < pixels; ++i)
            for (int c = 0; c < 3; ++c) {
                float sum = 0;
                for (int k = 1; k <= bounces; ++k) {
                    uint32_t l = part == 0 ? reflectionLayer(bounces, k) : transmissionLayer(bounces, k);
                    float v = r.layers[l][i * 4 + c];
                    sum += v;
                    lit[size_t(k) - 1] = lit[size_t(k) - 1] || v > 1e-3f;
                }
                float want = r.layers[total][i * 4 + c];
                ASSERT_NEAR(sum, want, 1e-5f * (1 + std::abs(want))) << "part " << part << " pixel " << i;
            }
        for (int k = 1; k <= bounces; ++k) EXPECT_TRUE(lit[size_t(k) - 1]) << "part " << part << " bounce " << k;
    }
}

// several_mirrors has mirrors seen in mirrors and a glass sphere: every
// split image has light in it. Default adaptive anti-aliasing, and bands of
// a few rows (bandBytes counts the split layers too); the other layers are
// those of a render without the split, bit for bit.
TEST(AovSplit, SplitImagesAddUpWithAdaptiveSamplingAndBands) {
    Scene scene = loadScene(sourceDir() / "scenes" / "several_mirrors.xml");
    RenderSettings s{.width = 96, .height = 72, .samplesPerPixel = 16, .maxDepth = 6, .auxiliary = true,
                     .aovBounces = 3, .antiAliasing = AntiAliasing::Adaptive};
    s.bandBytes = 96 * 16 * (gpu::kAovCount + 6) * 16;  // about 16 rows of layers (less: the adaptive buffers)
    RenderResult r = renderScene(scene, s);
    EXPECT_GT(r.bands, 4);
    bool varied = false;
    for (float n : r.sampleCounts) varied = varied || n != r.sampleCounts[0];
    EXPECT_TRUE(varied) << "adaptive sampling took different counts";
    expectSplitsAddUp(r, 3);

    RenderSettings plain = s;
    plain.aovBounces = 0;
    plain.bandBytes = RenderSettings{}.bandBytes;
    RenderResult p = renderScene(scene, plain);
    ASSERT_EQ(p.layers.size(), gpu::kAovCount);
    for (uint32_t l = 0; l < gpu::kAovCount; ++l) EXPECT_TRUE(p.layers[l] == r.layers[l]) << "layer " << l;
    EXPECT_EQ(p.sampleCounts, r.sampleCounts);
}

TEST(AovSplit, UniformSamplingAddsUpToo) {
    Scene scene = loadScene(sourceDir() / "scenes" / "several_mirrors.xml");
    RenderResult r = renderScene(scene, {.width = 64, .height = 48, .samplesPerPixel = 4, .maxDepth = 6,
                                         .auxiliary = true, .aovBounces = 2});
    expectSplitsAddUp(r, 2);
}

// A region gets exactly the full render's split values (adaptive decisions
// included), as every other layer does.
TEST(AovSplit, RegionIsTheCropOfTheFullRender) {
    Scene scene = loadScene(sourceDir() / "scenes" / "several_mirrors.xml");
    RenderSettings s{.width = 80, .height = 60, .samplesPerPixel = 16, .maxDepth = 6, .auxiliary = true,
                     .aovBounces = 2, .antiAliasing = AntiAliasing::Adaptive};
    RenderResult full = renderScene(scene, s);
    s.region = PixelRegion{17, 9, 60, 41};
    RenderResult part = renderScene(scene, s);
    ASSERT_EQ(part.width, 43);
    ASSERT_EQ(part.layers.size(), full.layers.size());
    for (uint32_t l = gpu::kAovCount; l < full.layers.size(); ++l)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 43; ++x)
                ASSERT_EQ(pixel(part, l, x, y), pixel(full, l, x + 17, y + 9))
                    << "layer " << l << " at " << x << "," << y;
}

// The split layers cost device memory only when asked for.
TEST(AovSplit, LayersExistOnlyWhenAskedFor) {
    Scene scene = loadSceneFromString(facingMirrors(), "inline.xml");
    EXPECT_EQ(Renderer(testContext(), scene, small(0)).layerCount(), gpu::kAovCount);
    EXPECT_EQ(Renderer(testContext(), scene, small(4)).layerCount(), gpu::kAovCount + 8);
    RenderSettings none = small(4);
    none.auxiliary = false;
    EXPECT_EQ(Renderer(testContext(), scene, none).layerCount(), 1u);
}

TEST(AovSplit, NamesFollowTheBounceCount) {
    std::vector<std::string> all = parseAovList("all", 2);
    EXPECT_EQ(all.size(), allAovs().size() + 4);
    auto at = std::find(all.begin(), all.end(), "transmission");
    ASSERT_NE(at, all.end());
    EXPECT_EQ(std::vector<std::string>(at + 1, at + 5),
              (std::vector<std::string>{"reflection.1", "reflection.2", "transmission.1", "transmission.2"}));
    EXPECT_EQ(parseAovList("all"), parseAovList("all", 0));
    EXPECT_EQ(parseAovList("transmission.2,depth", 2), (std::vector<std::string>{"transmission.2", "depth"}));
    EXPECT_TRUE(hasSplitAov(parseAovList("reflection.1", 1)));
    EXPECT_FALSE(hasSplitAov(parseAovList("all", 0)));
    try {
        parseAovList("reflection.3", 2);
        ADD_FAILURE() << "reflection.3 with 2 bounces was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "auxiliary image 'reflection.3' needs --aov-bounces 3 or more (got 2)");
    }
    for (const char* bad : {"reflection.0", "reflection.", "reflection.x", "reflection.01", "diffuse.1"})
        EXPECT_THROW(parseAovList(bad, 4), std::invalid_argument) << bad;
}

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// The command line: split images beside the main image in PNG and EXR (the
// EXR ones add up to the totals), the record says how many, bad names and
// counts are refused with status 2 and nothing written.
TEST(AovSplit, CommandLineWritesSplitImages) {
    fs::path dir = outputDir() / "aov_split";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string whitted = "'" WHITTED_EXECUTABLE "' render " +
                          (sourceDir() / "scenes" / "several_mirrors.xml").string() +
                          " --width 64 --height 48 --validate";
    CommandRun r = runCommand(whitted + " -o out.exr --aov-bounces 2", dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(readText(dir / "out.json").find("\"aov_bounces\": 2"), std::string::npos);
    for (const char* total : {"reflection", "transmission"}) {
        int w = 0, h = 0, c = 0;
        std::vector<float> want, one, two;
        readImageInto(dir / (std::string("out.") + total + ".exr"), w, h, c, want);
        readImageInto(dir / (std::string("out.") + total + ".1.exr"), w, h, c, one);
        readImageInto(dir / (std::string("out.") + total + ".2.exr"), w, h, c, two);
        ASSERT_EQ(want.size(), size_t(64 * 48 * 3));
        ASSERT_EQ(one.size(), want.size());
        ASSERT_EQ(two.size(), want.size());
        for (size_t i = 0; i < want.size(); ++i)
            ASSERT_NEAR(one[i] + two[i], want[i], 1e-5f * (1 + want[i])) << total << " value " << i;
    }

    r = runCommand(whitted + " -o out.png --aov reflection.1,transmission.3 --aov-bounces 3", dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out.reflection.1.png"));
    EXPECT_TRUE(fs::exists(dir / "out.transmission.3.png"));
    EXPECT_FALSE(fs::exists(dir / "out.reflection.2.png"));

    // Without a split name the bounce count is dropped: no split layers.
    r = runCommand(whitted + " -o plain.png --aov diffuse --aov-bounces 3", dir);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(readText(dir / "plain.json").find("\"aov_bounces\": 0"), std::string::npos);

    r = runCommand(whitted + " -o bad.png --aov reflection.3 --aov-bounces 2", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("whitted: --aov: auxiliary image 'reflection.3' needs --aov-bounces 3 or more (got 2)"),
              std::string::npos) << r.output;
    r = runCommand(whitted + " -o bad.png --aov-bounces 17", dir);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("--aov-bounces"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

}  // namespace
}  // namespace whitted::test

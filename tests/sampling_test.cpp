// Adaptive anti-aliasing, bands and regions: the same pixels whatever the
// split, few samples where the image is flat, more at edges, and a default
// render close to a 64-sample uniform one.
#include "test_support.h"

#include "io/image_io.h"
#include "io/srgb.h"
#include "render/adaptive.h"
#include "scene/scene_loader.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

void expectSamePixels(const RenderResult& a, const RenderResult& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    for (uint32_t l = 0; l < gpu::kAovCount; ++l) {
        ASSERT_EQ(a.layers[l].size(), b.layers[l].size()) << "layer " << l;
        for (size_t i = 0; i < a.layers[l].size(); ++i)
            ASSERT_EQ(a.layers[l][i], b.layers[l][i]) << "layer " << l << " value " << i;
    }
    EXPECT_EQ(a.sampleCounts, b.sampleCounts);
}

RenderSettings adaptive(int w, int h, int maxSpp = 16) {
    return {.width = w, .height = h, .samplesPerPixel = maxSpp, .maxDepth = 6, .auxiliary = true,
            .antiAliasing = AntiAliasing::Adaptive};
}

Scene shipped(const std::string& name) { return loadScene(sourceDir() / "scenes" / name); }

TEST(Adaptive, RefinementLevelsGrowByFourUpToTheMaximum) {
    EXPECT_EQ(refinementLevels(1), std::vector<uint32_t>{});
    EXPECT_EQ(refinementLevels(4), std::vector<uint32_t>{4});
    EXPECT_EQ(refinementLevels(16), (std::vector<uint32_t>{4, 16}));
    EXPECT_EQ(refinementLevels(10), (std::vector<uint32_t>{4, 10}));
    EXPECT_EQ(refinementLevels(64), (std::vector<uint32_t>{4, 16, 64}));
}

TEST(Adaptive, IsDeterministic) {
    Scene scene = shipped("room.xml");
    RenderResult a = renderScene(scene, adaptive(96, 72));
    RenderResult b = renderScene(scene, adaptive(96, 72));
    expectSamePixels(a, b);
}

// A view filled by one evenly lit surface (ambient light only) varies
// nowhere: one sample per pixel. The edge of a sphere in front of it gets
// more, and only near the edge.
TEST(Adaptive, FlatImageTakesOneSampleEdgesTakeMore) {
    const std::string wall = R"(<object><position x="0" y="0" z="-5"/><diffuse_color r="0.5" g="0.6" b="0.7"/>
        <properties><type>plane</type><normal x="0" y="0" z="1"/><ambiente_coef>1</ambiente_coef>
        <diffuse_coef>0</diffuse_coef></properties></object>)";
    const std::string sphere = R"(<object><position x="0" y="0" z="-3"/><diffuse_color r="1" g="0.2" b="0.1"/>
        <properties><type>sphere</type><radius>0.5</radius><ambiente_coef>1</ambiente_coef>
        <diffuse_coef>0</diffuse_coef></properties></object>)";
    auto xml = [](const std::string& objects) {
        return "<scene><camera><position x=\"0\" y=\"0\" z=\"0\"/><window_position x=\"0\" y=\"0\" z=\"-1\"/></camera>"
               "<lights/><objects>" + objects + "</objects></scene>";
    };
    RenderResult flat = renderXml(xml(wall), adaptive(64, 48));
    for (float n : flat.sampleCounts) ASSERT_EQ(n, 1.0f);

    RenderResult edge = renderXml(xml(wall + sphere), adaptive(64, 48));
    int refined = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            float n = edge.sampleCounts[size_t(y) * 64 + x];
            // Pixel centre's distance from the sphere's outline, in pixels
            // (the sphere subtends atan(0.5/3) ~ 9.46 deg; fov 60 deg over 48 rows).
            double px = x + 0.5 - 32, py = y + 0.5 - 24;
            double pixelsPerTan = 24.0 / std::tan(M_PI / 6);
            double radius = pixelsPerTan * 0.5 / std::sqrt(3.0 * 3.0 - 0.25);
            double d = std::abs(std::hypot(px, py) - radius);
            if (d > 2.5) {
                EXPECT_EQ(n, 1.0f) << x << "," << y;
            }
            // A pixel beside the outline takes 4 samples that agree; one the
            // outline crosses goes on to the maximum.
            EXPECT_TRUE(n == 1 || n == 4 || n == 16) << n;
            refined += n == 16;
        }
    EXPECT_GT(refined, 30) << "the outline (circumference ~ 2 pi 7.3 pixels) is refined to the maximum";
}

// The component layers still add up to the image, whatever each pixel took.
TEST(Adaptive, ComponentsAddUpToTheImage) {
    RenderResult r = renderScene(shipped("nested_spheres.xml"), adaptive(80, 60));
    bool varied = false;
    for (size_t i = 0; i < r.sampleCounts.size(); ++i) {
        varied = varied || r.sampleCounts[i] != r.sampleCounts[0];
        for (int c = 0; c < 3; ++c) {
            float sum = 0;
            for (uint32_t l = gpu::kAovAmbient; l <= gpu::kAovTransmission; ++l) sum += r.layers[l][i * 4 + c];
            ASSERT_NEAR(sum, r.layers[gpu::kAovColor][i * 4 + c], 1e-5f) << "pixel " << i;
        }
    }
    EXPECT_TRUE(varied);
}

// PSNR of two colour layers after clamping and sRGB encoding, as PNGs hold them.
double psnr(const RenderResult& a, const RenderResult& b) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.layers[0].size(); ++i) {
        if (i % 4 == 3) continue;
        double d = linearToSrgb(a.layers[0][i]) - linearToSrgb(b.layers[0][i]);
        sum += d * d;
        ++n;
    }
    return sum == 0 ? INFINITY : 10 * std::log10(double(n) / sum);
}

// The default render (`whitted render SCENE`: adaptive, at most 16 samples,
// the scene's own size) of every shipped scene is within 50 dB of a uniform
// 64-sample render.
class DefaultRender : public ::testing::TestWithParam<std::string> {};

TEST_P(DefaultRender, IsCleanAgainstSixtyFourSamples) {
    Scene scene = shipped(GetParam());
    RenderSettings defaults = adaptive(0, 0);
    RenderResult r = renderScene(scene, defaults);
    RenderSettings reference = defaults;
    reference.antiAliasing = AntiAliasing::Uniform;
    reference.samplesPerPixel = 64;
    RenderResult ref = renderScene(scene, reference);
    double db = psnr(r, ref);
    double meanSpp = double(r.samplesTaken) / (double(r.width) * r.height);
    EXPECT_GE(db, 50.0) << "mean " << meanSpp << " spp";
    RecordProperty("psnr_db", std::to_string(db));
    std::printf("%s: %.1f dB at %.2f samples per pixel\n", GetParam().c_str(), db, meanSpp);
}

INSTANTIATE_TEST_SUITE_P(Scenes, DefaultRender,
                         ::testing::Values("room.xml", "n_objects.xml", "n_diffuse_objects.xml", "nested_spheres.xml",
                                           "one_mirror.xml", "several_mirrors.xml", "three_diffuse_spheres.xml",
                                           "showcase.xml"),
                         [](const auto& info) { return info.param.substr(0, info.param.size() - 4); });

// Rendered in bands of a few rows (each with its own adaptive first pass and
// border), the image is the one rendered whole, bit for bit.
TEST(Bands, SplitIntoBandsGivesTheSamePixels) {
    Scene scene = shipped("room.xml");
    for (AntiAliasing aa : {AntiAliasing::Uniform, AntiAliasing::Adaptive}) {
        RenderSettings whole = adaptive(80, 60, 4);
        whole.antiAliasing = aa;
        RenderSettings banded = whole;
        // 7 rows a band: the layers, and the adaptive passes' list,
        // statistics and guide over the band's one-pixel border (one level).
        banded.bandBytes = 7 * (80 * gpu::kAovCount * 16 + 82 * 52);
        RenderResult a = renderScene(scene, whole);
        RenderResult b = renderScene(scene, banded);
        EXPECT_EQ(a.bands, 1);
        EXPECT_GE(b.bands, 7);
        expectSamePixels(a, b);
    }
}

// A region is the crop of the full render, bit for bit.
TEST(Region, IsTheCropOfTheFullRender) {
    Scene scene = shipped("room.xml");
    RenderSettings full = adaptive(80, 60);
    RenderSettings part = full;
    part.region = PixelRegion{13, 7, 51, 40};
    RenderResult a = renderScene(scene, full);
    RenderResult b = renderScene(scene, part);
    ASSERT_EQ(b.width, 38);
    ASSERT_EQ(b.height, 33);
    for (int y = 0; y < 33; ++y)
        for (int x = 0; x < 38; ++x) {
            for (uint32_t l = 0; l < gpu::kAovCount; ++l)
                ASSERT_EQ(pixel(a, l, x + 13, y + 7), pixel(b, l, x, y)) << "layer " << l << " at " << x << "," << y;
            ASSERT_EQ(a.sampleCounts[size_t(y + 7) * 80 + x + 13], b.sampleCounts[size_t(y) * 38 + x]);
        }
}

}  // namespace
}  // namespace whitted::test

// Files written from a render: encodings, tone mapping, names, atomicity.
#include "io/aov_output.h"
#include "io/image_io.h"
#include "test_support.h"

#include <cmath>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

// A 3x1 result whose colour layer holds the given grey values.
RenderResult greyResult(std::vector<float> greys) {
    RenderResult r;
    r.width = int(greys.size());
    r.height = 1;
    r.samplesPerPixel = 1;
    for (float g : greys) r.layers[gpu::kAovColor].insert(r.layers[gpu::kAovColor].end(), {g, g, g, 1.0f});
    return r;
}

std::vector<float> readBack(const fs::path& path) {
    std::vector<float> pixels;
    int w, h, c;
    readImageInto(path, w, h, c, pixels);
    return pixels;
}

fs::path freshDir(const std::string& name) { return freshOutputDir("images", name); }

TEST(ImageOutput, PngIsSrgbEncoded) {
    fs::path dir = freshDir("srgb");
    writeRenderImages(greyResult({0.0f, 0.5f, 2.0f}), dir / "a.png", {}, Tonemap::Clamp);
    std::vector<float> p = readBack(dir / "a.png");
    ASSERT_EQ(p.size(), 9u);
    EXPECT_EQ(p[0], 0.0f);
    // sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 188 of 255.
    EXPECT_NEAR(p[3] * 255.0f, 188.0f, 1e-3f);
    EXPECT_EQ(p[6], 1.0f) << "values above 1 are clamped";
}

TEST(ImageOutput, ExrIsLinearFloat) {
    fs::path dir = freshDir("exr");
    writeRenderImages(greyResult({0.0f, 0.5f, 2.0f}), dir / "a.exr", {}, Tonemap::Clamp);
    std::vector<float> p = readBack(dir / "a.exr");
    ASSERT_EQ(p.size(), 9u);
    EXPECT_EQ(p[3], 0.5f);
    EXPECT_EQ(p[6], 2.0f) << "no clamping in float files";
}

TEST(ImageOutput, SeedTonemapIsMinMaxWithGamma) {
    fs::path dir = freshDir("seed");
    writeRenderImages(greyResult({0.2f, 0.4f, 1.0f}), dir / "a.png", {}, Tonemap::Seed);
    std::vector<float> p = readBack(dir / "a.png");
    EXPECT_EQ(p[0], 0.0f);
    EXPECT_NEAR(p[3] * 255.0f, std::round(std::pow(0.25f, 0.667f) * 255.0f), 1e-3f);
    EXPECT_EQ(p[6], 1.0f);
}

TEST(ImageOutput, AuxiliaryImagesAreNamedBesideTheMainImage) {
    EXPECT_EQ(aovPath("out/room.png", "diffuse"), fs::path("out/room.diffuse.png"));
    EXPECT_EQ(aovPath("r.exr", "depth"), fs::path("r.depth.exr"));
    EXPECT_EQ(parseAovList("none").size(), 0u);
    EXPECT_EQ(parseAovList("all").size(), allAovs().size());
    EXPECT_EQ(parseAovList("depth,normal,depth"), (std::vector<std::string>{"depth", "normal"}));
    EXPECT_THROW(parseAovList("depth,bogus"), std::invalid_argument);
}

TEST(ImageOutput, FailedWriteLeavesNothingBehind) {
    fs::path dir = freshDir("atomic");
    EXPECT_THROW(writeImage(dir / "missing" / "a.png", 1, 1, 1, std::vector<float>{0.5f}, PixelEncoding::Linear8),
                 std::runtime_error);
    EXPECT_TRUE(fs::is_empty(dir));
    writeImage(dir / "b.png", 1, 1, 1, std::vector<float>{0.5f}, PixelEncoding::Linear8);
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path().filename());
    EXPECT_EQ(files, (std::vector<fs::path>{"b.png"})) << "no temporary file left";
}

}  // namespace
}  // namespace whitted::test

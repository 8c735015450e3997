// Golden-image tests: every scene in scenes/ rendered small and compared
// with tests/references/<scene>.png.
//
// Metric (8-bit sRGB values, per channel): the mean absolute difference must
// be at most 0.5 levels, and at most 0.2% of the pixels may differ by more
// than 16 levels in any channel. The second bound leaves room for a handful
// of edge pixels that flip between surfaces when llvmpipe is compiled for
// another vector width (FMA contraction differs), while a moved shadow, a
// changed material or a missing object changes far more pixels than that.
//
// Regenerate every reference (then LOOK at each image before committing):
//   tools/update_references.sh
// On failure the render and a difference image go to build/tests/output/.
#include "io/image_io.h"
#include "output/aov_output.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace whitted::test {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr int kSpp = 4;

std::vector<std::string> sceneNames() {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(sourceDir() / "scenes"))
        if (entry.path().extension() == ".xml") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

class GoldenImage : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenImage, MatchesReference) {
    const std::string name = GetParam();
    Scene scene = loadScene(sourceDir() / "scenes" / (name + ".xml"));
    RenderSettings settings{.width = kWidth, .height = kHeight, .samplesPerPixel = kSpp, .maxDepth = 6,
                            .auxiliary = false};
    RenderResult result = renderScene(scene, settings);

    std::filesystem::path reference = sourceDir() / "tests" / "references" / (name + ".png");
    if (const char* update = std::getenv("WHITTED_UPDATE_REFERENCES"); update && std::string(update) == "1") {
        writeRenderImages(result, reference, {}, Tonemap::Clamp);
        GTEST_SKIP() << "reference written: " << reference;
    }

    // Quantise the render exactly as a PNG file would be.
    std::filesystem::path rendered = outputDir() / (name + ".render.png");
    writeRenderImages(result, rendered, {}, Tonemap::Clamp);
    ASSERT_TRUE(std::filesystem::exists(reference)) << "missing reference " << reference
                                                    << "; run tools/update_references.sh";
    expectGoldenMatch(rendered, reference, outputDir() / (name + ".diff.png"), name);
}

INSTANTIATE_TEST_SUITE_P(Scenes, GoldenImage, ::testing::ValuesIn(sceneNames()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace whitted::test

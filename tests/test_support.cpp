#include "test_support.h"

#include "io/image_io.h"
#include "scene/scene_loader.h"

#include <algorithm>
#include <cmath>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sys/wait.h>
#include <vector>

namespace whitted::test {
namespace {
// No test may depend on pipelines an earlier run left in the user's cache
// folder: the executables the tests start inherit this and keep none
// (PipelineCache.* gives the cache folders of their own).
[[maybe_unused]] const bool kPipelineCacheOff = ::setenv("WHITTED_PIPELINE_CACHE", "0", 1) == 0;
}  // namespace

VulkanContext& testContext() {
    static VulkanContext ctx({.validation = true, .deviceName = "", .pipelineCacheFolder = std::filesystem::path()});
    return ctx;
}

RenderResult renderScene(const Scene& scene, const RenderSettings& settings) {
    VulkanContext& ctx = testContext();
    uint32_t before = ctx.validationMessageCount();
    Renderer renderer(ctx, scene, settings);
    RenderResult result = renderer.render();
    EXPECT_EQ(ctx.validationMessageCount(), before) << "the Vulkan validation layer reported messages (see stderr)";
    return result;
}

RenderResult renderXml(const std::string& xml, const RenderSettings& settings) {
    return renderScene(loadSceneFromString(xml, "inline.xml"), settings);
}

CommandRun runCommand(const std::string& command, const std::filesystem::path& cwd) {
    std::string full = "cd '" + cwd.string() + "' && " + command + " 2>&1";
    FILE* pipe = ::popen(full.c_str(), "r");
    if (!pipe) return {-1, "popen failed: " + command};
    std::string output;
    char buf[4096];
    while (size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
    int status = ::pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::filesystem::path sourceDir() { return WHITTED_SOURCE_DIR; }

std::filesystem::path outputDir() {
    std::filesystem::path dir = WHITTED_TEST_OUTPUT_DIR;
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path freshOutputDir(const std::string& group, const std::string& name) {
    std::filesystem::path dir = outputDir() / group / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                     (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += table[v >> 18 & 63];
        out += table[v >> 12 & 63];
        out += i + 1 < bytes.size() ? table[v >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

std::filesystem::path writeIlluminationObj(const std::filesystem::path& dir) {
    std::filesystem::create_directories(dir / "tex dir");
    writeQuadrantTexture(dir / "tex dir" / "quad.png");
    std::ofstream(dir / "scene.mtl") << "# illumination models\n"
                                        "newmtl plastic\nKa 0.1 0.1 0.1\nKd 0.8 0.2 0.2\nKs 0.5 0.5 0.5\nNs 50\nillum 2\n"
                                        "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nillum 3\n"
                                        "newmtl fresnel_mirror\nKd 0.1 0.1 0.1\nKs 1 1 1\nNi 2\nillum 5\n"
                                        "newmtl glass\nKd 0 0 0\nKs 0.1 0.1 0.1\nTf 1 0.9 0.8\nNi 1.5\nillum 6\n"
                                        "newmtl fresnel_glass\nKd 0 0 0\nKs 0 0 0\nNi 1.33\nillum 7\nmap_Kd tex dir\\quad.png\n";
    std::ofstream obj(dir / "scene.obj");
    obj << "mtllib scene.mtl\n";
    const char* names[] = {"plastic", "mirror", "fresnel_mirror", "glass", "fresnel_glass"};
    for (int i = 0; i < 5; ++i) {
        obj << "v " << i * 2 << " 0 0\nv " << i * 2 + 1 << " 0 0\nv " << i * 2 + 1 << " 1 0\n";
        obj << "vt 0 0\nvt 1 0\nvt 1 1\n";
        obj << "usemtl " << names[i] << "\nf " << i * 3 + 1 << "/" << i * 3 + 1 << " " << i * 3 + 2 << "/" << i * 3 + 2
            << " " << i * 3 + 3 << "/" << i * 3 + 3 << "\n";
    }
    return dir / "scene.obj";
}

std::filesystem::path assimpTestModel(const std::string& relative) {
    return std::filesystem::path("/usr/share/assimp/models") / relative;
}

void expectGoldenMatch(const std::filesystem::path& got, const std::filesystem::path& want,
                       const std::filesystem::path& diffPath, const std::string& what) {
    constexpr double kMaxMeanLevels = 0.5;
    constexpr double kMaxOutlierFraction = 0.002;
    constexpr float kOutlierLevels = 16;
    std::vector<float> a, b;
    int w1, h1, c1, w2, h2, c2;
    readImageInto(got, w1, h1, c1, a);
    readImageInto(want, w2, h2, c2, b);
    ASSERT_EQ(w1, w2) << what;
    ASSERT_EQ(h1, h2) << what;
    ASSERT_EQ(c1, c2) << what;

    double sum = 0;
    size_t outliers = 0;
    std::vector<float> diff(a.size());
    for (size_t p = 0; p < size_t(w1) * h1; ++p) {
        float worst = 0;
        for (int c = 0; c < c1; ++c) {
            size_t i = p * c1 + c;
            float d = std::abs(a[i] - b[i]) * 255.0f;
            sum += d;
            worst = std::max(worst, d);
            diff[i] = std::min(1.0f, d / 32.0f);
        }
        if (worst > kOutlierLevels) ++outliers;
    }
    double mean = sum / double(a.size());
    double outlierFraction = double(outliers) / double(size_t(w1) * h1);
    if (mean > kMaxMeanLevels || outlierFraction > kMaxOutlierFraction)
        writeImage(diffPath, w1, h1, c1, diff, PixelEncoding::Linear8);
    EXPECT_LE(mean, kMaxMeanLevels) << what << ": mean difference in 8-bit levels; see " << diffPath;
    EXPECT_LE(outlierFraction, kMaxOutlierFraction) << what << ": fraction of pixels off by > " << kOutlierLevels;
}

void writeTestTexture(const std::filesystem::path& path, int width, int height,
                      const std::function<glm::vec3(float u, float v)>& colour) {
    std::vector<float> pixels(size_t(width) * height * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            glm::vec3 c = colour((float(x) + 0.5f) / float(width), 1.0f - (float(y) + 0.5f) / float(height));
            for (int k = 0; k < 3; ++k) pixels[(size_t(y) * width + x) * 3 + k] = c[k];
        }
    writeImage(path, width, height, 3, pixels, PixelEncoding::Srgb8);
}

void writeQuadrantTexture(const std::filesystem::path& path) {
    writeTestTexture(path, 64, 64, [](float u, float v) {
        if (v >= 0.5f) return u < 0.5f ? kQuadrantTopLeft : kQuadrantTopRight;
        return u < 0.5f ? kQuadrantBottomLeft : kQuadrantBottomRight;
    });
}

void writeSmoothTexture(const std::filesystem::path& path) {
    writeTestTexture(path, 64, 64, [](float u, float v) {
        constexpr float kTau = 6.28318531f;
        return glm::vec3(0.45f + 0.4f * std::sin(kTau * u), 0.1f + 0.8f * v, 0.4f + 0.3f * std::sin(kTau * (u + v)));
    });
}

}  // namespace whitted::test

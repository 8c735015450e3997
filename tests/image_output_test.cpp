// Files written from a render: encodings, tone mapping, names, atomicity.
#include "output/aov_output.h"
#include "io/image_io.h"
#include "io/image_library.h"
#include "io/png_file.h"
#include "test_support.h"

#include <bit>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <utility>

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
    // The message names the file and the reason (PNG is written without the module: host/io/png_file.cpp).
    try {
        writeImage(dir / "missing" / "a.png", 1, 1, 3, std::vector<float>{0.5f, 0.5f, 0.5f}, PixelEncoding::Srgb8);
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        std::string message = e.what();
        EXPECT_EQ(message.rfind((dir / "missing" / "a.png").string() + ": cannot write image: cannot open ", 0), 0u)
            << message;
        EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
    }
    // A PNG given up after some of its rows (a render that failed halfway) leaves nothing either.
    {
        ImageStreamWriter writer(dir / "c.png", 4, 4, 3, PixelEncoding::Srgb8);
        writer.writeRows(0, 2, std::vector<float>(4 * 2 * 3, 0.25f));
    }
    EXPECT_TRUE(fs::is_empty(dir));
    writeImage(dir / "b.png", 1, 1, 1, std::vector<float>{0.5f}, PixelEncoding::Linear8);
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path().filename());
    EXPECT_EQ(files, (std::vector<fs::path>{"b.png"})) << "no temporary file left";
}

}  // namespace
}  // namespace whitted::test

namespace whitted::test {
namespace {

// OpenImageIO is a module loaded at run time (host/io/image_library.h), not
// a library the executable needs at start: linked, it cost every process
// 0.17 s in the dynamic loader.
TEST(ImageLibrary, ExecutableDoesNotLinkOpenImageIO) {
#ifdef WHITTED_IMAGE_LIBRARY_STATIC
    GTEST_SKIP() << "the sanitizer build links OpenImageIO in (CMakeLists.txt, WHITTED_SANITIZE)";
#endif
    CommandRun run = runCommand("readelf -d '" WHITTED_EXECUTABLE "'", sourceDir());
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("(NEEDED)"), std::string::npos) << run.output;   // the listing was read
    EXPECT_NE(run.output.find("libvulkan"), std::string::npos) << run.output;  // and lists the libraries
    EXPECT_EQ(run.output.find("OpenImageIO"), std::string::npos) << run.output;
}

TEST(ImageLibrary, LoadsOnceAndKnowsTheFormats) {
    preloadImageLibrary();  // on another thread or not, as the load allows: the same library after
    const ImageLibrary& library = imageLibrary();
    EXPECT_EQ(&library, &imageLibrary());
    EXPECT_TRUE(library.canWrite("x.png"));
    EXPECT_TRUE(library.canWrite("x.exr"));
    EXPECT_FALSE(library.canWrite("x.notanimageformat"));
    std::string error;
    EXPECT_EQ(library.openWriter((outputDir() / "no-such-folder" / "x.png").string(),
                                 ImageFileSpec{.width = 1, .height = 1, .channels = 3, .window = {}}, error),
              nullptr);
    EXPECT_FALSE(error.empty());
}

// The output's format is checked once the pipeline is built (the module
// may be loading beside it): a wrong extension is refused, exit 2, before
// any tracing, and nothing is written.
TEST(ImageLibrary, RenderCommandRefusesAnUnknownFormatAndWritesNothing) {
    fs::path dir = freshOutputDir("image_library", "unknown_format");
    CommandRun run = runCommand("'" WHITTED_EXECUTABLE "' render scenes/room.xml --width 8 --height 6 -q -o '" +
                                    (dir / "x.notanimageformat").string() + "'",
                                sourceDir());
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("cannot write images of type '.notanimageformat'"), std::string::npos) << run.output;
    EXPECT_TRUE(fs::is_empty(dir));
}

// PPM and PGM are written without the image module: the same bytes as the
// module writes for the same pixels, 3 channels (P6) and 1 (P5).
TEST(ImageOutput, PpmAndPgmAreTheModulesBytes) {
    fs::path dir = freshDir("pnm");
    auto bytesOf = [](const fs::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    for (auto [name, channels] : {std::pair{"a.ppm", 3}, std::pair{"b.ppm", 1}, std::pair{"c.pgm", 1}}) {
        const int width = 5, height = 3;
        std::vector<float> pixels(size_t(width * height * channels));
        for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i) / float(pixels.size() - 1);
        writeImage(dir / name, width, height, channels, pixels, PixelEncoding::Srgb8);

        std::vector<unsigned char> codes(pixels.size());
        for (size_t i = 0; i < pixels.size(); ++i) codes[i] = encode8(pixels[i], PixelEncoding::Srgb8);
        std::string error;
        fs::path reference = dir / ("module-" + std::string(name));
        auto writer = imageLibrary().openWriter(
            reference.string(), ImageFileSpec{.width = width, .height = height, .channels = channels, .srgb = true,
                                              .window = {}},
            error);
        ASSERT_NE(writer, nullptr) << error;
        ASSERT_TRUE(writer->writeRows(0, height, codes.data(), error)) << error;
        ASSERT_TRUE(writer->close(error)) << error;
        std::vector<char> ours = bytesOf(dir / name), theirs = bytesOf(reference);
        EXPECT_FALSE(ours.empty()) << name;
        EXPECT_EQ(ours, theirs) << name;
    }
}

// PNG is written without the image module (host/io/png_file.cpp): the same
// bytes as the module writes for the same pixels, for 1 to 4 channels, sRGB
// (its colour chunks and text) or not, odd sizes, rows handed in bands of
// several sizes; and the module reads the codes back.
TEST(ImageOutput, PngIsTheModulesBytes) {
    fs::path dir = freshDir("png");
    auto bytesOf = [](const fs::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    std::mt19937 random(19);
    std::uniform_real_distribution<float> unit(-0.1f, 1.1f);  // clamped at both ends too
    struct Size {
        int width, height, band;
    };
    int files = 0;
    for (Size size : {Size{7, 5, 2}, Size{1, 1, 1}, Size{300, 2, 1}, Size{64, 33, 16}})
        for (int channels = 1; channels <= 4; ++channels)
            for (PixelEncoding encoding : {PixelEncoding::Srgb8, PixelEncoding::Linear8}) {
                const int width = size.width, height = size.height;
                std::string name = std::to_string(width) + "x" + std::to_string(height) + "-" +
                                   std::to_string(channels) + (encoding == PixelEncoding::Srgb8 ? "-srgb" : "-linear");
                std::vector<float> pixels(size_t(width) * height * channels);
                for (size_t i = 0; i < pixels.size(); ++i) {
                    pixels[i] = unit(random);
                    // Alpha channels: a third of the pixels opaque (the first among them), a third
                    // transparent, a third in between.
                    size_t p = i / size_t(channels);
                    if ((channels == 2 || channels == 4) && i % channels == size_t(channels - 1) && p % 3 < 2)
                        pixels[i] = p % 3 == 0 ? 1.0f : 0.0f;
                }
                // Ours, in bands as a render hands them in.
                ImageStreamWriter ours(dir / (name + ".png"), width, height, channels, encoding);
                for (int y = 0; y < height; y += size.band) {
                    int rows = std::min(size.band, height - y);
                    ours.writeRows(y, rows, std::span<const float>(pixels).subspan(size_t(y) * width * channels,
                                                                                  size_t(rows) * width * channels));
                }
                ours.commit();

                // The module's, the same codes in one go.
                std::vector<unsigned char> codes(pixels.size());
                for (size_t i = 0; i < pixels.size(); ++i) codes[i] = encode8(pixels[i], encoding);
                std::string error;
                fs::path reference = dir / ("module-" + name + ".png");
                auto writer = imageLibrary().openWriter(
                    reference.string(),
                    ImageFileSpec{.width = width, .height = height, .channels = channels,
                                  .srgb = encoding == PixelEncoding::Srgb8, .window = {}},
                    error);
                ASSERT_NE(writer, nullptr) << error;
                ASSERT_TRUE(writer->writeRows(0, height, codes.data(), error)) << error;
                ASSERT_TRUE(writer->close(error)) << error;
                std::vector<char> mine = bytesOf(dir / (name + ".png")), theirs = bytesOf(reference);
                ASSERT_GT(mine.size(), 8u) << name;
                EXPECT_EQ(mine, theirs) << name;

                // Read back through the module: the codes, exactly. (Its reader
                // associates alpha again, so pixels with alpha are compared
                // where they are opaque.)
                int w, h, c;
                std::vector<float> decoded;
                readImageInto(dir / (name + ".png"), w, h, c, decoded);
                ASSERT_EQ(w, width);
                ASSERT_EQ(h, height);
                ASSERT_EQ(c, channels);
                ASSERT_EQ(decoded.size(), codes.size());
                bool alpha = channels == 2 || channels == 4;
                size_t compared = 0;
                for (size_t p = 0; p < size_t(width) * height; ++p) {
                    if (alpha && codes[p * channels + channels - 1] != 255) continue;
                    for (int k = 0; k < channels; ++k, ++compared)
                        ASSERT_EQ(std::lround(decoded[p * channels + k] * 255.0f), codes[p * channels + k])
                            << name << " pixel " << p << " channel " << k;
                }
                EXPECT_GT(compared, 0u) << name;
                ++files;
            }
    EXPECT_EQ(files, 32);
}

// libpng's errors (here the writes into a full device, at a row or at the
// end) come back as a clear error, not a crash; rows out of order and a
// close before the last row are refused.
TEST(ImageOutput, PngWriterReportsErrors) {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    const int width = 128, height = 64;
    std::vector<unsigned char> noise(size_t(width) * height * 3);
    std::mt19937 random(7);
    for (unsigned char& v : noise) v = static_cast<unsigned char>(random());  // incompressible: writes happen per row
    std::string error;
    auto full = openPngWriter("/dev/full", ImageFileSpec{.width = width, .height = height, .channels = 3,
                                                         .srgb = true, .window = {}},
                              error);
    ASSERT_NE(full, nullptr) << error;
    bool ok = full->writeRows(0, height, noise.data(), error) && full->close(error);
    EXPECT_FALSE(ok);
    EXPECT_NE(error.find("write failed: No space left on device"), std::string::npos) << error;

    fs::path dir = freshDir("png_errors");
    error.clear();
    auto writer = openPngWriter((dir / "a.png").string(),
                                ImageFileSpec{.width = width, .height = height, .channels = 3, .window = {}}, error);
    ASSERT_NE(writer, nullptr) << error;
    EXPECT_FALSE(writer->writeRows(2, 3, noise.data(), error));
    EXPECT_EQ(error, "PNG rows are written in order: expected row 0, got rows 2 to 3");
    ASSERT_TRUE(writer->writeRows(0, 3, noise.data(), error)) << error;
    EXPECT_FALSE(writer->close(error));
    EXPECT_EQ(error, "PNG closed after 3 of 64 rows");

    error.clear();
    EXPECT_EQ(openPngWriter((dir / "b.png").string(),
                            ImageFileSpec{.width = 0, .height = 4, .channels = 3, .window = {}}, error),
              nullptr);
    EXPECT_EQ(error, "PNG needs at least 1x1 pixels, got 0x4");
    EXPECT_EQ(openPngWriter((dir / "c.png").string(),
                            ImageFileSpec{.width = 4, .height = 4, .channels = 5, .window = {}}, error),
              nullptr);
    EXPECT_EQ(error, "PNG holds 1 to 4 channels, not 5");
}

// A render into PNG or PPM files never loads the image module (its load
// costs more than a small render): the dynamic loader's list of the files
// it opened does not name it, with the default auxiliary images and with
// --aov none, while an EXR render's does.
TEST(ImageLibrary, PngAndPpmRendersDoNotLoadTheModule) {
#ifdef WHITTED_IMAGE_LIBRARY_STATIC
    GTEST_SKIP() << "the sanitizer build links OpenImageIO in (CMakeLists.txt, WHITTED_SANITIZE)";
#endif
    fs::path dir = freshOutputDir("image_library", "png_ppm_render");
    for (auto [name, aov] : {std::pair{"x.ppm", "depth"}, std::pair{"y.png", ""}, std::pair{"z.png", "none"},
                             std::pair{"w.exr", "depth"}}) {
        CommandRun run = runCommand("LD_DEBUG=files '" WHITTED_EXECUTABLE
                                    "' render scenes/room.xml --width 8 --height 6 -q" +
                                        (std::string(aov).empty() ? "" : " --aov " + std::string(aov)) + " -o '" +
                                        (dir / name).string() + "'",
                                    sourceDir());
        ASSERT_EQ(run.status, 0) << run.output;
        EXPECT_NE(run.output.find("libvulkan"), std::string::npos) << "the loader's list was read";
        bool loaded = run.output.find("whitted_image_io") != std::string::npos;
        EXPECT_EQ(loaded, fs::path(name).extension() == ".exr") << name;
        EXPECT_TRUE(fs::exists(dir / name)) << name;
    }
    // The default auxiliary images were written beside y.png, each a PNG the module reads.
    int pngs = 0;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().rfind("y.", 0) == 0 && e.path().extension() == ".png") {
            ++pngs;
            std::vector<float> pixels = readBack(e.path());
            EXPECT_FALSE(pixels.empty()) << e.path();
            EXPECT_EQ(pixels.size() % (8u * 6u), 0u) << e.path();
        }
    EXPECT_GT(pngs, 1) << "the main image and auxiliary images";
}

}  // namespace
}  // namespace whitted::test

namespace whitted::test {
namespace {

// The sRGB table of encode8 gives the formula's code: on every 64th float
// of [0, 1], on the 33 floats around each of the codes' steps, and outside.
TEST(ImageOutput, SrgbTableMatchesTheFormula) {
    uint64_t checked = 0, mismatches = 0;
    auto check = [&](float v) {
        ++checked;
        if (encode8(v, PixelEncoding::Srgb8) != encodeSrgb8Formula(v) && ++mismatches <= 5)
            ADD_FAILURE() << "v = " << v << ": table " << int(encode8(v, PixelEncoding::Srgb8)) << ", formula "
                          << int(encodeSrgb8Formula(v));
    };
    const uint32_t one = std::bit_cast<uint32_t>(1.0f);
    for (uint32_t bits = 0; bits <= one; bits += 64) check(std::bit_cast<float>(bits));
    // Around each step: where the formula's code changes, found by walking the sampled floats.
    for (uint32_t bits = 64; bits <= one; bits += 64)
        if (encodeSrgb8Formula(std::bit_cast<float>(bits - 64)) != encodeSrgb8Formula(std::bit_cast<float>(bits)))
            for (uint32_t b = bits - 64; b <= bits; ++b) check(std::bit_cast<float>(b));
    for (float v : {-1.0f, -0.0f, 1.0f, 1.5f, 1e30f, std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                    std::numeric_limits<float>::denorm_min()})
        check(v);
    EXPECT_EQ(mismatches, 0u) << "of " << checked;
    EXPECT_GT(checked, 16000000u);
    EXPECT_EQ(encode8(1.0f, PixelEncoding::Srgb8), 255);
    EXPECT_EQ(encode8(0.5f, PixelEncoding::Srgb8), 188);  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
}

}  // namespace
}  // namespace whitted::test

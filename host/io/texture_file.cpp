#include "io/texture_file.h"

#include "io/image_io.h"
#include "io/image_library.h"
#include "io/srgb.h"

#include "device_types.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <fstream>
#include <glm/gtc/packing.hpp>
#include <iterator>
#include <memory>
#include <system_error>

namespace whitted {
namespace {

bool isLinearColourSpace(const std::string& name) {
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    return lower == "linear" || lower == "lin_srgb" || lower == "scene_linear";
}

// The mip chain of linear RGBA float texels: each level the 2x2 box filter
// of the one above (an odd last row or column is averaged with its
// neighbour's pair, so every level stays a mean of the file's texels), as
// half floats.
std::vector<TextureLevel> buildLevels(int width, int height, std::vector<float> texels) {
    std::vector<TextureLevel> levels;
    for (;;) {
        TextureLevel level{width, height, std::vector<uint16_t>(texels.size())};
        for (size_t i = 0; i < texels.size(); ++i) level.rgba[i] = glm::packHalf1x16(texels[i]);
        levels.push_back(std::move(level));
        if (width == 1 && height == 1) break;
        int w = std::max(1, width / 2), h = std::max(1, height / 2);
        std::vector<float> next(size_t(w) * h * 4, 0.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                int x0 = std::min(2 * x, width - 1), x1 = std::min(2 * x + 1, width - 1);
                int y0 = std::min(2 * y, height - 1), y1 = std::min(2 * y + 1, height - 1);
                for (int c = 0; c < 4; ++c)
                    next[(size_t(y) * w + x) * 4 + c] =
                        0.25f * (texels[(size_t(y0) * width + x0) * 4 + c] + texels[(size_t(y0) * width + x1) * 4 + c] +
                                 texels[(size_t(y1) * width + x0) * 4 + c] + texels[(size_t(y1) * width + x1) * 4 + c]);
            }
        texels = std::move(next);
        width = w;
        height = h;
    }
    return levels;
}

// A texture from a decoded file, or TextureFileError.
TextureData fromDecoded(const DecodedImage& image, TextureEncoding encoding, const std::string& name) {
    // The largest side accepted is the image's (scenes/README.md "Scene files").
    constexpr int maxSide = int(gpu::kMaxImageSide);
    if (image.width < 1 || image.height < 1 || image.width > maxSide || image.height > maxSide)
        throw TextureFileError("is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                               "; a texture must be 1 to " + std::to_string(maxSide) + " texels on each side");
    if (size_t(image.width) * size_t(image.height) > kMaxTextureTexels)
        throw TextureFileError("is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                               "; a texture holds at most " + std::to_string(kMaxTextureTexels) +
                               " texels (8192x8192)");
    if (image.channels < 1 || image.pixels.empty()) throw TextureFileError("has no channels");
    int channels = image.channels;
    const std::vector<float>& stored = image.pixels;
    bool decode = encoding == TextureEncoding::Colour && !image.floatFile && !isLinearColourSpace(image.colourSpace);

    // RGBA: grey fills r, g and b; a missing alpha is 1.
    size_t texels = size_t(image.width) * image.height;
    std::vector<float> rgba(texels * 4);
    for (size_t i = 0; i < texels; ++i) {
        const float* s = &stored[i * channels];
        float r = s[0], g = channels >= 3 ? s[1] : s[0], b = channels >= 3 ? s[2] : s[0];
        float a = channels == 2 ? s[1] : channels >= 4 ? s[3] : 1.0f;
        if (decode) {
            r = srgbToLinear(r);
            g = srgbToLinear(g);
            b = srgbToLinear(b);
        }
        for (float v : {r, g, b, a})
            if (!std::isfinite(v)) throw TextureFileError("has a texel that is not a finite number");
        // Texels are half floats on the device: a larger value would be infinite there.
        for (float v : {r, g, b, a})
            if (std::abs(v) > kMaxHalf)
                throw TextureFileError("has a texel beyond the half-float range (|value| > 65504)");
        rgba[i * 4 + 0] = r;
        rgba[i * 4 + 1] = g;
        rgba[i * 4 + 2] = b;
        rgba[i * 4 + 3] = a;
    }
    TextureData data;
    data.name = name;
    data.srgbDecoded = decode;
    data.levels = buildLevels(image.width, image.height, std::move(rgba));
    return data;
}

// OpenEXR 3.1 allocates each header attribute at the size the file states
// before it reads it, so a few hundred bytes claiming a 2 GB string exhaust
// memory (texture_fuzzer's finding). The header is a list of attributes
// (name\0 type\0 int32 size, then the value) ended by an empty name
// (OpenEXR file layout, "Header"); each is checked against the bytes the
// file has before OpenImageIO sees it. Not an EXR: nothing to check.
void checkExrHeader(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char magic[4] = {};
    if (!in.read(reinterpret_cast<char*>(magic), 4) || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 ||
        magic[3] != 0x01)
        return;
    std::error_code ec;
    const uint64_t fileSize = std::filesystem::file_size(path, ec);
    in.seekg(8);  // magic and version
    auto zeroTerminated = [&](std::string& text) {
        text.clear();
        for (char c; in.get(c) && c != '\0';)
            if (text.size() < 256) text += c;
            else return false;
        return bool(in);
    };
    for (std::string name, type;;) {
        if (!zeroTerminated(name)) throw TextureFileError("could not be read: its EXR header is cut short");
        if (name.empty()) return;
        unsigned char size[4] = {};
        if (!zeroTerminated(type) || !in.read(reinterpret_cast<char*>(size), 4))
            throw TextureFileError("could not be read: its EXR header is cut short");
        const uint64_t bytes = uint64_t(size[0]) | uint64_t(size[1]) << 8 | uint64_t(size[2]) << 16 |
                               uint64_t(size[3]) << 24;
        const uint64_t at = uint64_t(in.tellg());
        if (bytes > fileSize - std::min(at, fileSize))
            throw TextureFileError("could not be read: its EXR header attribute \"" + name + "\" claims " +
                                   std::to_string(bytes) + " bytes, more than the file has");
        in.seekg(std::streamoff(at + bytes));
    }
}

}  // namespace

TextureData readTextureFile(const std::filesystem::path& path, TextureEncoding encoding) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw TextureFileError("does not exist");
    if (std::filesystem::is_directory(path, ec)) throw TextureFileError("is a directory, expected an image file");
    checkExrHeader(path);
    DecodedImage image;
    std::string reason;
    if (!imageLibrary().read(path.string(), int(gpu::kMaxImageSide), kMaxTextureTexels, image, reason))
        throw TextureFileError("could not be read: " + reason);
    return fromDecoded(image, encoding, path.string());
}

TextureData readTextureMemory(std::span<const unsigned char> bytes, const std::string& hint, TextureEncoding encoding,
                              const std::string& name) {
    // The format from the hint, else from the first bytes.
    std::string format = hint;
    if (format.empty() && bytes.size() >= 4 && bytes[0] == 0x89 && bytes[1] == 'P' && bytes[2] == 'N') format = "png";
    if (format.empty() && bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8) format = "jpg";
    if (format.empty()) throw TextureFileError("is in a format that was not recognised (expected PNG or JPEG)");
    DecodedImage image;
    std::string reason;
    if (!imageLibrary().readMemory(bytes, format, int(gpu::kMaxImageSide), kMaxTextureTexels, image, reason))
        throw TextureFileError("could not be read: " + reason);
    TextureData data = fromDecoded(image, encoding, name);
    data.encoded.assign(bytes.begin(), bytes.end());
    data.encodedFormat = format;
    return data;
}

TextureData textureFromImagePixels(int width, int height, int channels, std::span<const float> pixels, bool eightBit,
                                   TextureEncoding encoding, const std::string& name) {
    // Encoded through the project's image writers into a file of the
    // temporary folder (they write files, atomically), read back as bytes.
    static std::atomic<uint64_t> counter{0};
    const std::string format = eightBit ? "png" : "exr";
    std::filesystem::path file = std::filesystem::temp_directory_path() /
                                 ("whitted-texture-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "." + format);
    std::vector<unsigned char> bytes;
    try {
        if (eightBit) {
            std::vector<float> unit(pixels.begin(), pixels.end());
            for (float& v : unit) v /= 255.0f;  // encode8's Linear8 gives the byte back
            writeImage(file, width, height, channels, unit, PixelEncoding::Linear8);
        } else {
            writeImage(file, width, height, channels, pixels, PixelEncoding::Float);
        }
        std::ifstream in(file, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } catch (const std::runtime_error& e) {
        std::error_code ec;
        std::filesystem::remove(file, ec);
        throw TextureFileError(std::string("could not be encoded: ") + e.what());
    }
    std::error_code ec;
    std::filesystem::remove(file, ec);
    return readTextureMemory(bytes, format, encoding, name);
}

TextureData textureFromPixels(int width, int height, std::span<const float> rgba, const std::string& name) {
    TextureData data;
    data.name = name;
    data.levels = buildLevels(width, height, std::vector<float>(rgba.begin(), rgba.end()));
    return data;
}

}  // namespace whitted

// The lean image module (whitted_image_io.so built with
// -DWHITTED_IMAGE_LIBRARY=stb): Sean Barrett's stb_image decoders behind the
// ImageLibrary interface of host/io/image_library.h, for a build that
// carries its shared libraries along (the GPU kit, tools/gpu_kit.sh), where
// OpenImageIO's module would need hundreds of them. The only file that
// includes stb_image.h.
//
// It reads PNG (8 and 16 bits), JPEG, BMP, TGA, GIF, PNM and Radiance HDR.
// It writes no format: 8-bit PNG, PPM and PGM are written without a module
// (host/io/image_io.h), and a render into any other format (EXR) fails with
// this module's reason. Beside OpenImageIO: the file names no colour space
// (8-bit colour textures count as sRGB, as OpenImageIO reports a PNG without
// a gAMA chunk), and JPEG's inverse DCT may round some values one code apart.
#include "io/image_library.h"

#include <stb_image.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <vector>

namespace whitted {
namespace {

constexpr const char* kFormats = "this build's image module (stb_image) reads PNG, JPEG, BMP, TGA, GIF, PNM and HDR";

// Decodes an image held in memory into `image` (all channels as floats;
// 8- and 16-bit values scaled to [0, 1] without the sRGB curve, HDR as
// stored). Larger than maxSide or maxTexels: the size only, no pixels.
bool decode(std::span<const unsigned char> bytes, int maxSide, size_t maxTexels, DecodedImage& image,
            std::string& error) {
    const auto* data = bytes.data();
    const int size = int(bytes.size());
    int width = 0, height = 0, channels = 0;
    if (bytes.size() > size_t(INT32_MAX) || !stbi_info_from_memory(data, size, &width, &height, &channels)) {
        const char* why = stbi_failure_reason();
        error = std::string(why ? why : "not an image") + " (" + kFormats + ")";
        return false;
    }
    image.width = width;
    image.height = height;
    image.channels = channels;
    image.floatFile = stbi_is_hdr_from_memory(data, size) != 0;
    image.colourSpace.clear();
    image.pixels.clear();
    if (width < 1 || height < 1 || channels < 1 || width > maxSide || height > maxSide ||
        size_t(width) * size_t(height) > maxTexels)
        return true;
    const size_t values = size_t(width) * height * channels;
    int w = 0, h = 0, n = 0;
    if (image.floatFile) {
        float* pixels = stbi_loadf_from_memory(data, size, &w, &h, &n, channels);
        if (pixels) image.pixels.assign(pixels, pixels + values);
        stbi_image_free(pixels);
    } else if (stbi_is_16_bit_from_memory(data, size)) {
        stbi_us* pixels = stbi_load_16_from_memory(data, size, &w, &h, &n, channels);
        if (pixels) {
            image.pixels.resize(values);
            for (size_t i = 0; i < values; ++i) image.pixels[i] = float(pixels[i]) / 65535.0f;
        }
        stbi_image_free(pixels);
    } else {
        stbi_uc* pixels = stbi_load_from_memory(data, size, &w, &h, &n, channels);
        if (pixels) {
            image.pixels.resize(values);
            for (size_t i = 0; i < values; ++i) image.pixels[i] = float(pixels[i]) / 255.0f;
        }
        stbi_image_free(pixels);
    }
    if (!image.pixels.empty()) return true;
    const char* why = stbi_failure_reason();
    error = why ? why : "stb_image could not decode it";
    return false;
}

class StbImageLibrary : public ImageLibrary {
public:
    bool canWrite(const std::string&) const override { return false; }

    std::unique_ptr<ImageFileWriter> openWriter(const std::string&, const ImageFileSpec&,
                                                std::string& error) const override {
        error = "this build's image module (stb_image) writes no format; 8-bit PNG, PPM and PGM are written without "
                "it (built with -DWHITTED_IMAGE_LIBRARY=stb)";
        return nullptr;
    }

    bool read(const std::string& path, int maxSide, size_t maxTexels, DecodedImage& image,
              std::string& error) const override {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            error = "could not be opened";
            return false;
        }
        std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        return decode(bytes, maxSide, maxTexels, image, error);
    }

    bool readMemory(std::span<const unsigned char> bytes, const std::string&, int maxSide, size_t maxTexels,
                    DecodedImage& image, std::string& error) const override {
        return decode(bytes, maxSide, maxTexels, image, error);
    }
};

}  // namespace

extern "C" const ImageLibrary* whittedImageLibrary(uint32_t abi) {
    static const StbImageLibrary library;
    return abi == kImageLibraryAbi ? &library : nullptr;
}

}  // namespace whitted

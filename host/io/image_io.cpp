#include "io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace whitted {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

// The sRGB transfer function (IEC 61966-2-1).
float linearToSrgb(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

bool isFloatFormat(const std::filesystem::path& path) {
    std::string ext = lowerExtension(path);
    return ext == ".exr" || ext == ".hdr";
}

bool isWritableFormat(const std::filesystem::path& path) {
    std::string ext = lowerExtension(path);
    if (ext.empty()) return false;
    auto out = OIIO::ImageOutput::create(path.string());
    return out != nullptr;
}

void writeImage(const std::filesystem::path& path, int width, int height, int channels,
                std::span<const float> pixels, PixelEncoding encoding) {
    namespace fs = std::filesystem;
    bool isFloat = isFloatFormat(path);
    std::vector<unsigned char> bytes;
    if (!isFloat) {
        bytes.resize(pixels.size());
        for (size_t i = 0; i < pixels.size(); ++i) {
            float v = encoding == PixelEncoding::Srgb8 ? linearToSrgb(pixels[i]) : std::clamp(pixels[i], 0.0f, 1.0f);
            bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
        }
    }

    // Temporary name in the same folder (same file system, so rename is
    // atomic) with the same extension (OpenImageIO picks the format by it).
    fs::path temporary = path.parent_path() /
                         ("." + path.stem().string() + ".partial-" + std::to_string(::getpid()) + path.extension().string());
    auto out = OIIO::ImageOutput::create(temporary.string());
    if (!out) throw std::runtime_error(path.string() + ": no image writer for this file extension");
    OIIO::ImageSpec spec(width, height, channels, isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!isFloat && encoding == PixelEncoding::Srgb8) spec.attribute("oiio:ColorSpace", "sRGB");
    if (isFloat) spec.attribute("compression", "zip");
    bool ok = out->open(temporary.string(), spec) &&
              (isFloat ? out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())
                       : out->write_image(OIIO::TypeDesc::UINT8, bytes.data())) &&
              out->close();
    if (!ok) {
        std::string error = out->geterror();
        std::error_code ignored;
        fs::remove(temporary, ignored);
        throw std::runtime_error(path.string() + ": cannot write image: " + error);
    }
    std::error_code ec;
    fs::rename(temporary, path, ec);
    if (ec) {
        fs::remove(temporary, ec);
        throw std::runtime_error(path.string() + ": cannot write image: " + ec.message());
    }
}

std::span<const float> readImageInto(const std::filesystem::path& path, int& width, int& height, int& channels,
                                     std::vector<float>& storage) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw std::runtime_error(path.string() + ": cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width;
    height = spec.height;
    channels = spec.nchannels;
    storage.resize(size_t(width) * height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, storage.data()))
        throw std::runtime_error(path.string() + ": cannot read image: " + in->geterror());
    return storage;
}

}  // namespace whitted

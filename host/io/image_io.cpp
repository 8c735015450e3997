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

unsigned char encode8(float v, PixelEncoding encoding) {
    float e = encoding == PixelEncoding::Srgb8 ? linearToSrgb(v) : std::clamp(v, 0.0f, 1.0f);
    return static_cast<unsigned char>(std::lround(e * 255.0f));
}

struct ImageStreamWriter::Output {
    std::unique_ptr<OIIO::ImageOutput> image;
};

ImageStreamWriter::ImageStreamWriter(const std::filesystem::path& path, int width, int height, int channels,
                                     PixelEncoding encoding, const ImageWindow& window)
    : path_(path), out_(std::make_unique<Output>()), width_(width), height_(height), channels_(channels),
      isFloat_(isFloatFormat(path)), encoding_(encoding) {
    // Temporary name in the same folder (same file system, so rename is
    // atomic) with the same extension (OpenImageIO picks the format by it).
    temporary_ = path.parent_path() /
                 ("." + path.stem().string() + ".partial-" + std::to_string(::getpid()) + path.extension().string());
    out_->image = OIIO::ImageOutput::create(temporary_.string());
    if (!out_->image) throw std::runtime_error(path.string() + ": no image writer for this file extension");
    OIIO::ImageSpec spec(width, height, channels, isFloat_ ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!isFloat_ && encoding == PixelEncoding::Srgb8) spec.attribute("oiio:ColorSpace", "sRGB");
    if (isFloat_) {
        spec.attribute("compression", "zip");
        if (window.fullWidth > 0) {
            spec.x = window.x0;
            spec.y = window.y0;
            spec.full_x = 0;
            spec.full_y = 0;
            spec.full_width = window.fullWidth;
            spec.full_height = window.fullHeight;
            y0_ = window.y0;
        }
    }
    if (!out_->image->open(temporary_.string(), spec)) {
        std::string error = out_->image->geterror();
        out_->image.reset();
        std::error_code ignored;
        std::filesystem::remove(temporary_, ignored);
        throw std::runtime_error(path.string() + ": cannot write image: " + error);
    }
}

ImageStreamWriter::~ImageStreamWriter() {
    if (committed_) return;
    if (out_->image) out_->image->close();
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
}

void ImageStreamWriter::writeRows(int row, int rows, std::span<const float> pixels) {
    bool ok;
    if (isFloat_) {
        ok = out_->image->write_scanlines(y0_ + row, y0_ + row + rows, 0, OIIO::TypeDesc::FLOAT, pixels.data());
    } else {
        bytes_.resize(pixels.size());
        for (size_t i = 0; i < pixels.size(); ++i) bytes_[i] = encode8(pixels[i], encoding_);
        ok = out_->image->write_scanlines(row, row + rows, 0, OIIO::TypeDesc::UINT8, bytes_.data());
    }
    if (!ok) throw std::runtime_error(path_.string() + ": cannot write image: " + out_->image->geterror());
}

void ImageStreamWriter::commit() {
    if (!out_->image->close()) throw std::runtime_error(path_.string() + ": cannot write image: " + out_->image->geterror());
    std::error_code ec;
    std::filesystem::rename(temporary_, path_, ec);
    if (ec) throw std::runtime_error(path_.string() + ": cannot write image: " + ec.message());
    committed_ = true;
}

void writeImage(const std::filesystem::path& path, int width, int height, int channels,
                std::span<const float> pixels, PixelEncoding encoding) {
    ImageStreamWriter writer(path, width, height, channels, encoding);
    writer.writeRows(0, height, pixels);
    writer.commit();
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

#include "io/image_io.h"

#include "io/image_library.h"
#include "io/png_file.h"
#include "io/srgb.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
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

// lround(255 * linearToSrgb(v)) without a pow per value: the 255 smallest
// floats at which that code steps up, found once by bisection over the bit
// patterns of the floats in [0, 1] with the formula itself, so that the
// table gives the formula's code for every float (tests/image_output_test.cpp
// checks it against the formula). Writing a 1080p PNG spent 30 ms in pow.
class SrgbEncoder {
public:
    SrgbEncoder() {
        auto code = [](float v) { return std::lround(linearToSrgb(v) * 255.0f); };
        for (long k = 1; k <= 255; ++k) {
            // The smallest float in [0, 1] whose code is at least k.
            uint32_t lo = 0, hi = std::bit_cast<uint32_t>(1.0f);
            while (lo < hi) {
                uint32_t mid = lo + (hi - lo) / 2;
                if (code(std::bit_cast<float>(mid)) >= k) hi = mid;
                else lo = mid + 1;
            }
            steps_[size_t(k - 1)] = std::bit_cast<float>(lo);
        }
    }
    unsigned char operator()(float v) const {
        if (!(v > 0.0f)) return 0;  // negative, zero and NaN, as the formula's lround gives
        return static_cast<unsigned char>(std::upper_bound(steps_.begin(), steps_.end(), v) - steps_.begin());
    }

private:
    std::array<float, 255> steps_;
};

const SrgbEncoder kSrgbEncoder;

// The 8-bit files written here rather than through the image module:
// loading OpenImageIO's hundreds of libraries costs far more than a small
// render (tools/benchmark_results/README.md). Each is the file OpenImageIO
// writes, byte for byte:
//   - binary PPM (3 channels) and PGM (1 channel): a header line and the
//     bytes ("P6\nW H\n255\n", rows from the top); other channel counts go
//     through the module;
//   - PNG of 1 to 4 channels through libpng, with the module's settings and
//     chunks (host/io/png_file.cpp).
bool isNativeFormat(const std::string& extension, int channels) {
    return (extension == ".ppm" && (channels == 1 || channels == 3)) || (extension == ".pgm" && channels == 1) ||
           (extension == ".png" && channels >= 1 && channels <= 4);
}

class PnmWriter final : public ImageFileWriter {
public:
    PnmWriter(const std::string& path, const ImageFileSpec& spec, std::string& error)
        : out_(path, std::ios::binary | std::ios::trunc), rowBytes_(size_t(spec.width) * size_t(spec.channels)) {
        char header[64];
        int n = std::snprintf(header, sizeof header, "P%c\n%d %d\n255\n", spec.channels == 1 ? '5' : '6', spec.width,
                              spec.height);
        out_.write(header, n);
        if (!out_) error = "cannot open " + path + " for writing";
    }
    bool ok() const { return bool(out_); }
    bool writeRows(int y0, int y1, const void* pixels, std::string& error) override {
        out_.write(static_cast<const char*>(pixels), std::streamsize(rowBytes_ * size_t(y1 - y0)));
        if (!out_) error = "write failed";
        return bool(out_);
    }
    bool close(std::string& error) override {
        out_.close();
        if (!out_) error = "write failed";
        return bool(out_);
    }

private:
    std::ofstream out_;
    size_t rowBytes_;
};

}  // namespace

bool isFloatFormat(const std::filesystem::path& path) {
    std::string ext = lowerExtension(path);
    return ext == ".exr" || ext == ".hdr";
}

bool isWritableFormat(const std::filesystem::path& path) {
    std::string ext = lowerExtension(path);
    if (ext.empty()) return false;
    if (writtenWithoutImageLibrary(path)) return true;
    return imageLibrary().canWrite(path.string());
}

bool writtenWithoutImageLibrary(const std::filesystem::path& path) {
    std::string ext = lowerExtension(path);
    return ext == ".ppm" || ext == ".pgm" || ext == ".png";
}

unsigned char encode8(float v, PixelEncoding encoding) {
    if (encoding == PixelEncoding::Srgb8) return kSrgbEncoder(v);
    return static_cast<unsigned char>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

unsigned char encodeSrgb8Formula(float v) { return static_cast<unsigned char>(std::lround(linearToSrgb(v) * 255.0f)); }

struct ImageStreamWriter::Output {
    std::unique_ptr<ImageFileWriter> file;
};

ImageStreamWriter::ImageStreamWriter(const std::filesystem::path& path, int width, int height, int channels,
                                     PixelEncoding encoding, const ImageWindow& window)
    : path_(path), out_(std::make_unique<Output>()),
      isFloat_(isFloatFormat(path)), encoding_(encoding) {
    // Temporary name in the same folder (same file system, so rename is
    // atomic) with the same extension (OpenImageIO picks the format by it).
    temporary_ = path.parent_path() /
                 ("." + path.stem().string() + ".partial-" + std::to_string(::getpid()) + path.extension().string());
    if (encoding == PixelEncoding::Uint32 && !isFloat_)
        throw std::logic_error(path.string() + ": 32-bit integer pixels need a float format (EXR)");
    ImageFileSpec spec{.width = width, .height = height, .channels = channels, .floatPixels = isFloat_,
                       .uintPixels = encoding == PixelEncoding::Uint32,
                       .srgb = encoding == PixelEncoding::Srgb8 || encoding == PixelEncoding::Srgb8Alpha,
                       .window = window};
    std::string error;
    std::string extension = lowerExtension(path);
    bool native = !isFloat_ && isNativeFormat(extension, channels);
    if (native && extension == ".png") {
        out_->file = openPngWriter(temporary_.string(), spec, error);
    } else if (native) {
        auto pnm = std::make_unique<PnmWriter>(temporary_.string(), spec, error);
        if (pnm->ok()) out_->file = std::move(pnm);
    } else {
        out_->file = imageLibrary().openWriter(temporary_.string(), spec, error);
    }
    if (!out_->file) {
        std::error_code ignored;
        std::filesystem::remove(temporary_, ignored);
        throw std::runtime_error(path.string() + ": cannot write image: " + error);
    }
}

ImageStreamWriter::~ImageStreamWriter() {
    if (committed_) return;
    out_->file.reset();  // closes it
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
}

void ImageStreamWriter::writeRows(int row, int rows, std::span<const float> pixels) {
    std::string error;
    bool ok;
    if (isFloat_) {
        ok = out_->file->writeRows(row, row + rows, pixels.data(), error);
    } else {
        bytes_.resize(pixels.size());
        if (encoding_ == PixelEncoding::Srgb8Alpha)
            for (size_t i = 0; i < pixels.size(); ++i)
                bytes_[i] = encode8(pixels[i], i % 4 == 3 ? PixelEncoding::Linear8 : PixelEncoding::Srgb8);
        else
            for (size_t i = 0; i < pixels.size(); ++i) bytes_[i] = encode8(pixels[i], encoding_);
        ok = out_->file->writeRows(row, row + rows, bytes_.data(), error);
    }
    if (!ok) throw std::runtime_error(path_.string() + ": cannot write image: " + error);
}

void ImageStreamWriter::commit() {
    std::string error;
    if (!out_->file->close(error)) throw std::runtime_error(path_.string() + ": cannot write image: " + error);
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
    DecodedImage image;
    std::string error;
    if (!imageLibrary().read(path.string(), std::numeric_limits<int>::max(), std::numeric_limits<size_t>::max(), image,
                             error))
        throw std::runtime_error(path.string() + ": cannot read image: " + error);
    width = image.width;
    height = image.height;
    channels = image.channels;
    storage = std::move(image.pixels);
    return storage;
}

}  // namespace whitted

#include "io/png_file.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <vector>

namespace whitted {
namespace {

// What OpenImageIO 2.4's PNG writer does with an 8-bit ImageSpec
// (src/png.imageio/pngoutput.cpp and png_pvt.h), mirrored call for call on
// the same libpng, so that the files are the same bytes (tested in
// tests/image_output_test.cpp against the module):
//   - zlib level 6, the default strategy, no row filters (png:filter 0);
//   - IHDR: 8 bits, grey / grey+alpha / RGB / RGBA by channel count, not
//     interlaced;
//   - oFFs 0 0 (pixel units), always;
//   - for oiio:ColorSpace sRGB: sRGB (absolute colorimetric intent) with its
//     gAMA and cHRM, and the attribute itself as the text chunk
//     "oiio:ColorSpace" = "sRGB" (every string attribute becomes one);
//   - no time, no software name, no pHYs;
//   - 2 and 4 channels: the alpha is taken as associated and divided out
//     (PNG stores unassociated alpha), in integers: c = min(255, c * 255 / a)
//     where a > 0.
class PngWriter final : public ImageFileWriter {
public:
    PngWriter(const ImageFileSpec& spec) : width_(spec.width), height_(spec.height), channels_(spec.channels) {}
    ~PngWriter() override { release(); }
    PngWriter(const PngWriter&) = delete;
    PngWriter& operator=(const PngWriter&) = delete;

    bool open(const std::string& path, const ImageFileSpec& spec, std::string& error) {
        if (spec.channels < 1 || spec.channels > 4) {
            error = "PNG holds 1 to 4 channels, not " + std::to_string(spec.channels);
            return false;
        }
        if (spec.width < 1 || spec.height < 1) {
            error = "PNG needs at least 1x1 pixels, got " + std::to_string(spec.width) + "x" +
                    std::to_string(spec.height);
            return false;
        }
        file_ = std::fopen(path.c_str(), "wb");
        if (!file_) {
            error = "cannot open " + path + " for writing: " + std::strerror(errno);
            return false;
        }
        png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, this, onError, onWarning);
        if (png_) info_ = png_create_info_struct(png_);
        if (!png_ || !info_) {
            error = "libpng could not start a write";
            return false;
        }
        static const int kColourTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                           PNG_COLOR_TYPE_RGB_ALPHA};
        bool srgb = spec.srgb;
        return guarded(error, [&] {
            png_set_write_fn(png_, this, onWrite, onFlush);
            png_set_compression_level(png_, 6);
            png_set_compression_strategy(png_, Z_DEFAULT_STRATEGY);
            png_set_filter(png_, 0, PNG_NO_FILTERS);
#if defined(PNG_SKIP_sRGB_CHECK_PROFILE) && defined(PNG_SET_OPTION_SUPPORTED)
            png_set_option(png_, PNG_SKIP_sRGB_CHECK_PROFILE, PNG_OPTION_ON);
#endif
            png_set_IHDR(png_, info_, png_uint_32(width_), png_uint_32(height_), 8, kColourTypes[channels_ - 1],
                         PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
            png_set_oFFs(png_, info_, 0, 0, PNG_OFFSET_PIXEL);
            if (srgb) {
                png_set_sRGB_gAMA_and_cHRM(png_, info_, PNG_sRGB_INTENT_ABSOLUTE);
                png_text text{};
                text.compression = PNG_TEXT_COMPRESSION_NONE;
                text.key = const_cast<char*>("oiio:ColorSpace");  // libpng copies both
                text.text = const_cast<char*>("sRGB");
                png_set_text(png_, info_, &text, 1);
            }
            png_write_info(png_, info_);
        });
    }

    bool writeRows(int y0, int y1, const void* pixels, std::string& error) override {
        if (!png_) {
            error = "the PNG file is closed";
            return false;
        }
        if (y0 != nextRow_ || y1 < y0 || y1 > height_) {
            error = "PNG rows are written in order: expected row " + std::to_string(nextRow_) + ", got rows " +
                    std::to_string(y0) + " to " + std::to_string(y1);
            return false;
        }
        const auto* bytes = static_cast<const unsigned char*>(pixels);
        size_t rowBytes = size_t(width_) * size_t(channels_);
        bool alpha = channels_ == 2 || channels_ == 4;
        if (alpha) scratch_.resize(rowBytes);
        bool ok = guarded(error, [&] {
            for (int y = y0; y < y1; ++y) {
                const unsigned char* row = bytes + size_t(y - y0) * rowBytes;
                if (alpha) {
                    std::copy(row, row + rowBytes, scratch_.begin());
                    unassociateAlpha(scratch_.data());
                    row = scratch_.data();
                }
                png_write_row(png_, row);
                ++nextRow_;
            }
        });
        return ok;
    }

    bool close(std::string& error) override {
        if (!png_) {
            error = "the PNG file is closed";
            return false;
        }
        bool ok = true;
        if (nextRow_ != height_) {
            error = "PNG closed after " + std::to_string(nextRow_) + " of " + std::to_string(height_) + " rows";
            ok = false;
        } else {
            ok = guarded(error, [&] { png_write_end(png_, info_); });
        }
        png_destroy_write_struct(&png_, &info_);
        png_ = nullptr;
        info_ = nullptr;
        if (std::fclose(file_) != 0 && ok) {
            error = std::string("write failed: ") + std::strerror(errno);
            ok = false;
        }
        file_ = nullptr;
        return ok;
    }

private:
    // Runs libpng calls; an error inside them (libpng's own, or the write
    // callback's) jumps back here and becomes `error`. `calls` must hold no
    // objects with destructors: the jump skips them.
    template <class Calls>
    bool guarded(std::string& error, Calls&& calls) {
        if (setjmp(png_jmpbuf(png_))) {  // NOLINT(cert-err52-cpp): libpng's error model
            error = libpngError_[0] ? libpngError_ : "libpng gave no reason";
            if (libpngWarning_[0]) error += std::string(" (") + libpngWarning_ + ")";
            return false;
        }
        calls();
        return true;
    }

    [[noreturn]] static void onError(png_structp png, png_const_charp message) {
        auto* self = static_cast<PngWriter*>(png_get_error_ptr(png));
        std::snprintf(self->libpngError_, sizeof self->libpngError_, "%s", message ? message : "");
        png_longjmp(png, 1);
    }
    // Warnings are not errors (as in the module); the last one is kept for
    // the message of an error that follows it ("Invalid IHDR data" says
    // which field in a warning before).
    static void onWarning(png_structp png, png_const_charp message) {
        auto* self = static_cast<PngWriter*>(png_get_error_ptr(png));
        std::snprintf(self->libpngWarning_, sizeof self->libpngWarning_, "%s", message ? message : "");
    }
    static void onWrite(png_structp png, png_bytep data, size_t length) {
        auto* self = static_cast<PngWriter*>(png_get_io_ptr(png));
        if (std::fwrite(data, 1, length, self->file_) != length) {
            char message[128];
            std::snprintf(message, sizeof message, "write failed: %s", std::strerror(errno));
            png_error(png, message);
        }
    }
    static void onFlush(png_structp png) { std::fflush(static_cast<PngWriter*>(png_get_io_ptr(png))->file_); }

    void unassociateAlpha(unsigned char* row) const {
        int a = channels_ - 1;
        for (int x = 0; x < width_; ++x, row += channels_) {
            unsigned alpha = row[a];
            if (!alpha) continue;
            for (int c = 0; c < a; ++c) row[c] = static_cast<unsigned char>(std::min(255u, row[c] * 255u / alpha));
        }
    }

    void release() {
        if (png_) png_destroy_write_struct(&png_, info_ ? &info_ : nullptr);
        if (file_) std::fclose(file_);
        png_ = nullptr;
        info_ = nullptr;
        file_ = nullptr;
    }

    int width_, height_, channels_;
    std::FILE* file_ = nullptr;
    png_structp png_ = nullptr;
    png_infop info_ = nullptr;
    int nextRow_ = 0;
    std::vector<unsigned char> scratch_;
    char libpngError_[256] = {};
    char libpngWarning_[256] = {};
};

}  // namespace

std::unique_ptr<ImageFileWriter> openPngWriter(const std::string& path, const ImageFileSpec& spec,
                                               std::string& error) {
    auto writer = std::make_unique<PngWriter>(spec);
    if (!writer->open(path, spec, error)) return nullptr;
    return writer;
}

}  // namespace whitted

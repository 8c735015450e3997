// The image file module (whitted_image_io.so): OpenImageIO behind the
// ImageLibrary interface of host/io/image_library.h. The only file that
// includes OpenImageIO's headers.
#include "io/image_library.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <exception>

namespace whitted {
namespace {

std::string reasonOr(std::string reason) {
    return reason.empty() ? std::string("OpenImageIO gave no reason") : reason;
}

class OiioWriter : public ImageFileWriter {
public:
    OiioWriter(std::unique_ptr<OIIO::ImageOutput> out, OIIO::TypeDesc format, int y0)
        : out_(std::move(out)), format_(format), y0_(y0) {}
    ~OiioWriter() override {
        if (out_) out_->close();
    }
    bool writeRows(int y0, int y1, const void* pixels, std::string& error) override {
        if (out_->write_scanlines(y0_ + y0, y0_ + y1, 0, format_, pixels))
            return true;
        error = reasonOr(out_->geterror());
        return false;
    }
    bool close(std::string& error) override {
        bool ok = out_->close();
        if (!ok) error = reasonOr(out_->geterror());
        out_.reset();
        return ok;
    }

private:
    std::unique_ptr<OIIO::ImageOutput> out_;
    OIIO::TypeDesc format_;  // of the pixels handed in and of the file
    int y0_;
};

// The spec and pixels of an opened input, all channels as floats.
bool readOpened(OIIO::ImageInput& in, int maxSide, size_t maxTexels, DecodedImage& image, std::string& error) {
    const OIIO::ImageSpec& spec = in.spec();
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    image.floatFile = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                      spec.format.basetype == OIIO::TypeDesc::HALF ||
                      spec.format.basetype == OIIO::TypeDesc::DOUBLE;
    image.colourSpace = spec.get_string_attribute("oiio:ColorSpace");
    image.pixels.clear();
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.width > maxSide || spec.height > maxSide ||
        size_t(spec.width) * size_t(spec.height) > maxTexels)
        return true;
    image.pixels.resize(size_t(spec.width) * spec.height * spec.nchannels);
    if (in.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) return true;
    error = reasonOr(in.geterror());
    image.pixels.clear();
    return false;
}

class OiioImageLibrary : public ImageLibrary {
public:
    bool canWrite(const std::string& path) const override {
        return OIIO::ImageOutput::create(path) != nullptr;
    }

    std::unique_ptr<ImageFileWriter> openWriter(const std::string& path, const ImageFileSpec& s,
                                                std::string& error) const override {
        try {
            auto out = OIIO::ImageOutput::create(path);
            if (!out) {
                error = "no image writer for this file extension";
                return nullptr;
            }
            OIIO::TypeDesc format = !s.floatPixels ? OIIO::TypeDesc::UINT8
                                    : s.uintPixels ? OIIO::TypeDesc::UINT32
                                                   : OIIO::TypeDesc::FLOAT;
            OIIO::ImageSpec spec(s.width, s.height, s.channels, format);
            if (!s.floatPixels && s.srgb) spec.attribute("oiio:ColorSpace", "sRGB");
            int y0 = 0;
            if (s.floatPixels) {
                spec.attribute("compression", "zip");
                if (s.window.fullWidth > 0) {
                    spec.x = s.window.x0;
                    spec.y = s.window.y0;
                    spec.full_x = 0;
                    spec.full_y = 0;
                    spec.full_width = s.window.fullWidth;
                    spec.full_height = s.window.fullHeight;
                    y0 = s.window.y0;
                }
            }
            if (!out->open(path, spec)) {
                error = reasonOr(out->geterror());
                return nullptr;
            }
            return std::make_unique<OiioWriter>(std::move(out), format, y0);
        } catch (const std::exception& e) {
            error = e.what();
            return nullptr;
        }
    }

    bool read(const std::string& path, int maxSide, size_t maxTexels, DecodedImage& image,
              std::string& error) const override {
        try {
            auto in = OIIO::ImageInput::open(path);
            if (!in) {
                error = reasonOr(OIIO::geterror());
                return false;
            }
            return readOpened(*in, maxSide, maxTexels, image, error);
        } catch (const std::exception& e) {
            error = e.what();
            return false;
        }
    }

    bool readMemory(std::span<const unsigned char> bytes, const std::string& format, int maxSide, size_t maxTexels,
                    DecodedImage& image, std::string& error) const override {
        try {
            OIIO::Filesystem::IOMemReader reader(const_cast<unsigned char*>(bytes.data()), bytes.size());
            auto in = OIIO::ImageInput::create(format);
            if (!in) {
                error = reasonOr(OIIO::geterror());
                return false;
            }
            OIIO::ImageSpec spec;
            if (!in->set_ioproxy(&reader) || !in->open("embedded." + format, spec)) {
                error = reasonOr(in->geterror());
                return false;
            }
            return readOpened(*in, maxSide, maxTexels, image, error);
        } catch (const std::exception& e) {
            error = e.what();
            return false;
        }
    }
};

}  // namespace

extern "C" const ImageLibrary* whittedImageLibrary(uint32_t abi) {
    static const OiioImageLibrary library;
    return abi == kImageLibraryAbi ? &library : nullptr;
}

}  // namespace whitted

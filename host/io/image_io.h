// Image files, written atomically: a temporary file in the destination
// folder is renamed over the target only once complete. 8-bit PNG, PPM and
// PGM are written here (libpng for PNG), other formats and all reading
// through OpenImageIO's module (host/io/image_library.h).
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace whitted {

enum class PixelEncoding {
    Srgb8,    // 8-bit, sRGB transfer curve applied (colour images)
    Srgb8Alpha,  // 8-bit RGBA: the sRGB curve on the colour, the alpha (each 4th value) stored as it is
    Linear8,  // 8-bit, values stored as they are (data images)
    Float,    // 32-bit float, linear (EXR)
    Uint32,   // float formats only: the floats' bits as 32-bit unsigned integers (mask ids, EXR UINT)
};

// True if the extension names a format that stores float pixels (.exr, .hdr).
bool isFloatFormat(const std::filesystem::path& path);
// True if OpenImageIO can write this file's format (.png, .ppm and .pgm
// without loading it: see writtenWithoutImageLibrary).
bool isWritableFormat(const std::filesystem::path& path);
// True for .png, .ppm and .pgm, whose 8-bit images (PNG: 1 to 4 channels;
// PPM: 1 and 3; PGM: 1, the channel counts a render writes) are written
// here without the image module (host/io/image_library.h), byte for byte
// as it would write them: a render into them need not load it.
bool writtenWithoutImageLibrary(const std::filesystem::path& path);

// Where an image's pixels sit in a larger picture: float formats (EXR) keep
// the full picture as display window and the pixels as data window at
// (x0, y0); 8-bit formats store the pixels alone.
struct ImageWindow {
    int fullWidth = 0;
    int fullHeight = 0;
    int x0 = 0;
    int y0 = 0;
};

// The 8-bit value written for v.
unsigned char encode8(float v, PixelEncoding encoding);
// The sRGB code by the formula, one pow per value: what encode8's table
// must give (tests).
unsigned char encodeSrgb8Formula(float v);

// An image written band by band, top to bottom, so that memory holds one
// band: under a temporary name in the destination folder, renamed over the
// target by commit() once complete; destroyed uncommitted, it removes the
// temporary file. Throws std::runtime_error naming the file.
class ImageStreamWriter {
public:
    ImageStreamWriter(const std::filesystem::path& path, int width, int height, int channels, PixelEncoding encoding,
                      const ImageWindow& window = {});
    ~ImageStreamWriter();
    ImageStreamWriter(const ImageStreamWriter&) = delete;
    ImageStreamWriter& operator=(const ImageStreamWriter&) = delete;

    // Rows [row, row + rows) of the image (0 = its first row), `channels`
    // interleaved floats per pixel.
    void writeRows(int row, int rows, std::span<const float> pixels);
    void commit();
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_, temporary_;
    struct Output;
    std::unique_ptr<Output> out_;
    bool isFloat_;
    PixelEncoding encoding_;
    std::vector<unsigned char> bytes_;
    bool committed_ = false;
};

// Writes `channels` interleaved floats per pixel, rows from the top. For
// float formats `encoding` is ignored. Throws std::runtime_error.
void writeImage(const std::filesystem::path& path, int width, int height, int channels,
                std::span<const float> pixels, PixelEncoding encoding);

// Reads an image as interleaved floats (8-bit data is returned in [0,1],
// sRGB decoding is not applied). Throws std::runtime_error.
std::span<const float> readImageInto(const std::filesystem::path& path, int& width, int& height, int& channels,
                                     std::vector<float>& storage);

}  // namespace whitted

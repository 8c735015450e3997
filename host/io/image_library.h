// OpenImageIO behind a module of its own (whitted_image_io.so), loaded when
// an image file is first read or written in a format other than 8-bit PNG,
// PPM and PGM (written without it: host/io/image_io.h), or ahead of that on
// a second thread (preloadImageLibrary).
//
// Why: Debian's OpenImageIO links hundreds of shared libraries (OpenCV,
// FFmpeg, GDAL, DCMTK, ...), all built with BIND_NOW, so a process linked to
// it spent a noticeable part of its start in the dynamic loader before main
// (measured: see tools/benchmark_results/README.md). A process that reads
// no image and writes none or only PNG, PPM and PGM (`whitted render` into
// PNG without textures, `whitted view` without textures, a refused scene,
// `whitted devices`) never pays it, and `whitted render` into other
// formats loads it on a second thread while lavapipe builds the pipeline,
// but only when a core is idle: the loader's locks, not the cores, are what
// the two would contend for (tools/benchmark_results/notes-build.md).
//
// The dynamic loader's state is per process, so the loaded module is too:
// imageLibrary() hands out the one instance, loading it on first use.
#pragma once

#include "io/image_io.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace whitted {

// An image file's pixels as floats, every channel, rows from the top.
struct DecodedImage {
    int width = 0;
    int height = 0;
    int channels = 0;
    bool floatFile = false;    // the file stores float, half or double values
    std::string colourSpace;   // the file's colour space, when it names one (oiio:ColorSpace)
    std::vector<float> pixels; // empty when the image was larger than the reader's limit
};

// How an image file is written.
struct ImageFileSpec {
    int width = 0;
    int height = 0;
    int channels = 0;
    bool floatPixels = false;  // 32-bit float (EXR, HDR), else 8-bit
    bool uintPixels = false;   // with floatPixels: 32-bit unsigned integers instead (EXR UINT)
    bool srgb = false;         // 8-bit pixels that carry the sRGB curve
    ImageWindow window;        // float files: the data window's place in the full picture
};

// An open image file being written. Errors come back as false with `error`
// set (nothing throws across the module's boundary).
class ImageFileWriter {
public:
    virtual ~ImageFileWriter() = default;
    // Rows [y0, y1) of the data window: floats for float files, else bytes.
    virtual bool writeRows(int y0, int y1, const void* pixels, std::string& error) = 0;
    virtual bool close(std::string& error) = 0;
};

// The functions the module offers (host/io/oiio_image_library.cpp).
class ImageLibrary {
public:
    virtual ~ImageLibrary() = default;
    // Whether a writer exists for this file name's extension.
    virtual bool canWrite(const std::string& path) const = 0;
    // A writer for `path` (its extension picks the format), or null and `error`.
    virtual std::unique_ptr<ImageFileWriter> openWriter(const std::string& path, const ImageFileSpec& spec,
                                                        std::string& error) const = 0;
    // Reads a file, or an image held in memory in `format` ("png", "jpg").
    // An image wider or taller than maxSide, or of more than maxTexels
    // texels, is returned without its pixels (nothing is allocated for them).
    virtual bool read(const std::string& path, int maxSide, size_t maxTexels, DecodedImage& image,
                      std::string& error) const = 0;
    virtual bool readMemory(std::span<const unsigned char> bytes, const std::string& format, int maxSide,
                            size_t maxTexels, DecodedImage& image, std::string& error) const = 0;
};

// The module's one entry point; null when `abi` is not the one it was built with.
constexpr uint32_t kImageLibraryAbi = 3;
extern "C" const ImageLibrary* whittedImageLibrary(uint32_t abi);

// The library, loaded now unless loaded already (waits for a load under
// way). Throws std::runtime_error naming the places tried.
const ImageLibrary& imageLibrary();

// Starts loading the library on another thread and returns at once, when
// a core is idle now (fewer threads running or ready to run than cores,
// this one included); else does nothing and the first use loads it. Call
// it after the Vulkan instance exists: the dynamic loader loads one library
// at a time, so a load under way would hold up the Vulkan loader's.
void preloadImageLibrary();

}  // namespace whitted

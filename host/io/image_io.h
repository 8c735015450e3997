// Image files through OpenImageIO, written atomically: a temporary file in
// the destination folder is renamed over the target only once complete.
#pragma once

#include <filesystem>
#include <span>
#include <vector>

namespace whitted {

enum class PixelEncoding {
    Srgb8,    // 8-bit, sRGB transfer curve applied (colour images)
    Linear8,  // 8-bit, values stored as they are (data images)
    Float,    // 32-bit float, linear (EXR)
};

// True if the extension names a format that stores float pixels (.exr, .hdr).
bool isFloatFormat(const std::filesystem::path& path);
// True if OpenImageIO can write this file's format.
bool isWritableFormat(const std::filesystem::path& path);

// Writes `channels` interleaved floats per pixel, rows from the top. For
// float formats `encoding` is ignored. Throws std::runtime_error.
void writeImage(const std::filesystem::path& path, int width, int height, int channels,
                std::span<const float> pixels, PixelEncoding encoding);

// Reads an image as interleaved floats (8-bit data is returned in [0,1],
// sRGB decoding is not applied). Throws std::runtime_error.
std::span<const float> readImageInto(const std::filesystem::path& path, int& width, int& height, int& channels,
                                     std::vector<float>& storage);

}  // namespace whitted

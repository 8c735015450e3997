// Image textures (diffuse colour maps, normal maps) read through
// OpenImageIO: PNG, JPEG, EXR, TIFF, ... decoded on the host to linear
// RGBA half floats with their whole mip chain, ready for upload
// (host/render/texture_set.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/texture.h"

namespace whitted {

// A texture file that can not be used. what() ends a sentence about the
// file ("does not exist", "could not be read: ..."); the scene loader names
// the file and places it at its element.
class TextureFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// How a file's values are meant. Colour: 8- and 16-bit integer files are
// sRGB-encoded (unless the file says it is linear) and are decoded to
// linear light; float files (EXR, HDR) are linear already. Data (normal
// maps): the values as stored, never decoded.
enum class TextureEncoding { Colour, Data };

// The most texels a texture may hold (8192x8192), checked before its pixels
// are allocated: decoding holds four floats a texel twice over (2 GiB at
// the limit), so a small file that claims a huge image is refused unread.
inline constexpr size_t kMaxTextureTexels = size_t(1) << 26;
// The largest finite half float, the texels' type on the device.
inline constexpr float kMaxHalf = 65504.0f;

// Reads a texture file. Throws TextureFileError.
TextureData readTextureFile(const std::filesystem::path& path, TextureEncoding encoding);
// The same from an image file held in memory (a model file's embedded
// texture); `hint` is its format's extension ("png", "jpg") or empty.
TextureData readTextureMemory(std::span<const unsigned char> bytes, const std::string& hint, TextureEncoding encoding,
                              const std::string& name);
// A texture from pixels held in memory (Python's Material(diffuse_texture=
// array)): `channels` (3 or 4) interleaved values a pixel, rows from the
// top; eightBit: bytes (as floats 0..255) stored as an 8-bit PNG, else
// floats stored as a 32-bit float EXR. The texels are decoded from those
// file bytes as readTextureMemory decodes them (an 8-bit PNG as
// sRGB-encoded for TextureEncoding::Colour, an EXR as linear), and the
// bytes kept in TextureData::encoded, so that the file written from them
// (scene/scene_writer.h writeFilelessTextures) reads back to the same
// texels. Throws TextureFileError.
TextureData textureFromImagePixels(int width, int height, int channels, std::span<const float> pixels, bool eightBit,
                                   TextureEncoding encoding, const std::string& name);
// A texture from linear RGBA float texels (rows from the top), mip chain built.
TextureData textureFromPixels(int width, int height, std::span<const float> rgba, const std::string& name);

}  // namespace whitted

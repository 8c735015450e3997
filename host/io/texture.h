// Decoded image textures: plain data shared by the scene model (materials
// hold them), the file reader (io/texture_file.h) and the upload
// (render/texture_set.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace whitted {

struct TextureLevel {
    int width = 0;
    int height = 0;
    std::vector<uint16_t> rgba;  // half floats, 4 per texel, rows from the image's top
};

struct TextureData {
    std::string name;                  // as the scene (or model file) gives it, for messages
    std::vector<TextureLevel> levels;  // level 0 the file itself, each next one half the size, down to 1x1
    bool srgbDecoded = false;          // the file was sRGB-encoded and decoded on reading
    // A texture decoded from bytes inside another file (a .glb's image): those
    // bytes and their format ("png", "jpg"), so that `whitted convert` can
    // write them out as a file of their own; empty for a texture file.
    std::vector<unsigned char> encoded;
    std::string encodedFormat;
};

}  // namespace whitted

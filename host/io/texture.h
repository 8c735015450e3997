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
};

}  // namespace whitted

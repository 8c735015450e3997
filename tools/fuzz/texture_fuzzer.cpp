// libFuzzer target for texture decoding (io/texture_file.cpp through the
// image module, OpenImageIO linked in; tools/run_fuzzer.sh builds and runs
// it, seeded from tests/fuzz_corpus/texture). The first byte picks how the
// rest is met: as a texture file of one of the formats a scene names
// (.png .jpg .exr .hdr .tga .bmp .tif), or as an embedded glTF image in
// memory (PNG or JPEG, or told by its first bytes). Whatever the bytes, the
// reader must refuse them with a TextureFileError or return a texture that
// keeps its promises: 1 to 16384 texels a side and at most
// kMaxTextureTexels, a full mip chain each level half the one above down to
// 1x1, four finite half floats a texel.
#include "io/texture_file.h"

#include "device_types.h"
#include "model_file.h"
#include "scene_checks.h"

#include <glm/gtc/packing.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

using namespace whitted;

namespace {

void checkTexture(const TextureData& t) {
    fuzz::check(!t.levels.empty());
    const TextureLevel& top = t.levels.front();
    fuzz::check(top.width >= 1 && top.height >= 1 && top.width <= int(gpu::kMaxImageSide) &&
                top.height <= int(gpu::kMaxImageSide) && size_t(top.width) * size_t(top.height) <= kMaxTextureTexels);
    for (size_t i = 0; i < t.levels.size(); ++i) {
        const TextureLevel& l = t.levels[i];
        if (i > 0) {
            fuzz::check(l.width == std::max(1, t.levels[i - 1].width / 2));
            fuzz::check(l.height == std::max(1, t.levels[i - 1].height / 2));
        }
        fuzz::check(l.rgba.size() == size_t(l.width) * size_t(l.height) * 4);
        for (uint16_t h : l.rgba) fuzz::check(std::isfinite(glm::unpackHalf1x16(h)));
    }
    fuzz::check(t.levels.back().width == 1 && t.levels.back().height == 1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    constexpr std::array<std::string_view, 7> kFileFormats = {"png", "jpg", "exr", "hdr", "tga", "bmp", "tif"};
    constexpr std::array<std::string_view, 3> kMemoryHints = {"png", "jpg", ""};
    const uint8_t how = data[0];
    const std::span<const unsigned char> bytes(data + 1, size - 1);
    const TextureEncoding encoding = (how & 0x80) ? TextureEncoding::Data : TextureEncoding::Colour;
    try {
        if (how & 0x40) {
            const std::string hint(kMemoryHints[(how & 0x3F) % kMemoryHints.size()]);
            checkTexture(readTextureMemory(bytes, hint, encoding, "embedded"));
        } else {
            const std::string ext(kFileFormats[(how & 0x3F) % kFileFormats.size()]);
            const std::filesystem::path file = fuzz::writeScratch(
                "fuzz." + ext, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
            checkTexture(readTextureFile(file, encoding));
        }
    } catch (const TextureFileError& e) {
        fuzz::check(std::string_view(e.what()).size() > 0);
    }
    return 0;
}

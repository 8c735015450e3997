// Wavefront MTL material libraries, read by whitted itself: Assimp keeps
// only illum 0-2, and the illumination models 3-9 are Whitted's own
// (mirrors and ray-traced glass). Keys read: Ka Kd Ks Ke Ns Ni d Tr Tf
// illum map_Kd bump map_bump norm (with -bm for bump); others are skipped.
// Texture paths may use `\` or `/` and contain spaces; they are relative
// to the .mtl file. This reader knows no scene (scene/authored_scene maps
// the values; scenes/README.md "OBJ/MTL" gives the table).
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace whitted {

struct TextureData;  // io/texture.h

// A library that cannot be used: what() is "FILE:LINE: reason".
// file, line (0: the file as a whole) and reason are also kept apart, so a
// caller that words errors its own way need not parse what().
class MtlFileError : public std::runtime_error {
public:
    MtlFileError(std::string file, int line, std::string reason)
        : std::runtime_error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + reason),
          file(std::move(file)), line(line), reason(std::move(reason)) {}
    std::string file;
    int line = 0;
    std::string reason;
};

struct MtlMaterial {
    std::string name;
    int line = 0;  // of its newmtl
    std::optional<glm::dvec3> Ka, Kd, Ks, Ke, Tf;
    std::optional<double> Ns, Ni, d;  // d: dissolve (Tr is read as 1 - Tr)
    int illum = -1;  // -1: not given
    int illumLine = 0;
    std::shared_ptr<const TextureData> diffuseTexture;  // map_Kd, sRGB decoded
    // norm (a tangent-space normal map), or bump/map_bump (a height map)
    // turned into one: n = normalize(-bm dh/dx, -bm dh/dy, 1), the height's
    // differences between neighbouring texels (x right, y up the image).
    std::shared_ptr<const TextureData> normalMap;
    // The files they were read from (normalMapFile: only for norm; a bump's
    // normal map is made here), for a scene file that names them again.
    std::filesystem::path diffuseTextureFile, normalMapFile;
};

struct MtlFile {
    std::vector<MtlMaterial> materials;
    std::vector<std::string> warnings;  // "FILE:LINE: ..."
};

// Reads `path`; a texture that does not exist or cannot be read throws
// MtlFileError at its line, as does a malformed value.
MtlFile readMtlFile(const std::filesystem::path& path);

// A path as an MTL or OBJ file writes it: `\` taken for `/`.
std::filesystem::path mtlPath(const std::filesystem::path& folder, std::string written);

// The height map `heights` (its first channel) as a tangent-space normal
// map of the same size, strength `bm` (see MtlMaterial::normalMap).
std::shared_ptr<const TextureData> normalMapFromHeights(const TextureData& heights, double bm);

}  // namespace whitted

// Triangle meshes from model files (OBJ, PLY, STL, glTF, ... : every format
// Assimp reads). Assimp is used rather than one loader per format: one
// library covers OBJ, PLY, STL, glTF and more, it is packaged by Debian
// (libassimp-dev), and it keeps the per-vertex normals a file carries.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <glm/glm.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace whitted {

// A model file that can not be used. what() is the reason as the end of a
// sentence about the file ("does not exist", "has no triangles"); the scene
// loader names the file and places it at its <file> element.
class MeshFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The triangles of a model file in the file's own coordinates, every mesh of
// the file joined with its node transforms applied. normals is either empty
// (the file has none: flat shading) or holds three unit vertex normals per
// triangle; a triangle of a file that gives normals for only some of its
// meshes, or a zero or non-finite one, gets its geometric normal (flat).
// uvs is empty when no mesh of the file has texture coordinates, else it
// holds each triangle's first UV channel (Assimp's convention: v up, (0, 0)
// at the image's bottom-left corner, glTF's flipped to it); a triangle of a
// mesh without them gets (0, 0).
struct TextureData;

// A material of the file, as far as whitted uses it: the base colour
// (glTF baseColorFactor, OBJ/MTL Kd; white without one) and the base-colour
// texture (glTF baseColorTexture, OBJ/MTL map_Kd; a file beside the model
// or embedded in it), which multiplies it; and the normal texture.
struct MeshFileMaterial {
    glm::dvec3 baseColour{1, 1, 1};
    std::shared_ptr<const TextureData> baseColourTexture;
    std::shared_ptr<const TextureData> normalTexture;  // glTF normalTexture, MTL norm/bump: linear data
};

struct MeshFileData {
    std::vector<std::array<glm::dvec3, 3>> triangles;
    std::vector<std::array<glm::dvec3, 3>> normals;
    std::vector<std::array<glm::dvec2, 3>> uvs;
    // With MeshFileMaterials::Read: the file's materials and each triangle's
    // index into them.
    std::vector<MeshFileMaterial> materials;
    std::vector<uint32_t> triangleMaterials;
    // With MeshFileMaterials::Names or Read: each material's name (empty
    // for the one Assimp makes up for triangles without a material).
    std::vector<std::string> materialNames;
    // With tangents asked for: each triangle's unit vertex tangents
    // (Assimp's aiProcess_CalcTangentSpace, along +u), or empty when the
    // file has no normals and UVs to compute them from; a triangle whose
    // tangents are unusable has zero vectors.
    std::vector<std::array<glm::dvec3, 3>> tangents;
};

// Names: only each material's name (materialNames) and the triangles'
// indices, no colours or textures: for a file whose materials are read by
// whitted itself (OBJ/MTL, io/mtl_file.h).
enum class MeshFileMaterials { Ignore, Read, Names };

// Reads every triangle of `path`; points and lines are dropped, polygons are
// triangulated. Throws MeshFileError when the file does not exist, has an
// extension Assimp does not know, does not parse (Assimp's message is
// included), has no triangles, or has a vertex that is not finite or beyond
// ±1e6 (the scene format's limit).
// With MeshFileMaterials::Read it also reads the materials and their
// textures; a texture that cannot be read throws MeshFileError naming it.
MeshFileData readMeshFile(const std::filesystem::path& path, MeshFileMaterials materials = MeshFileMaterials::Ignore,
                          bool withTangents = false);

}  // namespace whitted

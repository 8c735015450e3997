// Triangle meshes from model files (OBJ, PLY, STL, glTF, ... : every format
// Assimp reads). Assimp is used rather than one loader per format: one
// library covers OBJ, PLY, STL, glTF and more, it is packaged by Debian
// (libassimp-dev), and it keeps the per-vertex normals a file carries.
#pragma once

#include <array>
#include <filesystem>
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
struct MeshFileData {
    std::vector<std::array<glm::dvec3, 3>> triangles;
    std::vector<std::array<glm::dvec3, 3>> normals;
    std::vector<std::array<glm::dvec2, 3>> uvs;
};

// Reads every triangle of `path`; points and lines are dropped, polygons are
// triangulated. Throws MeshFileError when the file does not exist, has an
// extension Assimp does not know, does not parse (Assimp's message is
// included), has no triangles, or has a vertex that is not finite or beyond
// ±1e6 (the scene format's limit).
MeshFileData readMeshFile(const std::filesystem::path& path);

}  // namespace whitted

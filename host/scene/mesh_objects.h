// The mesh part of the scene loader: an <object> of type mesh, from inline
// <polygons> or a model <file> (io/mesh_file.h), placed by its <position>,
// <scale> and <rotation>; a model file whose own materials apply split
// into one object per material (scenes/README.md "Model files"). Also the triangle
// reading and the degenerate-triangle test the triangle type shares.
#pragma once

#include "io/mesh_file.h"
#include "scene/scene.h"
#include "scene/xml_reader.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace whitted {

// Zero area relative to its size: |cross(e1, e2)| at most 1e-12 times its
// longest squared edge.
bool degenerate(const Triangle& t);

// A count with its thousands grouped by commas: 2345 -> "2,345".
std::string withThousands(uint64_t n);

// What a warning about dropped triangles says: "1 degenerate triangle
// skipped", "2,345 degenerate triangles skipped".
std::string skippedTriangles(uint64_t count);

// The three <vertex> elements of `parent`, each moved by `offset`; another
// count is refused.
Triangle readTriangle(const xml::Diagnostics& diag, const xml::XMLElement* parent,
                      const std::vector<const xml::XMLElement*>& vertices, const glm::dvec3& offset);

// A model file's own materials while its object is read: `wanted` (set by
// the caller) when the object gives no colour of its own; the reader then
// fills `materials` and, for each triangle it keeps, its index into them.
// An OBJ file with MTL libraries gives whole materials instead (`authored`,
// one per material of the file, mapped as the OBJ/MTL scene maps them), and
// `names`, its materials' names.
struct FileMaterials {
    bool wanted = false;
    std::vector<MeshFileMaterial> materials;
    std::vector<uint32_t> triangleMaterials;
    std::vector<Material> authored;
    std::vector<std::string> names;
};

struct GltfFile;  // io/gltf_file.h

// The model files one scene has read, so that the <file part="..."> objects
// of one file (a converted glTF or OBJ: one object per part) read it once.
struct ModelFiles {
    std::map<std::filesystem::path, std::shared_ptr<const GltfFile>> gltf;
    std::map<std::tuple<std::filesystem::path, MeshFileMaterials, bool>, std::shared_ptr<const MeshFileData>> meshes;
};

// The mesh of an <object> (whose readers `object` and `properties` are):
// <polygons> or a <file>, its path relative to `sceneFolder`. Degenerate
// polygons and triangles are dropped with a warning.
Mesh readMeshObject(const xml::Diagnostics& diag, xml::ElementReader& object, xml::ElementReader& properties,
                    const glm::dvec3& position, const std::filesystem::path& sceneFolder,
                    FileMaterials& fileMaterials, ModelFiles& modelFiles);

// An <instance>'s placement (scenes/README.md "Instances"), from the
// children of `instance`: <position>, then <matrix>, or <scale> and
// <rotation>, as a mesh object's (a singular <matrix> refused).
glm::dmat4 readInstanceTransform(const xml::Diagnostics& diag, xml::ElementReader& instance);

// A model file's triangles grouped by their material, each group an
// object with the scene's material but the file's base colour and
// texture (the texture where the file has texture coordinates).
std::vector<Object> splitByFileMaterial(Object whole, const FileMaterials& fileMaterials);

}  // namespace whitted

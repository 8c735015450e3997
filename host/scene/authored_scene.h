// Model files as their authors set them up (scenes/README.md "Authored
// scenes"): a glTF 2.0 file's node tree, cameras, KHR_lights_punctual
// lights and materials, and an OBJ file's own MTL materials, mapped into
// the scene model by the formulas documented there. What is not authored
// (a camera, lights and a floor) is scene/quick_look's to add.
#pragma once

#include "scene/scene.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace whitted {

struct GltfMaterial;  // io/gltf_file.h
struct GltfLight;
struct GltfPrimitive;
struct MtlMaterial;   // io/mtl_file.h

// A camera of the file, placed by its node: cameras in node order
// (depth first from the scene's roots), named by the camera's name, else
// its node's.
struct AuthoredCamera {
    std::string name;
    std::string nodeName;
    Camera camera;
};

struct AuthoredScene {
    Scene scene;  // the file's objects and lights; ambient light 0 for glTF
    std::vector<AuthoredCamera> cameras;
};

// .gltf or .glb (any case).
bool isGltfFile(const std::filesystem::path& path);

// The MTL libraries an OBJ file names (mtllib), beside it; empty for any
// other file or an OBJ without one.
std::vector<std::filesystem::path> objMaterialLibraries(const std::filesystem::path& path);

// Both throw SceneError: for glTF "FILE: JSON-PATH: reason", for MTL
// "FILE:LINE: reason".
AuthoredScene loadGltfScene(const std::filesystem::path& path);
AuthoredScene loadObjMtlScene(const std::filesystem::path& path);

// The materials of an OBJ file's MTL libraries (mtllib), mapped, by name;
// `normalMaps`: whether any has one. A library that does not exist is a
// warning; one that cannot be read throws SceneError (FILE.mtl:LINE). The
// OBJ/MTL scene and a scene file's <file> of such an OBJ both use it.
std::map<std::string, Material> objMtlMaterials(const std::filesystem::path& path, std::vector<std::string>& warnings,
                                                bool& normalMaps);

// The mappings themselves (scenes/README.md gives the formulas).
Material materialFromGltf(const GltfMaterial& material);
Material materialFromMtl(const MtlMaterial& material, const std::string& file, std::vector<std::string>& warnings);
// `world` places the light: its position the origin's image, its
// direction that of -Z.
Light lightFromGltf(const GltfLight& light, const glm::dmat4& world);

// A primitive's triangles placed by `world` (its winding turned over where
// the determinant is negative), its normals by world's inverse transpose;
// texture coordinates (v flipped to whitted's up) only when `textured`,
// tangents only when also `normalMapped`. The glTF scene and a <file
// part="mesh M primitive P"> both build their meshes with it, so that a
// converted scene renders bit for bit as the file. Triangles degenerate
// once placed are dropped and counted in `degenerateSkipped`.
Mesh meshFromGltfPrimitive(const GltfPrimitive& primitive, const glm::dmat4& world, bool textured, bool normalMapped,
                           size_t& degenerateSkipped);
// "mesh M primitive P", the part attribute naming one primitive.
std::string gltfPartName(size_t mesh, size_t primitive);

// --camera INDEX|NAME: INDEX counts the cameras in node order from 0, NAME
// is a camera's or its node's name. Throws SceneError(file, 0, ...) when
// no camera answers.
const AuthoredCamera& chooseCamera(const std::vector<AuthoredCamera>& cameras, const std::string& choice,
                                   const std::string& file);

}  // namespace whitted

// glTF 2.0 files (.gltf with external or base64 buffers, and .glb) read as
// authored: the node tree with each node's local transform, meshes and
// their primitives as triangle lists, cameras, KHR_lights_punctual lights
// and the materials with the extensions whitted maps (scenes/README.md
// "glTF scenes"). This reader knows no scene: scene/authored_scene maps
// what it reads into one.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace whitted {

struct TextureData;  // io/texture.h

// A file that cannot be used. what() is "FILE: JSON-PATH: reason"
// ("scene.gltf: /materials/0/pbrMetallicRoughness/metallicFactor: must be
// a number in [0, 1]").
class GltfFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct GltfMaterial {
    std::string name;
    glm::dvec4 baseColorFactor{1, 1, 1, 1};
    std::shared_ptr<const TextureData> baseColorTexture;  // sRGB decoded to linear
    double metallicFactor = 1.0;
    double roughnessFactor = 1.0;
    // pbrMetallicRoughness.metallicRoughnessTexture: linear data, roughness in green (metalness in blue, unused)
    std::shared_ptr<const TextureData> metallicRoughnessTexture;
    std::shared_ptr<const TextureData> normalTexture;  // linear data
    double normalScale = 1.0;
    glm::dvec3 emissiveFactor{0, 0, 0};
    double emissiveStrength = 1.0;     // KHR_materials_emissive_strength
    std::shared_ptr<const TextureData> emissiveTexture;  // sRGB decoded to linear
    double transmissionFactor = 0.0;   // KHR_materials_transmission
    double ior = 1.5;                  // KHR_materials_ior
    bool hasVolume = false;            // KHR_materials_volume:
    double thicknessFactor = 0.0;
    glm::dvec3 attenuationColor{1, 1, 1};
    double attenuationDistance = std::numeric_limits<double>::infinity();
};

// One primitive as triangles (strips and fans unrolled, points and lines
// dropped): three indices per triangle into the vertex arrays. normals,
// uvs and tangents are empty or one per position; uvs as the file has them
// (glTF's v down, (0, 0) the image's top-left corner).
struct GltfPrimitive {
    std::vector<glm::dvec3> positions;
    std::vector<glm::dvec3> normals;
    std::vector<glm::dvec2> uvs;
    std::vector<glm::dvec4> tangents;  // xyz, w the bitangent's sign
    std::vector<uint32_t> indices;
    int material = -1;  // index into materials; -1: none given
};

struct GltfMesh {
    std::string name;
    std::vector<GltfPrimitive> primitives;
};

struct GltfCamera {
    std::string name;
    bool orthographic = false;
    double yfov = 0;          // perspective: vertical field of view, radians
    double aspectRatio = 0;   // perspective: 0 when the file gives none
    double xmag = 0, ymag = 0;  // orthographic: half the view's width and height
};

struct GltfLight {
    enum class Type { Point, Spot, Directional };
    std::string name;
    Type type = Type::Point;
    glm::dvec3 color{1, 1, 1};
    double intensity = 1.0;  // candela (point, spot) or lux (directional)
    double range = 0;        // 0: infinite (not used by whitted)
    double innerConeAngle = 0;                 // radians
    double outerConeAngle = 0.78539816339744830962;  // pi / 4
};

struct GltfNode {
    std::string name;
    glm::dmat4 local{1.0};  // matrix, or T * R * S
    int mesh = -1, camera = -1, light = -1;
    std::vector<int> children;
};

struct GltfFile {
    std::vector<GltfNode> nodes;
    std::vector<int> sceneRoots;  // the nodes of the file's scene ("scene", else the first), each once
    std::vector<GltfMesh> meshes;
    std::vector<GltfCamera> cameras;
    std::vector<GltfLight> lights;
    std::vector<GltfMaterial> materials;
    std::vector<std::string> warnings;  // "FILE: JSON-PATH: ..." for what is read but not used
};

// What a glTF file may hold (scenes/README.md "Limits"), each checked before
// the work or memory it bounds: the JSON text (a .gltf file's size, a .glb's
// JSON chunk) before it is parsed, the node count and the node tree's depth
// before the tree is walked. Walks of the tree are iterative, never
// recursive, so depth costs no stack.
inline constexpr size_t kMaxGltfJsonBytes = size_t(64) << 20;
inline constexpr size_t kMaxGltfNodes = size_t(1) << 20;
inline constexpr size_t kMaxGltfNodeDepth = 1024;
// An accessor without a bufferView is all zeros (of use only to sparse
// accessors, which whitted does not read): its count is bounded so that a
// tiny file cannot ask for gigabytes of zeros.
inline constexpr size_t kMaxGltfZeroAccessorCount = size_t(1) << 16;

// Reads a .gltf or .glb file. Throws GltfFileError.
GltfFile readGltfFile(const std::filesystem::path& path);

}  // namespace whitted

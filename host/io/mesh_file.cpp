#include "io/mesh_file.h"

#include "io/srgb.h"
#include "io/texture_file.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <span>
#include <system_error>

namespace whitted {
namespace {

// The scene format's limit on any coordinate (scenes/README.md "Scene files").
constexpr double kMaxMeshMagnitude = 1e6;

bool finiteWithin(const glm::dvec3& v, double limit) {
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(v[i]) <= limit)) return false;  // also false for NaN
    return true;
}

// A usable vertex normal, or none (zero length or not finite).
bool unitNormal(const aiVector3D& n, glm::dvec3& out) {
    glm::dvec3 v(n.x, n.y, n.z);
    double length = glm::length(v);
    if (!std::isfinite(length) || !(length > 1e-12)) return false;
    out = v / length;
    return true;
}

// The first texture of a material of one of `types`: embedded in the file
// ("*N", or the name of an embedded texture) or a file relative to the
// model's folder.
std::shared_ptr<const TextureData> materialTexture(const aiScene& scene, const aiMaterial& material,
                                                   std::initializer_list<aiTextureType> types, TextureEncoding encoding,
                                                   const std::filesystem::path& modelPath) {
    aiString name;
    bool found = false;
    for (aiTextureType type : types)
        if (!found && material.GetTexture(type, 0, &name) == AI_SUCCESS) found = true;
    if (!found) return nullptr;
    std::string written = name.C_Str();
    try {
        if (const aiTexture* embedded = scene.GetEmbeddedTexture(name.C_Str())) {
            std::string label = modelPath.filename().string() + " embedded texture " + written;
            if (embedded->mHeight == 0) {  // compressed: mWidth bytes of a PNG, JPEG, ... file
                auto bytes = std::span(reinterpret_cast<const unsigned char*>(embedded->pcData), embedded->mWidth);
                return std::make_shared<const TextureData>(
                    readTextureMemory(bytes, embedded->achFormatHint, encoding, label));
            }
            // Raw 8-bit BGRA texels (sRGB, as a PNG's), rows from the top.
            size_t count = size_t(embedded->mWidth) * embedded->mHeight;
            std::vector<float> rgba(count * 4);
            auto decode = [&](unsigned char c) {
                float v = float(c) / 255.0f;
                return encoding == TextureEncoding::Data ? v : srgbToLinear(v);
            };
            for (size_t i = 0; i < count; ++i) {
                const aiTexel& t = embedded->pcData[i];
                rgba[i * 4 + 0] = decode(t.r);
                rgba[i * 4 + 1] = decode(t.g);
                rgba[i * 4 + 2] = decode(t.b);
                rgba[i * 4 + 3] = float(t.a) / 255.0f;
            }
            return std::make_shared<const TextureData>(
                textureFromPixels(int(embedded->mWidth), int(embedded->mHeight), rgba, label));
        }
        std::filesystem::path file(written);
        if (file.is_relative()) file = modelPath.parent_path() / file;
        return std::make_shared<const TextureData>(readTextureFile(file, encoding));
    } catch (const TextureFileError& error) {
        throw MeshFileError("has a texture \"" + written + "\" that " + error.what());
    }
}

}  // namespace

MeshFileData readMeshFile(const std::filesystem::path& path, MeshFileMaterials withMaterials, bool withTangents) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw MeshFileError("does not exist");
    if (std::filesystem::is_directory(path, ec)) throw MeshFileError("is a directory, expected a model file");

    // Assimp guesses a format from the contents when the extension is
    // unknown; refuse instead, so a mistyped name is never read as something.
    Assimp::Importer importer;
    std::string extension = path.extension().string();
    if (extension.empty() || !importer.IsExtensionSupported(extension))
        throw MeshFileError("has " + (extension.empty() ? "no extension" : "unknown extension \"" + extension + "\"") +
                            "; expected a model format Assimp reads, such as .obj, .ply, .stl, .off, .gltf or .glb");

    // Triangulate polygons, bake the node hierarchy into the vertices and
    // check the result (Assimp's validation step); points and lines are
    // skipped below. Normals are not generated: a file without them is
    // shaded flat.
    // Tangents (for normal maps) only when asked: they cost load time.
    const unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure |
                           (withTangents ? aiProcess_CalcTangentSpace : 0u);
    const aiScene* scene = importer.ReadFile(path.string(), flags);
    if (!scene) {
        std::string reason = importer.GetErrorString();
        throw MeshFileError("could not be read: " + (reason.empty() ? std::string("Assimp gave no reason") : reason));
    }

    MeshFileData data;
    if (withMaterials != MeshFileMaterials::Ignore)
        for (unsigned m = 0; m < scene->mNumMaterials; ++m) {
            const aiString name = scene->mMaterials[m]->GetName();
            data.materialNames.push_back(name == aiString(AI_DEFAULT_MATERIAL_NAME) ? "" : name.C_Str());
            if (withMaterials == MeshFileMaterials::Names) data.materials.emplace_back();
        }
    if (withMaterials == MeshFileMaterials::Read)
        for (unsigned m = 0; m < scene->mNumMaterials; ++m) {
            const aiMaterial& material = *scene->mMaterials[m];
            MeshFileMaterial read;
            // The material Assimp makes up for a file without any (OBJ
            // without MTL, PLY, STL: diffuse 0.6 grey) stays white.
            if (material.GetName() == aiString(AI_DEFAULT_MATERIAL_NAME)) {
                data.materials.push_back(read);
                continue;
            }
            aiColor4D colour;
            if (material.Get(AI_MATKEY_BASE_COLOR, colour) == AI_SUCCESS ||
                material.Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS)
                if (std::isfinite(colour.r) && std::isfinite(colour.g) && std::isfinite(colour.b))
                    read.baseColour = glm::clamp(glm::dvec3(colour.r, colour.g, colour.b), 0.0, 1.0);
            read.baseColourTexture = materialTexture(
                *scene, material, {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}, TextureEncoding::Colour, path);
            read.normalTexture =
                materialTexture(*scene, material, {aiTextureType_NORMALS}, TextureEncoding::Data, path);
            data.materials.push_back(std::move(read));
        }
    bool anyNormals = false, anyUvs = false, anyTangents = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        if (withTangents && scene->mMeshes[m]->HasTangentsAndBitangents()) anyTangents = true;
        if (scene->mMeshes[m]->HasNormals()) anyNormals = true;
        if (scene->mMeshes[m]->HasTextureCoords(0)) anyUvs = true;
    }
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue;
            std::array<glm::dvec3, 3> triangle;
            for (int k = 0; k < 3; ++k) {
                const aiVector3D& v = mesh->mVertices[face.mIndices[k]];
                triangle[k] = glm::dvec3(v.x, v.y, v.z);
                if (!finiteWithin(triangle[k], kMaxMeshMagnitude)) {
                    std::array<char, 96> text{};
                    std::snprintf(text.data(), text.size(), "(%g, %g, %g)", v.x, v.y, v.z);
                    throw MeshFileError("has a vertex beyond ±1e6 or not finite: " + std::string(text.data()));
                }
            }
            data.triangles.push_back(triangle);
            if (!data.materials.empty())
                data.triangleMaterials.push_back(std::min(mesh->mMaterialIndex, scene->mNumMaterials - 1));
            if (anyUvs) {
                std::array<glm::dvec2, 3> uv{};
                if (mesh->HasTextureCoords(0))
                    for (int k = 0; k < 3; ++k) {
                        const aiVector3D& t = mesh->mTextureCoords[0][face.mIndices[k]];
                        uv[k] = std::isfinite(t.x) && std::isfinite(t.y) ? glm::dvec2(t.x, t.y) : glm::dvec2(0.0);
                    }
                data.uvs.push_back(uv);
            }
            if (anyTangents) {
                std::array<glm::dvec3, 3> tangent{};
                bool usable = mesh->HasTangentsAndBitangents();
                for (int k = 0; k < 3 && usable; ++k)
                    usable = unitNormal(mesh->mTangents[face.mIndices[k]], tangent[k]);
                data.tangents.push_back(usable ? tangent : std::array<glm::dvec3, 3>{});
            }
            if (!anyNormals) continue;
            // The geometric normal stands in for missing or unusable ones.
            glm::dvec3 cross = glm::cross(triangle[1] - triangle[0], triangle[2] - triangle[0]);
            glm::dvec3 flat = glm::length(cross) > 0 ? glm::normalize(cross) : glm::dvec3(0, 0, 1);
            std::array<glm::dvec3, 3> normals{flat, flat, flat};
            if (mesh->HasNormals()) {
                std::array<glm::dvec3, 3> given;
                bool usable = true;
                for (int k = 0; k < 3; ++k) usable = usable && unitNormal(mesh->mNormals[face.mIndices[k]], given[k]);
                if (usable) normals = given;
            }
            data.normals.push_back(normals);
        }
    }
    if (data.triangles.empty()) throw MeshFileError("has no triangles");
    return data;
}

}  // namespace whitted

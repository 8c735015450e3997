#include "io/mesh_file.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdio>
#include <system_error>

namespace whitted {
namespace {

// The scene format's limit on any coordinate (README "Scene files").
constexpr double kMaxMagnitude = 1e6;

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

}  // namespace

MeshFileData readMeshFile(const std::filesystem::path& path) {
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
    const unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure;
    const aiScene* scene = importer.ReadFile(path.string(), flags);
    if (!scene) {
        std::string reason = importer.GetErrorString();
        throw MeshFileError("could not be read: " + (reason.empty() ? std::string("Assimp gave no reason") : reason));
    }

    MeshFileData data;
    bool anyNormals = false, anyUvs = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
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
                if (!finiteWithin(triangle[k], kMaxMagnitude)) {
                    std::array<char, 96> text{};
                    std::snprintf(text.data(), text.size(), "(%g, %g, %g)", v.x, v.y, v.z);
                    throw MeshFileError("has a vertex beyond ±1e6 or not finite: " + std::string(text.data()));
                }
            }
            data.triangles.push_back(triangle);
            if (anyUvs) {
                std::array<glm::dvec2, 3> uv{};
                if (mesh->HasTextureCoords(0))
                    for (int k = 0; k < 3; ++k) {
                        const aiVector3D& t = mesh->mTextureCoords[0][face.mIndices[k]];
                        uv[k] = std::isfinite(t.x) && std::isfinite(t.y) ? glm::dvec2(t.x, t.y) : glm::dvec2(0.0);
                    }
                data.uvs.push_back(uv);
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

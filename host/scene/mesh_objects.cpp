#include "scene/mesh_objects.h"

#include "io/gltf_file.h"
#include "scene/authored_scene.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

namespace whitted {

using namespace xml;

namespace {

// A triangle is degenerate when |cross(e1, e2)| <= this times its longest
// squared edge (zero area relative to its size).
constexpr double kDegenerateTolerance = 1e-12;

// Where a mesh's vertices go: world = position + R (S v), S the <scale>
// (per axis), R = Rz Ry Rx the <rotation> in degrees: about x first, then
// y, then z, each about the fixed world axes. Normals go through the
// inverse transpose, R S^-1 (Phong normal transform).
// A <matrix> M instead: world = position + M·(v, 1), normals through the
// inverse transpose of M's linear part, the winding turned over where its
// determinant is negative.
struct Placement {
    glm::dvec3 offset{0};
    glm::dmat3 linear{1.0};
    glm::dmat3 normalLinear{1.0};
    bool identity = true;  // no <scale>, <rotation> or <matrix>: vertices are only offset
    bool flip = false;     // a mirroring <matrix>
    glm::dvec3 position{0};                   // the object's <position>
    glm::dvec3 scale{1}, rotationDegrees{0};  // as written
    std::optional<glm::dmat4> matrix;         // as written

    // Within ±1e6 of the position on every axis, as inline vertices
    // are; false when <scale> or <rotation> take a vertex further.
    bool inRange(const glm::dvec3& v) const {
        if (identity) return true;
        return withinMagnitude(linear * v);
    }
    // An unmoved vertex is kept as it is (adding zero would turn -0 into 0).
    glm::dvec3 point(const glm::dvec3& v) const {
        return identity ? (offset == glm::dvec3(0) ? v : offset + v) : offset + linear * v;
    }
    glm::dvec3 normal(const glm::dvec3& n) const { return identity ? n : glm::normalize(normalLinear * n); }
};

glm::dmat3 rotationXyz(const glm::dvec3& degrees) {
    glm::dvec3 r = glm::radians(degrees);
    double cx = std::cos(r.x), sx = std::sin(r.x), cy = std::cos(r.y), sy = std::sin(r.y);
    double cz = std::cos(r.z), sz = std::sin(r.z);
    // glm matrices are column-major: each line below is one column.
    glm::dmat3 rx(1, 0, 0, 0, cx, sx, 0, -sx, cx);
    glm::dmat3 ry(cy, 0, -sy, 0, 1, 0, sy, 0, cy);
    glm::dmat3 rz(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
    return rz * ry * rx;
}

// <matrix>: three rows of four numbers (the affine transform's rows), or
// four with the last 0 0 0 1; finite, within ±1e6, the 3×3 part invertible.
glm::dmat4 readMatrix(const Diagnostics& diag, const XMLElement* e) {
    std::string text = valueText(diag, e);
    std::vector<double> values;
    const char* at = text.data();
    const char* end = text.data() + text.size();
    while (at < end) {
        if (std::isspace((unsigned char)*at)) {
            ++at;
            continue;
        }
        const char* start = at + (*at == '+' ? 1 : 0);
        double v = 0;
        auto [next, ec] = std::from_chars(start, end, v);
        if (ec != std::errc() || (next < end && !std::isspace((unsigned char)*next)))
            diag.fail(e, "<matrix> holds numbers separated by spaces, got \"" +
                             std::string(at, std::find_if(at, end, [](char c) { return std::isspace((unsigned char)c); })) +
                             "\"");
        if (!(std::abs(v) <= kMaxMagnitude)) diag.fail(e, "<matrix> has a number beyond ±1e6 or not finite");
        values.push_back(v);
        at = next;
    }
    if (values.size() != 12 && values.size() != 16)
        diag.fail(e, "<matrix> has " + std::to_string(values.size()) +
                         " numbers; expected 12 (three rows of four) or 16 (the fourth row 0 0 0 1)");
    if (values.size() == 16 && (values[12] != 0 || values[13] != 0 || values[14] != 0 || values[15] != 1))
        diag.fail(e, "<matrix>'s fourth row must be 0 0 0 1 (an affine transform)");
    glm::dmat4 m(1.0);
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) m[col][row] = values[size_t(row * 4 + col)];
    double det = glm::determinant(glm::dmat3(m));
    if (!(std::abs(det) > 1e-300)) diag.fail(e, "<matrix> is singular: its 3×3 part has determinant 0");
    return m;
}

// <scale> is one number for all axes, or a vector (x, y, z); each > 0.
Placement readPlacement(const Diagnostics& diag, ElementReader& properties, const glm::dvec3& position) {
    Placement placement;
    placement.offset = position;
    placement.position = position;
    if (const XMLElement* e = properties.optional("matrix")) {
        for (const char* other : {"scale", "rotation"})
            if (const XMLElement* o = properties.optional(other))
                diag.fail(laterOf(e, o), tag(properties.element()->Name()) + " has both <matrix> and " + tag(other) +
                                             (properties.element()->Name() == std::string_view("instance")
                                                  ? "; an instance takes one"
                                                  : "; a mesh takes one"));
        glm::dmat4 m = readMatrix(diag, e);
        placement.matrix = m;
        placement.identity = false;
        placement.linear = glm::dmat3(m);
        placement.normalLinear = glm::transpose(glm::inverse(placement.linear));
        placement.flip = glm::determinant(placement.linear) < 0;
        placement.offset = position + glm::dvec3(m[3]);
        return placement;
    }
    glm::dvec3 scale(1.0), rotation(0.0);
    if (const XMLElement* e = properties.optional("scale")) {
        scale = e->FirstAttribute() || e->FirstChildElement() ? vector(diag, e, kPositive)
                                                              : glm::dvec3(number(diag, e, kPositive));
        placement.identity = false;
    }
    if (const XMLElement* e = properties.optional("rotation")) {
        rotation = vector(diag, e);
        placement.identity = false;
    }
    placement.scale = scale;
    placement.rotationDegrees = rotation;
    glm::dmat3 r = rotationXyz(rotation);
    placement.linear = r * glm::dmat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
    placement.normalLinear = r * glm::dmat3(1 / scale.x, 0, 0, 0, 1 / scale.y, 0, 0, 0, 1 / scale.z);
    return placement;
}

}  // namespace

glm::dmat4 readInstanceTransform(const Diagnostics& diag, ElementReader& instance) {
    const XMLElement* position = instance.optional("position");
    Placement placement = readPlacement(diag, instance, position ? vector(diag, position) : glm::dvec3(0));
    glm::dmat4 m(placement.linear);
    m[3] = glm::dvec4(placement.offset, 1.0);
    return m;
}

namespace {

std::string outOfRange(const glm::dvec3& v) {
    std::array<char, 96> text{};
    std::snprintf(text.data(), text.size(), "(%g, %g, %g)", v.x, v.y, v.z);
    return std::string("<scale> and <rotation> take vertex ") + text.data() +
           " beyond ±1e6 of the object's <position>";
}

// Degenerate polygons are dropped with a warning; a mesh needs at least
// one that is not.
Mesh readMesh(const Diagnostics& diag, const XMLElement* e, const Placement& placement) {
    ElementReader polygons(diag, e, {{"polygon", true}});
    if (polygons.all("polygon").empty()) diag.fail(e, "<polygons> has no <polygon>; a mesh needs at least one");
    Mesh mesh;
    std::optional<bool> withUv, withNormals;  // from the first polygon
    for (const XMLElement* polygon : polygons.all("polygon")) {
        ElementReader vertices(diag, polygon, {{"vertex", true}, {"uv", true}, {"normal", true}});
        Triangle local = readTriangle(diag, polygon, vertices.all("vertex"), glm::dvec3(0));
        // Texture coordinates: one <uv u=".." v=".."/> per vertex, in
        // the vertices' order, on every polygon or on none.
        const std::vector<const XMLElement*>& uvs = vertices.all("uv");
        if (!uvs.empty() && uvs.size() != 3)
            diag.fail(polygon, "<polygon> has " + std::to_string(uvs.size()) + " <uv>, expected 3 (one per <vertex>)");
        if (withUv && *withUv == uvs.empty())
            diag.fail(polygon, uvs.empty() ? "<polygon> has no <uv>, but the first <polygon> has"
                                           : "<polygon> has <uv>, but the first <polygon> has none");
        withUv = !uvs.empty();
        std::array<glm::dvec2, 3> uv{};
        for (size_t k = 0; k < uvs.size(); ++k) {
            auto c = components(diag, uvs[k], {{"u", kAnyValue}, {"v", kAnyValue}});
            uv[k] = {c[0], c[1]};
        }
        // Vertex normals (smooth shading): one <normal x y z/> per vertex,
        // in the vertices' order, on every polygon or on none; what a model
        // file's mesh carries, so that a converted one shades the same.
        const std::vector<const XMLElement*>& normals = vertices.all("normal");
        if (!normals.empty() && normals.size() != 3)
            diag.fail(polygon,
                      "<polygon> has " + std::to_string(normals.size()) + " <normal>, expected 3 (one per <vertex>)");
        if (withNormals && *withNormals == normals.empty())
            diag.fail(polygon, normals.empty() ? "<polygon> has no <normal>, but the first <polygon> has"
                                               : "<polygon> has <normal>, but the first <polygon> has none");
        withNormals = !normals.empty();
        std::array<glm::dvec3, 3> normal{};
        for (size_t k = 0; k < normals.size(); ++k) {
            // A unit normal is used as written (normalising it again could
            // move its last bit); any other is normalised.
            glm::dvec3 n = vector(diag, normals[k]);
            if (std::abs(glm::length(n) - 1.0) > 1e-9) n = direction(diag, normals[k]);
            normal[k] = placement.normal(n);
        }
        for (const glm::dvec3& v : {local.v0, local.v1, local.v2})
            if (!placement.inRange(v)) diag.fail(polygon, outOfRange(v));
        Triangle t{placement.point(local.v0), placement.point(local.v1), placement.point(local.v2)};
        if (degenerate(t)) {
            diag.warn(polygon, "degenerate polygon skipped");
            continue;
        }
        if (placement.flip) {
            std::swap(t.v1, t.v2);
            std::swap(uv[1], uv[2]);
            std::swap(normal[1], normal[2]);
        }
        mesh.triangles.push_back(t);
        if (!uvs.empty()) mesh.uvs.push_back(uv);
        if (!normals.empty()) mesh.normals.push_back(normal);
    }
    if (mesh.triangles.empty()) diag.fail(e, "every <polygon> in <polygons> is degenerate");
    return mesh;
}

// "mesh M primitive P" of a glTF file: M the mesh's index or name, P the
// primitive's index.
const GltfPrimitive& gltfPart(const Diagnostics& diag, const XMLElement* e, const GltfFile& file,
                              const std::string& part, const std::string& name) {
    const std::string form = "; expected part=\"mesh M primitive P\" (M the mesh's index or name, P the primitive's index)";
    size_t at = part.rfind(" primitive ");
    if (part.rfind("mesh ", 0) != 0 || at == std::string::npos || at < 5)
        diag.fail(e, name + ": part \"" + part + "\" names no glTF primitive" + form);
    auto index = [](const std::string& text) -> std::optional<size_t> {
        if (text.empty() || text.size() > 9 || !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); }))
            return std::nullopt;
        return size_t(std::stoul(text));
    };
    std::string meshText = part.substr(5, at - 5), primitiveText = part.substr(at + 11);
    std::optional<size_t> mesh = index(meshText);
    if (!mesh)
        for (size_t m = 0; m < file.meshes.size() && !mesh; ++m)
            if (file.meshes[m].name == meshText) mesh = m;
    if (!mesh || *mesh >= file.meshes.size())
        diag.fail(e, name + ": part \"" + part + "\": the file has no mesh " + meshText + " (it has " +
                         std::to_string(file.meshes.size()) + " mesh" + (file.meshes.size() == 1 ? "" : "es") +
                         ", 0 to " + std::to_string(int(file.meshes.size()) - 1) + ")");
    const GltfMesh& m = file.meshes[*mesh];
    std::optional<size_t> primitive = index(primitiveText);
    if (!primitive) diag.fail(e, name + ": part \"" + part + "\": primitive " + primitiveText + " is not an index" + form);
    if (*primitive >= m.primitives.size())
        diag.fail(e, name + ": part \"" + part + "\": mesh " + meshText + " has " + std::to_string(m.primitives.size()) +
                         " primitive" + (m.primitives.size() == 1 ? "" : "s"));
    if (m.primitives[*primitive].indices.empty())
        diag.fail(e, name + ": part \"" + part + "\" has no triangles");
    return m.primitives[*primitive];
}

// Whether the object's <properties> give it a texture of its own (the
// texture elements of scenes/README.md "Textures"), which reads the mesh's
// texture coordinates.
bool namesTexture(const XMLElement* properties) {
    for (const char* texture : {"diffuse_texture", "normal_map", "emission_texture", "roughness_texture"})
        if (properties->FirstChildElement(texture)) return true;
    return false;
}

// A glTF primitive, built as the glTF scene builds it (authored_scene.h),
// so that a converted scene renders bit for bit as the file: world = the
// <matrix> (else the <scale> and <rotation>), then moved by <position>.
Mesh readGltfPart(const Diagnostics& diag, const XMLElement* e, const Placement& placement,
                  const std::filesystem::path& path, const std::string& part, const std::string& name,
                  FileMaterials& fileMaterials, ModelFiles& files) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) diag.fail(e, name + " does not exist");
    std::shared_ptr<const GltfFile>& file = files.gltf[std::filesystem::absolute(path).lexically_normal()];
    if (!file) {
        try {
            file = std::make_shared<const GltfFile>(readGltfFile(path));
        } catch (const GltfFileError& error) {
            std::string text = error.what(), prefix = path.string() + ": ";
            diag.fail(e, name + ": " + (text.rfind(prefix, 0) == 0 ? text.substr(prefix.size()) : text));
        }
    }
    const GltfPrimitive& primitive = gltfPart(diag, e, *file, part, name);
    const GltfMaterial* material =
        primitive.material >= 0 ? &file->materials[size_t(primitive.material)] : nullptr;
    const XMLElement* properties = e->Parent()->ToElement();
    bool ownNormalMap = properties->FirstChildElement("normal_map") != nullptr;
    bool fileTextures = fileMaterials.wanted && material && (material->baseColorTexture || material->normalTexture);
    bool normalMapped = ownNormalMap || (fileMaterials.wanted && material && material->normalTexture);
    bool textured = fileTextures || namesTexture(properties);
    glm::dmat4 world = placement.matrix ? *placement.matrix : glm::dmat4(placement.linear);
    size_t skipped = 0;
    Mesh mesh = meshFromGltfPrimitive(primitive, world, textured, normalMapped, skipped);
    if (mesh.triangles.empty()) diag.fail(e, name + ": every triangle of part \"" + part + "\" is degenerate");
    if (skipped > 0) diag.warn(e, name + ": " + skippedTriangles(skipped));
    for (Triangle& t : mesh.triangles) {
        if (placement.position != glm::dvec3(0))
            for (glm::dvec3* v : {&t.v0, &t.v1, &t.v2}) *v += placement.position;
        for (const glm::dvec3& v : {t.v0, t.v1, t.v2})
            if (!withinMagnitude(v))
                diag.fail(e, name + ": part \"" + part + "\" is placed beyond ±1e6 or not finite");
    }
    if (fileMaterials.wanted) {  // the primitive's own base colour, texture and normal texture
        MeshFileMaterial own;
        if (material) {
            own.baseColour = glm::dvec3(material->baseColorFactor);
            own.baseColourTexture = material->baseColorTexture;
            own.normalTexture = material->normalTexture;
        }
        fileMaterials.materials = {own};
        fileMaterials.triangleMaterials.assign(mesh.triangles.size(), 0);
    }
    mesh.source = Mesh::FileSource{std::filesystem::absolute(path).lexically_normal(), placement.position,
                                   placement.scale, placement.rotationDegrees, -1, part, placement.matrix};
    return mesh;
}

// What a <file> element names: the model file (its path relative to the
// scene file's folder), the name errors give it, and the part, if any.
struct FileReference {
    std::filesystem::path path;
    std::string name;
    std::string part;
};

FileReference readFileReference(const Diagnostics& diag, const XMLElement* e,
                                const std::filesystem::path& sceneFolder) {
    std::string written = valueText(diag, e, "part");
    if (written.empty()) diag.fail(e, "<file> is empty; expected the path of a model file");
    FileReference ref{written, "mesh file \"" + written + "\"", ""};
    if (ref.path.is_relative()) ref.path = sceneFolder / ref.path;
    const char* partAttribute = e->Attribute("part");
    ref.part = partAttribute ? trimmed(partAttribute) : "";
    if (partAttribute && ref.part.empty()) diag.fail(e, "<file>'s part is empty; leave it out for the whole file");
    return ref;
}

// A model file as read (host/io/mesh_file.h), and the MTL materials that
// apply to it.
struct ReadModelFile {
    std::shared_ptr<const MeshFileData> data;
    // An OBJ file with MTL libraries whose materials apply: mapped by
    // whitted's MTL reader, as `whitted render FILE.obj` maps them (Assimp
    // 5.2 keeps only illum 0-2 and refuses Windows texture paths).
    bool withMtl = false;
    std::map<std::string, Material> mtl;
    bool tangents = false;  // read with tangents: a normal map may apply, the scene's or the file's
};

ReadModelFile readModelFile(const Diagnostics& diag, const XMLElement* e, const FileReference& ref,
                            const FileMaterials& fileMaterials, ModelFiles& files) {
    ReadModelFile out;
    bool mtlNormalMaps = false;
    out.withMtl = fileMaterials.wanted && !objMaterialLibraries(ref.path).empty();
    if (out.withMtl) {
        std::vector<std::string> warnings;
        out.mtl = objMtlMaterials(ref.path, warnings, mtlNormalMaps);
        for (const std::string& w : warnings) diag.warn(e, w);
    }
    const XMLElement* properties = e->Parent()->ToElement();
    out.tangents = out.withMtl ? mtlNormalMaps || properties->FirstChildElement("normal_map")
                               : fileMaterials.wanted || properties->FirstChildElement("normal_map");
    const MeshFileMaterials mode = out.withMtl || (!ref.part.empty() && !fileMaterials.wanted)
                                       ? MeshFileMaterials::Names
                                   : fileMaterials.wanted ? MeshFileMaterials::Read
                                                          : MeshFileMaterials::Ignore;
    try {
        if (ref.part.empty()) {
            out.data = std::make_shared<const MeshFileData>(readMeshFile(ref.path, mode, out.tangents));
        } else {  // one file, many parts: read once
            std::shared_ptr<const MeshFileData>& cached =
                files.meshes[{std::filesystem::absolute(ref.path).lexically_normal(), mode, out.tangents}];
            if (!cached) cached = std::make_shared<const MeshFileData>(readMeshFile(ref.path, mode, out.tangents));
            out.data = cached;
        }
    } catch (const MeshFileError& error) {
        diag.fail(e, ref.name + " " + error.what());
    }
    return out;
}

// part="material NAME": the index of the file's one material of that name.
uint32_t partMaterial(const Diagnostics& diag, const XMLElement* e, const FileReference& ref,
                      const MeshFileData& data) {
    if (ref.part.rfind("material ", 0) != 0)
        diag.fail(e, ref.name + ": part \"" + ref.part +
                         "\" names no part; expected part=\"material NAME\" (glTF files: \"mesh M primitive P\")");
    std::string wanted = trimmed(ref.part.substr(9));
    std::string names;
    std::optional<uint32_t> found;
    for (uint32_t k = 0; k < data.materialNames.size(); ++k) {
        if (data.materialNames[k].empty()) continue;
        if (data.materialNames[k] == wanted) {
            if (found) diag.fail(e, ref.name + ": part \"" + ref.part + "\": two materials of the file have that name");
            found = k;
        }
        names += (names.empty() ? "\"" : ", \"") + data.materialNames[k] + "\"";
    }
    if (!found)
        diag.fail(e, ref.name + ": part \"" + ref.part + "\": the file has no material \"" + wanted + "\"" +
                         (names.empty() ? std::string(" (it has no named materials)") : " (it has " + names + ")"));
    return *found;
}

// The file's triangles (of the one material, with a part) placed in the
// scene, with their normals, texture coordinates and tangents; degenerate
// ones dropped and counted in `skipped`. Each triangle's file material goes
// into fileMaterials where they are wanted.
Mesh placeFileTriangles(const Diagnostics& diag, const XMLElement* e, const std::string& name,
                        const ReadModelFile& read, const Placement& placement,
                        std::optional<uint32_t> partMaterial, bool keepUvs, FileMaterials& fileMaterials,
                        size_t& skipped) {
    const MeshFileData& data = *read.data;
    Mesh mesh;
    for (size_t i = 0; i < data.triangles.size(); ++i) {
        if (partMaterial && data.triangleMaterials[i] != *partMaterial) continue;
        const auto& v = data.triangles[i];
        for (const glm::dvec3& p : v)
            if (!placement.inRange(p)) diag.fail(e, name + ": " + outOfRange(p));
        std::array<size_t, 3> order{0, 1, 2};
        if (placement.flip) order = {0, 2, 1};
        Triangle t{placement.point(v[order[0]]), placement.point(v[order[1]]), placement.point(v[order[2]])};
        if (degenerate(t)) {
            ++skipped;
            continue;
        }
        mesh.triangles.push_back(t);
        const bool uvs = keepUvs && !data.uvs.empty();
        if (uvs) mesh.uvs.push_back({data.uvs[i][order[0]], data.uvs[i][order[1]], data.uvs[i][order[2]]});
        if (!data.tangents.empty() && uvs) {
            const auto& t = data.tangents[i];
            auto place = [&](const glm::dvec3& v) {  // directions go through the linear part
                if (placement.identity) return v;    // unit already (or zero)
                glm::dvec3 w = placement.linear * v;
                return glm::length(w) > 0 ? glm::normalize(w) : w;
            };
            mesh.tangents.push_back({place(t[order[0]]), place(t[order[1]]), place(t[order[2]])});
        } else if (partMaterial && read.tangents && uvs) {
            mesh.tangents.push_back({});  // as the OBJ/MTL scene: none computed
        }
        if (!data.triangleMaterials.empty() && fileMaterials.wanted)
            fileMaterials.triangleMaterials.push_back(data.triangleMaterials[i]);
        if (!data.normals.empty()) {
            const auto& n = data.normals[i];
            mesh.normals.push_back(
                {placement.normal(n[order[0]]), placement.normal(n[order[1]]), placement.normal(n[order[2]])});
        }
    }
    return mesh;
}

// The file's materials, for the object's split into one object per
// material (splitByFileMaterial); with MTL libraries, each one's whole.
void keepFileMaterials(const ReadModelFile& read, FileMaterials& fileMaterials) {
    const MeshFileData& data = *read.data;
    if (!fileMaterials.wanted || data.triangleMaterials.empty()) return;
    fileMaterials.materials = data.materials;
    fileMaterials.names = data.materialNames;
    if (read.withMtl)
        for (const std::string& n : data.materialNames) {
            auto it = read.mtl.find(n);
            Material m;
            m.ambient = 0.1;  // a material the libraries lack: white, as the OBJ/MTL scene has it
            fileMaterials.authored.push_back(it != read.mtl.end() ? it->second : m);
        }
}

// A <file> element's mesh: a model file (host/io/mesh_file.h) placed in the
// scene. Degenerate triangles are dropped with one warning. With
// part="material NAME" only the triangles of that material of the file
// (a glTF file's part="mesh M primitive P": readGltfPart).
Mesh meshFromFileElement(const Diagnostics& diag, const XMLElement* e, const Placement& placement,
                         const std::filesystem::path& sceneFolder, FileMaterials& fileMaterials, ModelFiles& files) {
    const FileReference ref = readFileReference(diag, e, sceneFolder);
    if (!ref.part.empty() && isGltfFile(ref.path))
        return readGltfPart(diag, e, placement, ref.path, ref.part, ref.name, fileMaterials, files);
    const ReadModelFile read = readModelFile(diag, e, ref, fileMaterials, files);
    std::optional<uint32_t> material;
    if (!ref.part.empty()) material = partMaterial(diag, e, ref, *read.data);
    // A part keeps texture coordinates (and tangents) only where a texture
    // applies, as the OBJ/MTL scene does; the whole file always.
    const bool keepUvs =
        ref.part.empty() || fileMaterials.wanted || read.tangents || namesTexture(e->Parent()->ToElement());
    size_t skipped = 0;
    Mesh mesh = placeFileTriangles(diag, e, ref.name, read, placement, material, keepUvs, fileMaterials, skipped);
    if (mesh.triangles.empty()) diag.fail(e, "every triangle in " + ref.name + " is degenerate");
    mesh.source = Mesh::FileSource{std::filesystem::absolute(ref.path).lexically_normal(), placement.position,
                                   placement.scale, placement.rotationDegrees, -1, ref.part, placement.matrix};
    keepFileMaterials(read, fileMaterials);
    if (skipped > 0) diag.warn(e, ref.name + ": " + skippedTriangles(skipped));
    return mesh;
}

}  // namespace

bool degenerate(const Triangle& t) {
    glm::dvec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0, e3 = t.v2 - t.v1;
    double scale = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
    return !(glm::length(glm::cross(e1, e2)) > kDegenerateTolerance * scale);
}

std::string withThousands(uint64_t n) {
    std::string digits = std::to_string(n), out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

std::string skippedTriangles(uint64_t count) {
    return withThousands(count) + " degenerate triangle" + (count == 1 ? "" : "s") + " skipped";
}

Triangle readTriangle(const Diagnostics& diag, const XMLElement* parent, const std::vector<const XMLElement*>& vertices,
                      const glm::dvec3& offset) {
    if (vertices.size() != 3)
        diag.fail(parent, tag(parent->Name()) + " has " + std::to_string(vertices.size()) + " <vertex>, expected 3");
    return {offset + vector(diag, vertices[0]), offset + vector(diag, vertices[1]), offset + vector(diag, vertices[2])};
}

// A mesh has either inline <polygons> or a model <file>.
Mesh readMeshObject(const Diagnostics& diag, ElementReader& object, ElementReader& properties,
                    const glm::dvec3& position, const std::filesystem::path& sceneFolder,
                    FileMaterials& fileMaterials, ModelFiles& modelFiles) {
    const XMLElement* polygons = properties.optional("polygons");
    const XMLElement* file = properties.optional("file");
    if (polygons && file)
        diag.fail(laterOf(polygons, file), "<properties> has both <polygons> and <file>; a mesh takes one");
    if (!polygons && !file)
        diag.fail(object.element(), "<object> is missing <polygons> or <file> (required for type mesh)");
    Placement placement = readPlacement(diag, properties, position);
    return polygons ? readMesh(diag, polygons, placement)
                    : meshFromFileElement(diag, file, placement, sceneFolder, fileMaterials, modelFiles);
}

std::vector<Object> splitByFileMaterial(Object whole, const FileMaterials& fileMaterials) {
    const Mesh& mesh = std::get<Mesh>(whole.shape);
    const std::vector<MeshFileMaterial>& materials = fileMaterials.materials;
    std::vector<Object> parts;
    for (uint32_t k = 0; k < materials.size(); ++k) {
        Object part;
        part.sourceLine = whole.sourceLine;
        part.name = whole.name;
        part.material = whole.material;
        part.material.diffuseColor = materials[k].baseColour;
        Mesh piece;
        for (size_t i = 0; i < mesh.triangles.size(); ++i) {
            if (fileMaterials.triangleMaterials[i] != k) continue;
            piece.triangles.push_back(mesh.triangles[i]);
            if (!mesh.normals.empty()) piece.normals.push_back(mesh.normals[i]);
            if (!mesh.uvs.empty()) piece.uvs.push_back(mesh.uvs[i]);
            if (!mesh.tangents.empty()) piece.tangents.push_back(mesh.tangents[i]);
        }
        if (piece.triangles.empty()) continue;
        if (!fileMaterials.authored.empty()) {  // the file's MTL material, whole
            part.material = fileMaterials.authored[k];
            if (part.name.empty()) part.name = fileMaterials.names[k];
            if (piece.uvs.empty())
                part.material.dropTextures();
            if (part.material.normalMap && piece.tangents.empty())
                piece.tangents.assign(piece.triangles.size(), std::array<glm::dvec3, 3>{});
        }
        if (materials[k].baseColourTexture && !piece.uvs.empty())
            part.material.diffuseTexture = {"", materials[k].baseColourTexture};
        if (materials[k].normalTexture && !piece.uvs.empty() && !part.material.normalMap)
            part.material.normalMap = {"", materials[k].normalTexture};
        if (mesh.source) {
            piece.source = mesh.source;
            piece.source->part = int(parts.size());
        }
        part.shape = std::move(piece);
        parts.push_back(std::move(part));
    }
    return parts;
}

}  // namespace whitted

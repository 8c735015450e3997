#include "scene/mesh_objects.h"

#include <algorithm>
#include <array>
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
struct Placement {
    glm::dvec3 offset{0};
    glm::dmat3 linear{1.0};
    glm::dmat3 normalLinear{1.0};
    bool identity = true;  // no <scale> and no <rotation>: vertices are only offset
    glm::dvec3 scale{1}, rotationDegrees{0};  // as written

    // Within ±1e6 of the position on every axis, as inline vertices
    // are; false when <scale> or <rotation> take a vertex further.
    bool inRange(const glm::dvec3& v) const {
        if (identity) return true;
        glm::dvec3 placed = linear * v;
        return std::abs(placed.x) <= kMaxMagnitude && std::abs(placed.y) <= kMaxMagnitude &&
               std::abs(placed.z) <= kMaxMagnitude;
    }
    glm::dvec3 point(const glm::dvec3& v) const { return identity ? offset + v : offset + linear * v; }
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

// <scale> is one number for all axes, or a vector (x, y, z); each > 0.
Placement readPlacement(const Diagnostics& diag, ElementReader& properties, const glm::dvec3& position) {
    Placement placement;
    placement.offset = position;
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
        mesh.triangles.push_back(t);
        if (!uvs.empty()) mesh.uvs.push_back(uv);
        if (!normals.empty()) mesh.normals.push_back(normal);
    }
    if (mesh.triangles.empty()) diag.fail(e, "every <polygon> in <polygons> is degenerate");
    return mesh;
}

// A model file (host/io/mesh_file.h), its path relative to the scene
// file's folder. Degenerate triangles are dropped with one warning.
Mesh readMeshFile(const Diagnostics& diag, const XMLElement* e, const Placement& placement,
                  const std::filesystem::path& sceneFolder, FileMaterials& fileMaterials) {
    std::string written = valueText(diag, e);
    if (written.empty()) diag.fail(e, "<file> is empty; expected the path of a model file");
    std::filesystem::path path(written);
    if (path.is_relative()) path = sceneFolder / path;
    std::string name = "mesh file \"" + written + "\"";
    MeshFileData data;
    try {
        // Tangents where a normal map may apply: the scene's or the file's.
        bool tangents = fileMaterials.wanted || e->Parent()->FirstChildElement("normal_map");
        data = whitted::readMeshFile(path, fileMaterials.wanted ? MeshFileMaterials::Read : MeshFileMaterials::Ignore,
                                     tangents);
    } catch (const MeshFileError& error) {
        diag.fail(e, name + " " + error.what());
    }

    Mesh mesh;
    size_t skipped = 0;
    for (size_t i = 0; i < data.triangles.size(); ++i) {
        const auto& v = data.triangles[i];
        for (const glm::dvec3& p : v)
            if (!placement.inRange(p)) diag.fail(e, name + ": " + outOfRange(p));
        Triangle t{placement.point(v[0]), placement.point(v[1]), placement.point(v[2])};
        if (degenerate(t)) {
            ++skipped;
            continue;
        }
        mesh.triangles.push_back(t);
        if (!data.uvs.empty()) mesh.uvs.push_back(data.uvs[i]);
        if (!data.tangents.empty()) {
            const auto& t = data.tangents[i];
            auto place = [&](const glm::dvec3& v) {  // directions go through the linear part
                glm::dvec3 w = placement.identity ? v : placement.linear * v;
                return glm::length(w) > 0 ? glm::normalize(w) : w;
            };
            mesh.tangents.push_back({place(t[0]), place(t[1]), place(t[2])});
        }
        if (!data.triangleMaterials.empty()) fileMaterials.triangleMaterials.push_back(data.triangleMaterials[i]);
        if (!data.normals.empty()) {
            const auto& n = data.normals[i];
            mesh.normals.push_back({placement.normal(n[0]), placement.normal(n[1]), placement.normal(n[2])});
        }
    }
    if (mesh.triangles.empty()) diag.fail(e, "every triangle in " + name + " is degenerate");
    mesh.source = Mesh::FileSource{std::filesystem::absolute(path).lexically_normal(), placement.offset,
                                   placement.scale, placement.rotationDegrees};
    if (!data.triangleMaterials.empty()) fileMaterials.materials = std::move(data.materials);
    if (skipped > 0)
        diag.warn(e, name + ": " + std::to_string(skipped) + " degenerate triangle" + (skipped > 1 ? "s" : "") +
                         " skipped");
    return mesh;
}

}  // namespace

bool degenerate(const Triangle& t) {
    glm::dvec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0, e3 = t.v2 - t.v1;
    double scale = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
    return !(glm::length(glm::cross(e1, e2)) > kDegenerateTolerance * scale);
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
                    FileMaterials& fileMaterials) {
    const XMLElement* polygons = properties.optional("polygons");
    const XMLElement* file = properties.optional("file");
    if (polygons && file)
        diag.fail(laterOf(polygons, file), "<properties> has both <polygons> and <file>; a mesh takes one");
    if (!polygons && !file)
        diag.fail(object.element(), "<object> is missing <polygons> or <file> (required for type mesh)");
    Placement placement = readPlacement(diag, properties, position);
    return polygons ? readMesh(diag, polygons, placement)
                    : readMeshFile(diag, file, placement, sceneFolder, fileMaterials);
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

#include "scene/authored_scene.h"

#include "io/gltf_file.h"
#include "io/mesh_file.h"
#include "io/mtl_file.h"
#include "scene/mesh_objects.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>

namespace whitted {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Every position of a scene is within ±1e6 (xml::withinMagnitude); node
// transforms multiply, so a placed glTF point is checked where placed.
using xml::withinMagnitude;

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// Per-triangle tangents along +u (whitted's convention, v up), from the
// triangle's world vertices and its texture coordinates; zero where the
// UVs are degenerate.
std::array<glm::dvec3, 3> tangentsOf(const Triangle& t, const std::array<glm::dvec2, 3>& uv) {
    glm::dvec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0;
    glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    double det = d1.x * d2.y - d2.x * d1.y;
    glm::dvec3 tangent = std::abs(det) > 1e-20 ? (e1 * d2.y - e2 * d1.y) / det : glm::dvec3(0);
    double length = glm::length(tangent);
    tangent = length > 1e-20 && std::isfinite(length) ? tangent / length : glm::dvec3(0);
    return {tangent, tangent, tangent};
}

}  // namespace

bool isGltfFile(const std::filesystem::path& path) {
    std::string ext = lowerExtension(path);
    return ext == ".gltf" || ext == ".glb";
}

std::vector<std::filesystem::path> objMaterialLibraries(const std::filesystem::path& path) {
    std::vector<std::filesystem::path> libraries;
    if (lowerExtension(path) != ".obj") return libraries;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        size_t at = line.find_first_not_of(" \t");
        if (at == std::string::npos || line.compare(at, 7, "mtllib ") != 0) continue;
        std::string name = line.substr(at + 7);
        while (!name.empty() && std::isspace((unsigned char)name.back())) name.pop_back();
        while (!name.empty() && std::isspace((unsigned char)name.front())) name.erase(name.begin());
        if (!name.empty()) libraries.push_back(mtlPath(path.parent_path(), name));
    }
    return libraries;
}

// ---- glTF ----

Material materialFromGltf(const GltfMaterial& g) {
    const glm::dvec3 b(g.baseColorFactor);
    const double m = g.metallicFactor, r = g.roughnessFactor, t = g.transmissionFactor, eta = g.ior;
    const double f0 = std::pow((eta - 1) / (eta + 1), 2);
    Material out;
    out.ambient = 0;  // a glTF scene has no ambient light
    out.diffuseColor = b;
    out.diffuseTexture = {"", g.baseColorTexture};
    out.diffuse = (1 - m) * (1 - t);
    // Reflection and highlight: Schlick's F0 for dielectrics, b for metals.
    // Metals and glass reflect (and refract) through the glossy lobe of the
    // roughness (Material::roughness); an opaque dielectric's faint
    // reflection fades with roughness instead, as its diffuse term
    // dominates (a glossy lobe there would add noise for little light).
    double specular = glm::mix(f0, 1.0, m);
    const bool glossy = m > 0 || t > 0;
    out.specularColor = glm::mix(glm::dvec3(1), b, m);
    out.reflection = glossy ? specular : specular * (1 - r) * (1 - r);
    out.roughness = glossy ? r : 0.0;
    // Its green channel times roughnessFactor is the roughness (glTF 2.0,
    // 3.9.2), where the lobe is used; its blue (metalness) is not read.
    if (glossy && r > 0 && g.metallicRoughnessTexture) out.roughnessTexture = {"", g.metallicRoughnessTexture};
    out.specular = specular * (1 - r);
    double alpha = r * r;
    out.shininess = alpha > 0 ? std::clamp(2 / (alpha * alpha) - 2, 1.0, 1e4) : 1e4;
    // Glass.
    out.transmission = t * (1 - m);
    if (out.transmission > 0) {
        bool thin = g.hasVolume && g.thicknessFactor == 0;
        out.ior = thin ? 1.0 : eta;
        out.fresnel = true;
        out.transmissionColor = b;
        if (g.hasVolume && !thin && std::isfinite(g.attenuationDistance))
            for (int c = 0; c < 3; ++c)
                out.absorption[c] = -std::log(std::max(g.attenuationColor[c], 1e-9)) / g.attenuationDistance;
    }
    out.emission = g.emissiveFactor * g.emissiveStrength;
    if (g.emissiveTexture) out.emissionTexture = {"", g.emissiveTexture};
    if (g.normalTexture) {
        out.normalMap = {"", g.normalTexture};
        out.normalStrength = g.normalScale;
    }
    return out;
}

Light lightFromGltf(const GltfLight& g, const glm::dmat4& world) {
    Light light;
    light.name = g.name;
    light.type = g.type == GltfLight::Type::Point  ? Light::Type::Point
                 : g.type == GltfLight::Type::Spot ? Light::Type::Spot
                                                   : Light::Type::Directional;
    light.color = g.color;
    light.intensity = g.intensity / kPi;  // so that a Lambertian albedo rho gives rho / pi * E
    light.falloff = g.type == GltfLight::Type::Directional ? Light::Falloff::None : Light::Falloff::InverseSquare;
    light.position = light.type == Light::Type::Directional ? glm::dvec3(0) : glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
    light.direction = glm::normalize(glm::dvec3(world * glm::dvec4(0, 0, -1, 0)));
    light.innerAngleDegrees = glm::degrees(g.innerConeAngle);
    light.outerAngleDegrees = glm::degrees(g.outerConeAngle);
    return light;
}

std::string gltfPartName(size_t mesh, size_t primitive) {
    return "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive);
}

Mesh meshFromGltfPrimitive(const GltfPrimitive& prim, const glm::dmat4& world, bool textured, bool normalMapped,
                           size_t& degenerateSkipped) {
    const glm::dmat3 linear(world);
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
    const bool flip = glm::determinant(linear) < 0;  // mirrored: the winding turns over
    textured = textured && !prim.uvs.empty();
    Mesh out;
    for (size_t i = 0; i + 2 < prim.indices.size(); i += 3) {
        std::array<uint32_t, 3> v{prim.indices[i], prim.indices[i + 1], prim.indices[i + 2]};
        if (flip) std::swap(v[1], v[2]);
        Triangle t;
        glm::dvec3* corners[3] = {&t.v0, &t.v1, &t.v2};
        for (int k = 0; k < 3; ++k) *corners[k] = glm::dvec3(world * glm::dvec4(prim.positions[v[size_t(k)]], 1));
        // Dropped where placed, as a scene file's <file> drops them: a
        // transform can flatten a triangle the file holds whole.
        if (degenerate(t)) {
            ++degenerateSkipped;
            continue;
        }
        out.triangles.push_back(t);
        if (!prim.normals.empty()) {
            std::array<glm::dvec3, 3> n;
            glm::dvec3 flat = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
            flat = glm::length(flat) > 0 ? glm::normalize(flat) : glm::dvec3(0, 0, 1);
            for (int k = 0; k < 3; ++k) {
                glm::dvec3 x = normalMatrix * prim.normals[v[size_t(k)]];
                n[size_t(k)] = glm::length(x) > 1e-12 && std::isfinite(glm::length(x)) ? glm::normalize(x) : flat;
            }
            out.normals.push_back(n);
        }
        if (textured) {
            std::array<glm::dvec2, 3> uv;
            for (int k = 0; k < 3; ++k) {
                glm::dvec2 u = prim.uvs[v[size_t(k)]];
                uv[size_t(k)] = glm::dvec2(u.x, 1.0 - u.y);  // glTF's v runs down the image
            }
            out.uvs.push_back(uv);
            if (normalMapped) out.tangents.push_back(tangentsOf(t, uv));
        }
    }
    return out;
}

namespace {

// A node's mesh: an object per primitive with indices, placed by the
// node's world transform. Returns how many triangles were degenerate once
// placed; they are dropped.
size_t addNodeMesh(const GltfFile& file, int meshIndex, const std::string& nodeName, const glm::dmat4& world,
                   const std::vector<Material>& materials, const std::filesystem::path& absolutePath,
                   const std::string& where, Scene& scene) {
    size_t skippedTotal = 0;
    const GltfMesh& mesh = file.meshes[size_t(meshIndex)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const GltfPrimitive& prim = mesh.primitives[p];
        if (prim.indices.empty()) continue;
        Object object;
        object.name = nodeName + (mesh.primitives.size() > 1 ? " primitive " + std::to_string(p) : "");
        if (prim.material >= 0) {
            object.material = materials[size_t(prim.material)];
        } else {  // no material: white Lambert (the specification's default, a rough metal, is black here)
            object.material.ambient = 0;
        }
        bool textured = object.material.textured();
        if (textured && prim.uvs.empty()) {
            scene.warnings.push_back(where + ": node \"" + nodeName +
                                     "\": its textures are not used: the primitive has no TEXCOORD_0");
            object.material.dropTextures();
            textured = false;
        }
        size_t skipped = 0;
        Mesh out = meshFromGltfPrimitive(prim, world, textured, bool(object.material.normalMap), skipped);
        for (const Triangle& t : out.triangles)
            for (const glm::dvec3& v : {t.v0, t.v1, t.v2})
                if (!withinMagnitude(v))
                    throw SceneError(where, 0, "node \"" + nodeName + "\": a vertex is placed beyond ±1e6");
        skippedTotal += skipped;
        if (out.triangles.empty()) continue;
        // Written back by the scene writer as <file part="mesh M primitive P"> with <matrix>.
        out.source = Mesh::FileSource{absolutePath, glm::dvec3(0), glm::dvec3(1), glm::dvec3(0), -1,
                                      gltfPartName(size_t(meshIndex), p), world};
        object.shape = std::move(out);
        scene.objects.push_back(std::move(object));
    }
    return skippedTotal;
}

// The file's degenerate triangles in one warning: a node's own line when
// only one node had any, else the totals, with each node's line a detail
// (Scene::warningDetails).
void warnSkippedTriangles(const std::string& where, const std::vector<std::pair<std::string, size_t>>& byNode,
                          Scene& scene) {
    if (byNode.empty()) return;
    std::vector<std::string> lines;
    uint64_t total = 0;
    for (const auto& [nodeName, skipped] : byNode) {
        lines.push_back(where + ": node \"" + nodeName + "\": " + skippedTriangles(skipped));
        total += skipped;
    }
    if (lines.size() == 1) {
        scene.warnings.push_back(lines.front());
        return;
    }
    scene.warnings.push_back(where + ": " + skippedTriangles(total) + " in " + withThousands(lines.size()) + " nodes");
    scene.warningDetails.insert(scene.warningDetails.end(), lines.begin(), lines.end());
}

}  // namespace

AuthoredScene loadGltfScene(const std::filesystem::path& path) {
    GltfFile file;
    try {
        file = readGltfFile(path);
    } catch (const GltfFileError& e) {
        std::string text = e.what(), prefix = path.string() + ": ";
        throw SceneError(path.string(), 0, text.rfind(prefix, 0) == 0 ? text.substr(prefix.size()) : text);
    }
    AuthoredScene out;
    Scene& scene = out.scene;
    scene.ambientLight = glm::dvec3(0);
    scene.warnings = file.warnings;
    std::vector<Material> materials;
    for (const GltfMaterial& m : file.materials) materials.push_back(materialFromGltf(m));
    const std::string where = path.string();
    const std::filesystem::path absolutePath = std::filesystem::absolute(path).lexically_normal();
    std::vector<std::pair<std::string, size_t>> skippedByNode;  // the nodes with degenerate triangles

    // One node with its world transform; the tree is walked below without
    // recursion (the reader bounds its depth, io/gltf_file.h).
    auto visit = [&](int index, const glm::dmat4& world) {
        const GltfNode& node = file.nodes[size_t(index)];
        const std::string nodeName = node.name.empty() ? "node " + std::to_string(index) : node.name;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k)
                if (!std::isfinite(world[c][k]))
                    throw SceneError(where, 0, "node \"" + nodeName + "\": its transform is not finite");
        const glm::dmat3 linear(world);
        if (node.camera >= 0) {
            const GltfCamera& g = file.cameras[size_t(node.camera)];
            AuthoredCamera c;
            c.name = g.name.empty() ? nodeName : g.name;
            c.nodeName = node.name;
            Camera& camera = c.camera;
            camera.eye = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
            if (!withinMagnitude(camera.eye))
                throw SceneError(where, 0, "node \"" + nodeName + "\": its camera is placed beyond ±1e6");
            glm::dvec3 forward = linear * glm::dvec3(0, 0, -1), up = linear * glm::dvec3(0, 1, 0);
            if (!(glm::length(forward) > 1e-12) || !(glm::length(glm::cross(forward, up)) > 1e-12))
                throw SceneError(where, 0, "node \"" + nodeName + "\": its camera's transform is degenerate");
            camera.windowCenter = camera.eye + glm::normalize(forward);
            camera.up = glm::normalize(up);
            camera.width = 640;
            double aspect = 0;
            if (g.orthographic) {
                camera.projection = Camera::Projection::Orthographic;
                camera.windowHeight = 2 * g.ymag;
                aspect = g.xmag / g.ymag;
            } else {
                camera.verticalFovDegrees = glm::degrees(g.yfov);
                aspect = g.aspectRatio;
            }
            camera.height = aspect > 0 ? std::clamp(int(std::lround(640 / aspect)), 1, 16384) : 480;
            out.cameras.push_back(std::move(c));
        }
        if (node.light >= 0) {
            Light light = lightFromGltf(file.lights[size_t(node.light)], world);
            if (light.name.empty()) light.name = nodeName;
            if (!std::isfinite(glm::length(light.direction)))
                throw SceneError(where, 0, "node \"" + nodeName + "\": its light's direction is degenerate");
            if (!withinMagnitude(light.position))
                throw SceneError(where, 0, "node \"" + nodeName + "\": its light is placed beyond ±1e6");
            scene.lights.push_back(light);
        }
        if (node.mesh >= 0)
            if (size_t skipped = addNodeMesh(file, node.mesh, nodeName, world, materials, absolutePath, where, scene))
                skippedByNode.emplace_back(nodeName, skipped);
    };
    // Depth first, each node before its children and children in order, as
    // the file lists them (the order objects are numbered in).
    std::vector<std::pair<int, glm::dmat4>> open;
    for (auto root = file.sceneRoots.rbegin(); root != file.sceneRoots.rend(); ++root)
        open.emplace_back(*root, glm::dmat4(1.0) * file.nodes[size_t(*root)].local);
    while (!open.empty()) {
        const auto [index, world] = open.back();
        open.pop_back();
        visit(index, world);
        const std::vector<int>& children = file.nodes[size_t(index)].children;
        for (auto c = children.rbegin(); c != children.rend(); ++c)
            open.emplace_back(*c, world * file.nodes[size_t(*c)].local);
    }
    warnSkippedTriangles(where, skippedByNode, scene);
    if (scene.objects.empty()) throw SceneError(where, 0, "has no triangles in its scene");
    return out;
}

// ---- OBJ / MTL ----

Material materialFromMtl(const MtlMaterial& m, const std::string& file, std::vector<std::string>& warnings) {
    Material out;
    int illum = m.illum < 0 ? 2 : m.illum;
    if (illum == 10) {
        warnings.push_back(file + ":" + std::to_string(m.illumLine) +
                           ": illum 10 (casts shadows onto invisible surfaces) is not supported; rendered as illum 2");
        illum = 2;
    }
    const glm::dvec3 kd = m.Kd.value_or(glm::dvec3(1)), ks = m.Ks.value_or(glm::dvec3(0));
    const glm::dvec3 tf = m.Tf.value_or(glm::dvec3(1));
    const double ni = m.Ni.value_or(1.5);
    out.diffuseColor = kd;
    // The texture files by their absolute paths: the scene writer names them
    // (relative to the file it writes), and reading them again decodes the same texels.
    auto absolute = [](const std::filesystem::path& p) {
        return p.empty() ? std::string() : std::filesystem::absolute(p).lexically_normal().string();
    };
    out.diffuseTexture = {absolute(m.diffuseTextureFile), m.diffuseTexture};
    if (m.normalMap) out.normalMap = {absolute(m.normalMapFile), m.normalMap};
    // Ambient: Ka as ka * ambient colour (ka its largest channel); none: the
    // quick look's 0.1 of the diffuse colour.
    if (m.Ka) {
        out.ambient = std::max({m.Ka->r, m.Ka->g, m.Ka->b});
        if (out.ambient > 0) out.ambientColor = *m.Ka / out.ambient;
    } else {
        out.ambient = 0.1;
    }
    out.diffuse = 1;
    out.specular = 0;
    out.specularColor = ks;
    // Ns below 1 (spider.obj's 0) is 1: the scene format needs n > 0, and
    // the shader's pow(0, 0) is undefined.
    out.shininess = std::clamp(m.Ns.value_or(32.0), 1.0, 1e5);
    if (m.Ke) out.emission = *m.Ke;
    if (illum == 0) {  // constant colour Kd
        out.ambient = 0;
        out.ambientColor.reset();
        out.diffuse = 0;
        out.emission = kd;
        return out;
    }
    if (illum >= 2) out.specular = 1;  // the highlight Ks, Ns
    const bool mirror = illum >= 3;    // every model from 3 on reflects Ks
    const bool glass = illum == 4 || illum == 6 || illum == 7 || illum == 9;
    if (mirror) out.reflection = 1;
    if (illum == 5 || illum == 7) {  // Fresnel: F0 of Ni
        out.fresnel = true;
        out.reflection = std::pow((ni - 1) / (ni + 1), 2);
    }
    if (glass) {
        out.transmission = 1;
        out.ior = illum == 6 || illum == 7 ? ni : 1.0;
        // The scene format's index of refraction is in [0.1, 10] (<refraction_coef>).
        if (!(out.ior >= kIorRange.lo && out.ior <= kIorRange.hi))
            throw SceneError(file, m.illumLine,
                             "illum " + std::to_string(illum) + " refracts by Ni, which must then be in [0.1, 10]");
        out.transmissionColor = (glm::dvec3(1) - glm::min(ks, glm::dvec3(1))) * tf;
    } else if (m.d && *m.d < 1) {  // dissolve: see-through without bending
        double d = *m.d;
        out.transmission = 1 - d;
        out.ior = 1;
        out.transmissionColor = tf;
        out.ambient *= d;
        out.diffuse *= d;
        out.specular *= d;
    }
    return out;
}

std::map<std::string, Material> objMtlMaterials(const std::filesystem::path& path, std::vector<std::string>& warnings,
                                                bool& normalMaps) {
    const std::string where = path.string();
    std::map<std::string, Material> byName;
    normalMaps = false;
    for (const std::filesystem::path& library : objMaterialLibraries(path)) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(library, ec)) {
            warnings.push_back(where + ": material library " + library.filename().string() +
                               " does not exist; its materials are white");
            continue;
        }
        MtlFile mtl;
        try {
            mtl = readMtlFile(library);
        } catch (const MtlFileError& e) {
            throw SceneError(e.file, e.line, e.reason);
        }
        warnings.insert(warnings.end(), mtl.warnings.begin(), mtl.warnings.end());
        for (const MtlMaterial& m : mtl.materials) {
            byName[m.name] = materialFromMtl(m, library.string(), warnings);
            normalMaps = normalMaps || m.normalMap;
        }
    }
    return byName;
}

AuthoredScene loadObjMtlScene(const std::filesystem::path& path) {
    AuthoredScene out;
    Scene& scene = out.scene;
    const std::string where = path.string();
    bool normalMaps = false;
    std::map<std::string, Material> byName = objMtlMaterials(path, scene.warnings, normalMaps);
    MeshFileData data;
    try {
        data = readMeshFile(path, MeshFileMaterials::Names, normalMaps);
    } catch (const MeshFileError& e) {
        throw SceneError(where, 0, std::string("mesh file \"") + path.filename().string() + "\" " + e.what());
    }
    // One object per material, in the file's material order.
    std::vector<Object> objects(data.materialNames.size());
    for (size_t i = 0; i < objects.size(); ++i) {
        objects[i].name = data.materialNames[i];
        auto it = byName.find(data.materialNames[i]);
        if (it != byName.end()) objects[i].material = it->second;
        else objects[i].material.ambient = 0.1;
        objects[i].shape = Mesh{};
    }
    // Degenerate triangles are dropped, as a scene file's <file> drops them
    // (so that its <file part> renders the same).
    size_t skipped = 0;
    for (size_t t = 0; t < data.triangles.size(); ++t) {
        Object& o = objects[data.triangleMaterials[t]];
        Mesh& mesh = std::get<Mesh>(o.shape);
        const auto& v = data.triangles[t];
        if (degenerate({v[0], v[1], v[2]})) {
            ++skipped;
            continue;
        }
        mesh.triangles.push_back({v[0], v[1], v[2]});
        if (!data.normals.empty()) mesh.normals.push_back(data.normals[t]);
        bool textured = o.material.textured();
        if (textured && !data.uvs.empty()) {
            mesh.uvs.push_back(data.uvs[t]);
            if (o.material.normalMap)
                mesh.tangents.push_back(data.tangents.empty() ? std::array<glm::dvec3, 3>{} : data.tangents[t]);
        }
    }
    if (skipped > 0) scene.warnings.push_back(where + ": " + skippedTriangles(skipped));
    // Written back by the scene writer as <file part="material NAME">: a
    // material with a name of its own (Assimp's stand-in for triangles
    // without one has none, and a name used twice would take both).
    const std::filesystem::path absolutePath = std::filesystem::absolute(path).lexically_normal();
    for (Object& o : objects) {
        Mesh& mesh = std::get<Mesh>(o.shape);
        if (mesh.triangles.empty()) continue;
        if (!o.name.empty() && std::count(data.materialNames.begin(), data.materialNames.end(), o.name) == 1)
            mesh.source = Mesh::FileSource{absolutePath, glm::dvec3(0), glm::dvec3(1), glm::dvec3(0), -1,
                                           "material " + o.name, std::nullopt};
        scene.objects.push_back(std::move(o));
    }
    return out;
}

const AuthoredCamera& chooseCamera(const std::vector<AuthoredCamera>& cameras, const std::string& choice,
                                   const std::string& file) {
    if (cameras.empty()) throw SceneError(file, 0, "--camera " + choice + ": the file has no cameras");
    if (choice.empty()) return cameras.front();
    bool digits = std::all_of(choice.begin(), choice.end(), [](unsigned char c) { return std::isdigit(c); });
    if (digits && choice.size() < 9 && size_t(std::stoi(choice)) < cameras.size()) return cameras[size_t(std::stoi(choice))];
    for (const AuthoredCamera& c : cameras)
        if (c.name == choice || (!c.nodeName.empty() && c.nodeName == choice)) return c;
    std::string names;
    for (size_t i = 0; i < cameras.size(); ++i)
        names += (i ? ", " : "") + std::to_string(i) + " \"" + cameras[i].name + "\"";
    throw SceneError(file, 0, "--camera " + choice + " names no camera; the file has " + names);
}

}  // namespace whitted

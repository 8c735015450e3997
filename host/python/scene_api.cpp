// whitted.load, loads, SceneError, and the editable Scene: camera, objects
// (placement and the material fields the window's editor panel edits, and
// a few more), lights, save, copy. Every setter checks its value against
// the scene format's range (the XML reader's) and raises ValueError naming
// the field and the range before anything reaches a device.
#include "scene/quick_look.h"
#include "io/texture_file.h"
#include "python/python_api.h"
#include "scene/mesh_objects.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "scene/shape_edit.h"
#include "scene/xml_reader.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <atomic>
#include <optional>
#include <cmath>
#include <string>

namespace whitted::python {

SceneHandle::SceneHandle(Scene s) : scene(std::make_shared<Scene>(std::move(s))) {
    static std::atomic<uint64_t> next{1};
    id = next++;
    for (size_t i = 0; i < scene->objects.size(); ++i) objectIds.push_back(nextObjectId++);
    for (size_t i = 0; i < scene->lights.size(); ++i) lightIds.push_back(nextLightId++);
}

namespace {

// Scene.copy(): an independent scene (a new handle, so a renderer uploads
// it afresh) that keeps the original's object and light ids, the ids still
// to come and each object's transform, so its masks and legend number the
// objects as the original's do.
SceneRef copyHandle(const SceneRef& s) {
    auto c = std::make_shared<SceneHandle>(*s->scene);
    c->objectIds = s->objectIds;
    c->lightIds = s->lightIds;
    c->nextObjectId = s->nextObjectId;
    c->nextLightId = s->nextLightId;
    c->transforms = s->transforms;
    return c;
}

using xml::Range;
constexpr Range kColourRange = xml::kUnitInterval;
constexpr Range kIor = kIorRange;
constexpr Range kShininess = kShininessRange;
constexpr Range kFov = kFovRange;
constexpr Range kNormalStrength{0, 4, false, false};  // the editor panel's slider
constexpr Range kImageSide{1, 16384, false, false};   // gpu::kMaxImageSide

// "Object.diffuse: must be in [0, 1], got 2"
[[noreturn]] void refuse(const std::string& field, const std::string& expected, const std::string& got) {
    throw py::value_error(field + ": must be " + expected + ", got " + got);
}
std::string shown(double v) { return py::str(py::float_(v)).cast<std::string>(); }

double checked(const std::string& field, double v, const Range& r) {
    if (!std::isfinite(v) || !r.contains(v)) refuse(field, r.describe(), shown(v));
    return v;
}
glm::dvec3 checked(const std::string& field, const glm::dvec3& v, const Range& r) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(v[i]) || !r.contains(v[i]))
            refuse(field, "3 numbers each " + r.describe(), "(" + shown(v.x) + ", " + shown(v.y) + ", " + shown(v.z) + ")");
    return v;
}
// Sets one of the camera's frame vectors, refusing (and undoing) a value
// that leaves it without an image frame, in the XML loader's terms
// (scene/scene.h cameraFrameProblem).
void setCameraFrame(Camera& camera, glm::dvec3 Camera::*member, const glm::dvec3& value, const std::string& field) {
    const glm::dvec3 was = camera.*member;
    camera.*member = value;
    const CameraFrameProblem frame = cameraFrameProblem(camera);
    if (frame == CameraFrameProblem::None) return;
    camera.*member = was;
    throw py::value_error(field + ": " +
                          (frame == CameraFrameProblem::EyeAtWindow ? "Camera.position and Camera.look_at would coincide"
                                                             : "Camera.up would be parallel to the viewing direction"));
}

glm::dvec3 unit(const std::string& field, const glm::dvec3& v) {
    glm::dvec3 f = checked(field, v, xml::kAnyValue);
    if (glm::length(f) < 1e-12) refuse(field, "a non-zero direction", "(0, 0, 0)");
    return glm::normalize(f);
}

// Vectors and colours cross as tuples of three floats.
glm::dvec3 toVec(const py::handle& h, const std::string& field) {
    py::sequence s;
    try {
        s = h.cast<py::sequence>();
    } catch (const py::cast_error&) {
        refuse(field, "3 numbers", py::repr(h).cast<std::string>());
    }
    if (py::len(s) != 3) refuse(field, "3 numbers", py::repr(h).cast<std::string>());
    return {s[0].cast<double>(), s[1].cast<double>(), s[2].cast<double>()};
}
py::tuple toTuple(const glm::dvec3& v) { return py::make_tuple(v.x, v.y, v.z); }

// ---- Views into a scene: they keep it alive and bump its counters ----

// CameraView: python_api.h (camera_api.cpp adds to the class).
// Object and light views hold the handle's id of what they show (python_api.h):
// one removed raises KeyError, the others keep working.
size_t indexOf(const std::vector<uint64_t>& ids, uint64_t id, const char* what) {
    auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) throw py::key_error(std::string("the ") + what + " was removed from its scene");
    return size_t(it - ids.begin());
}
struct ObjectView {
    SceneRef s;
    uint64_t id;
    size_t index() const { return indexOf(s->objectIds, id, "object"); }
    Object& o() const { return s->scene->objects[index()]; }
    std::string field(const char* name) const { return std::string("Object.") + name; }
};
struct LightView {
    SceneRef s;
    uint64_t id;
    size_t index() const { return indexOf(s->lightIds, id, "light"); }
    Light& l() const { return s->scene->lights[index()]; }
};

// whitted.Material: a material's values, not tied to a scene; an object
// takes a copy (Object.material = m).
struct MaterialValue {
    Material m;
};

// The two holders of material fields: an object (an edit bumps its scene's
// materials counter) and a free Material.
Material& materialOf(const ObjectView& v) { return v.o().material; }
Material& materialOf(MaterialValue& v) { return v.m; }
void materialEdited(const ObjectView& v) { ++v.s->versions.materials; }
void materialEdited(MaterialValue&) {}
std::string fieldOf(const ObjectView&, const char* name) { return std::string("Object.") + name; }
std::string fieldOf(MaterialValue&, const char* name) { return std::string("Material.") + name; }

const char* lightTypeName(Light::Type t) {
    switch (t) {
        case Light::Type::Spot: return "spot";
        case Light::Type::Directional: return "directional";
        case Light::Type::Rect: return "rect";
        case Light::Type::Point: break;
    }
    return "point";
}

// A material field of an object: double or colour, with its range; an edit
// bumps the materials counter only.
template <typename View, typename T>
void materialField(py::class_<View>& cls, const char* name, T Material::*member, const Range& range,
                   const char* doc) {
    if constexpr (std::is_same_v<T, double>)
        cls.def_property(
            name, [member](View& v) { return materialOf(v).*member; },
            [member, name, range](View& v, double x) {
                materialOf(v).*member = checked(fieldOf(v, name), x, range);
                materialEdited(v);
            },
            doc);
    else
        cls.def_property(
            name, [member](View& v) { return toTuple(materialOf(v).*member); },
            [member, name, range](View& v, py::object x) {
                materialOf(v).*member = checked(fieldOf(v, name), toVec(x, fieldOf(v, name)), range);
                materialEdited(v);
            },
            doc);
}

// The material fields of the scene format (<properties> and the object's
// colours), on an object and on whitted.Material alike.
template <typename View>
void materialFields(py::class_<View>& cls) {
    materialField(cls, "diffuse_color", &Material::diffuseColor, kColourRange, "Cd");
    materialField(cls, "specular_color", &Material::specularColor, kColourRange, "Cs");
    materialField(cls, "checker_color", &Material::checkerColor, kColourRange, "the checker's second colour");
    materialField(cls, "absorption", &Material::absorption, xml::kNonNegative, "Beer-Lambert sigma per unit length");
    materialField(cls, "transmission_color", &Material::transmissionColor, kColourRange, "tints refracted light");
    materialField(cls, "emission", &Material::emission, xml::kNonNegative, "added where a ray hits");
    materialField(cls, "ambient", &Material::ambient, kColourRange, "ka");
    materialField(cls, "diffuse", &Material::diffuse, kColourRange, "kd");
    materialField(cls, "specular", &Material::specular, kColourRange, "ks");
    materialField(cls, "shininess", &Material::shininess, kShininess, "Phong exponent");
    materialField(cls, "reflection", &Material::reflection, kColourRange, "kr");
    materialField(cls, "transmission", &Material::transmission, kColourRange, "kt");
    materialField(cls, "ior", &Material::ior, kIor, "index of refraction");
    materialField(cls, "texture_scale", &Material::textureScale, xml::kPositive, "a plane's texture repeat length");
    materialField(cls, "normal_strength", &Material::normalStrength, kNormalStrength, "normal map strength");
    materialField(cls, "roughness", &Material::roughness, kColourRange,
                  "glossy reflection and refraction in [0, 1] (<roughness>); 0: a mirror");
    cls.def_property(
        "fresnel", [](View& v) { return materialOf(v).fresnel; },
        [](View& v, bool f) {
            materialOf(v).fresnel = f;
            materialEdited(v);
        },
        "reflection as Schlick's Fresnel term with kr as F0");
    cls.def_property(
        "ambient_color",
        [](View& v) -> py::object {
            const Material& m = materialOf(v);
            return m.ambientColor ? py::object(toTuple(*m.ambientColor)) : py::object(py::none());
        },
        [](View& v, py::object x) {
            if (x.is_none()) materialOf(v).ambientColor.reset();
            else materialOf(v).ambientColor = checked(fieldOf(v, "ambient_color"), toVec(x, fieldOf(v, "ambient_color")), kColourRange);
            materialEdited(v);
        },
        "the ambient term's colour (<ambient_color>); None: Cd");
}

// ---- Building: the shapes of the scene format, checked as the loader checks them ----
//
// What is stored is what the scene writer writes and the loader reads back
// bit for bit (Scene.save): positions as the loader places them (origin +
// <position>, which turns -0 into 0), directions divided by their length
// until that changes nothing (the loader's xml::direction divides again),
// a box's corner as <position> + <size> would give it again.

// A name the saved file gives back as it is: the loader trims a <name>'s
// text, and XML 1.0 has no control characters but tab and line breaks.
std::string checkedName(const std::string& field, const py::object& name) {
    if (name.is_none()) return {};
    if (!py::isinstance<py::str>(name)) throw py::type_error(field + ": expected a string or None, got " + py::repr(name).cast<std::string>());
    std::string n = name.cast<std::string>();
    bool control = std::any_of(n.begin(), n.end(), [](char c) { return (unsigned char)c < 0x20 && c != '\t' && c != '\n' && c != '\r'; });
    if (control || xml::trimmed(n) != n)
        refuse(field, "text without control characters or surrounding whitespace", py::repr(name).cast<std::string>());
    return n;
}

glm::dvec3 placed(const glm::dvec3& v) { return glm::dvec3(0) + v; }

glm::dvec3 loaderDirection(const std::string& field, glm::dvec3 v) {
    checked(field, v, xml::kAnyValue);
    double length = glm::length(v);
    if (!(length > xml::kMinLength)) refuse(field, "a non-zero direction", py::repr(toTuple(v)).cast<std::string>());
    v /= length;
    for (int i = 0; i < 8; ++i) {
        glm::dvec3 again = v / glm::length(v);
        if (again == v) break;
        v = again;
    }
    return v;
}

// Where a checker's cells start so that the saved file anchors them the
// same: the <position> the writer writes (none for triangles and inline
// meshes, whose vertices it writes in world space).
glm::dvec3 builtCheckerAnchor(const Shape& shape) {
    const Mesh* mesh = std::get_if<Mesh>(&shape);
    if (std::holds_alternative<Triangle>(shape) || (mesh && !mesh->source)) return glm::dvec3(0);
    return checkerAnchor(shape);
}

// A material given to an object: a copy, its checker anchored on the
// object; textures only where the object has texture coordinates (the loader's rule).
Material materialFor(const Shape& shape, const py::object& material, const std::string& field) {
    if (material.is_none()) return Material{};
    if (!py::isinstance<MaterialValue>(material))
        throw py::type_error(field + ": expected a whitted.Material or None, got " + py::repr(material).cast<std::string>());
    Material m = material.cast<const MaterialValue&>().m;
    if (m.checkerSize > 0) m.checkerOrigin = builtCheckerAnchor(shape);
    const Mesh* mesh = std::get_if<Mesh>(&shape);
    if (m.textured() && (std::holds_alternative<Triangle>(shape) || (mesh && mesh->uvs.empty())))
        refuse(field, "a material without textures for a " + std::string(shapeName(shape)) + " without uvs", "a textured one");
    return m;
}

ObjectView addObject(const SceneRef& s, Shape shape, const py::object& material, const py::object& name,
                     const std::string& call) {
    Object o;
    o.material = materialFor(shape, material, call + ".material");
    o.shape = std::move(shape);
    o.name = checkedName(call + ".name", name);
    s->scene->objects.push_back(std::move(o));
    s->objectIds.push_back(s->nextObjectId++);
    ++s->versions.geometry;  // a new renderer scene: geometry, BVH, materials, lights
    return ObjectView{s, s->objectIds.back()};
}

std::string shapeText(const py::array& a) {
    std::string t = "shape (";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) t += (i ? ", " : "") + std::to_string(a.shape(i));
    return t + (a.ndim() == 1 ? ",)" : ")");
}

using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;

// An (N, columns) array of floats, or ValueError naming the field.
Rows floatRows(const py::object& x, py::ssize_t columns, const std::string& field) {
    std::string expected = "an (N, " + std::to_string(columns) + ") array of numbers";
    py::array any = py::array::ensure(x);
    if (!any) refuse(field, expected, py::repr(x).cast<std::string>());
    char kind = any.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u') refuse(field, expected, "dtype " + py::str(any.dtype()).cast<std::string>());
    Rows a = Rows::ensure(any);
    if (a.ndim() != 2 || a.shape(1) != columns || a.shape(0) == 0) refuse(field, expected, shapeText(a));
    return a;
}

// A 4x4 affine transform (the last row 0 0 0 1), finite, within ±1e6, its
// 3x3 part invertible: the XML format's <matrix>.
glm::dmat4 transformMatrix(const py::object& x, const std::string& field) {
    auto a = floatRows(x, 4, field);
    if (a.shape(0) != 4) refuse(field, "a 4x4 matrix", shapeText(a));
    glm::dmat4 m(1.0);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            double v = a.at(r, c);
            if (!(std::abs(v) <= xml::kMaxMagnitude)) refuse(field, "numbers within ±1e6", "M[" + std::to_string(r) + ", " + std::to_string(c) + "] = " + shown(v));
            m[c][r] = v;
        }
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
        refuse(field, "an affine matrix (last row 0 0 0 1)", "last row (" + shown(m[0][3]) + ", " + shown(m[1][3]) + ", " + shown(m[2][3]) + ", " + shown(m[3][3]) + ")");
    double det = glm::determinant(glm::dmat3(m));
    if (!(std::abs(det) > 0) || !std::isfinite(det)) refuse(field, "invertible (its 3x3 part)", "determinant " + shown(det));
    return m;
}

glm::dvec3 row3(const Rows& a, py::ssize_t i) { return {a.at(i, 0), a.at(i, 1), a.at(i, 2)}; }

Mesh buildMesh(const py::object& vertices, const py::object& faces, const py::object& normals, const py::object& uvs,
               const py::object& transform) {
    auto V = floatRows(vertices, 3, "add_mesh.vertices");
    const py::ssize_t n = V.shape(0);
    py::array anyFaces = py::array::ensure(faces);
    if (!anyFaces || (anyFaces.dtype().kind() != 'i' && anyFaces.dtype().kind() != 'u'))
        refuse("add_mesh.faces", "an (M, 3) array of integers", anyFaces ? "dtype " + py::str(anyFaces.dtype()).cast<std::string>() : py::repr(faces).cast<std::string>());
    auto F = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(anyFaces);
    if (F.ndim() != 2 || F.shape(1) != 3 || F.shape(0) == 0) refuse("add_mesh.faces", "an (M, 3) array of integers, M >= 1", shapeText(F));
    std::optional<Rows> N, UV;
    if (!normals.is_none()) {
        N = floatRows(normals, 3, "add_mesh.normals");
        if (N->shape(0) != n) refuse("add_mesh.normals", "one per vertex, (" + std::to_string(n) + ", 3)", shapeText(*N));
    }
    if (!uvs.is_none()) {
        UV = floatRows(uvs, 2, "add_mesh.uvs");
        if (UV->shape(0) != n) refuse("add_mesh.uvs", "one per vertex, (" + std::to_string(n) + ", 2)", shapeText(*UV));
    }
    std::optional<glm::dmat4> M;
    if (!transform.is_none()) M = transformMatrix(transform, "add_mesh.transform");
    const glm::dmat3 normalLinear = M ? glm::transpose(glm::inverse(glm::dmat3(*M))) : glm::dmat3(1.0);
    const bool flip = M && glm::determinant(glm::dmat3(*M)) < 0;

    std::vector<glm::dvec3> world(static_cast<size_t>(n)), normal(N ? static_cast<size_t>(n) : 0);
    std::vector<glm::dvec2> uv(UV ? static_cast<size_t>(n) : 0);
    for (py::ssize_t i = 0; i < n; ++i) {
        const std::string at = "[" + std::to_string(i) + "]";
        glm::dvec3 v = checked("add_mesh.vertices" + at, row3(V, i), xml::kAnyValue);
        if (M) {
            v = glm::dvec3(*M * glm::dvec4(v, 1.0));
            checked("add_mesh.vertices" + at + " transformed", v, xml::kAnyValue);
        }
        world[size_t(i)] = v;
        if (N) {
            // As the loader: a unit normal as given, any other divided by its length.
            glm::dvec3 nv = checked("add_mesh.normals" + at, row3(*N, i), xml::kAnyValue);
            if (std::abs(glm::length(nv) - 1.0) > 1e-9) nv = loaderDirection("add_mesh.normals" + at, nv);
            if (M) nv = glm::normalize(normalLinear * nv);
            normal[size_t(i)] = nv;
        }
        if (UV) {
            for (int k = 0; k < 2; ++k)
                if (!(std::abs(UV->at(i, k)) <= xml::kMaxMagnitude))
                    refuse("add_mesh.uvs" + at, "2 numbers each " + xml::kAnyValue.describe(), "(" + shown(UV->at(i, 0)) + ", " + shown(UV->at(i, 1)) + ")");
            uv[size_t(i)] = {UV->at(i, 0), UV->at(i, 1)};
        }
    }
    Mesh mesh;
    size_t skipped = 0;
    for (py::ssize_t f = 0; f < F.shape(0); ++f) {
        std::array<size_t, 3> idx{};
        for (int k = 0; k < 3; ++k) {
            int64_t j = F.at(f, k);
            if (j < 0 || j >= n)
                refuse("add_mesh.faces[" + std::to_string(f) + "]", "vertex indices in [0, " + std::to_string(n - 1) + "]", std::to_string(j));
            idx[size_t(k)] = size_t(j);
        }
        if (flip) std::swap(idx[1], idx[2]);
        Triangle t{world[idx[0]], world[idx[1]], world[idx[2]]};
        if (degenerate(t)) {
            ++skipped;
            continue;
        }
        mesh.triangles.push_back(t);
        if (N) mesh.normals.push_back({normal[idx[0]], normal[idx[1]], normal[idx[2]]});
        if (UV) mesh.uvs.push_back({uv[idx[0]], uv[idx[1]], uv[idx[2]]});
    }
    if (mesh.triangles.empty()) refuse("add_mesh.faces", "at least one face that is not degenerate", "none");
    if (skipped > 0) {
        std::string text = "add_mesh: " + std::to_string(skipped) + " degenerate face(s) skipped";
        if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) throw py::error_already_set();
    }
    return mesh;
}

// The area-light fields (scenes/README.md "Area lights"), checked as the
// XML loader checks them: `prefix` is "add_light" or "Light".
void setRadius(const std::string& prefix, Light& l, double radius) {
    if (radius != 0.0 && l.type != Light::Type::Point && l.type != Light::Type::Spot)
        refuse(prefix + ".radius", std::string("0 for a ") + lightTypeName(l.type) + " light (only point and spot lights are spheres)", shown(radius));
    l.radius = checked(prefix + ".radius", radius, kLightRadiusRange);
    if (!l.area()) l.shadowSamples = 1;  // a point again: one shadow ray, as the saved file reads back
}
void setRectEdges(const std::string& field, Light& l, const glm::dvec3& u, const glm::dvec3& v) {
    if (l.type != Light::Type::Rect) refuse(field, std::string("None for a ") + lightTypeName(l.type) + " light (only a rect light has edges)", "a value");
    checked(field, u, xml::kAnyValue);
    checked(field, v, xml::kAnyValue);
    if (!rectEdgesSpan(u, v)) refuse(field, "edges u and v that are neither zero nor parallel", "(" + shown(u.x) + ", " + shown(u.y) + ", " + shown(u.z) + ") and (" + shown(v.x) + ", " + shown(v.y) + ", " + shown(v.z) + ")");
    l.u = u;
    l.v = v;
}
void setShadowSamples(const std::string& prefix, Light& l, int samples) {
    if (samples < 1 || samples > kMaxShadowSamples) refuse(prefix + ".shadow_samples", "in 1.." + std::to_string(kMaxShadowSamples), std::to_string(samples));
    if (samples != 1 && !l.area()) refuse(prefix + ".shadow_samples", "1 for a light without area (a point or spot light of radius 0, a directional light)", std::to_string(samples));
    l.shadowSamples = samples;
}

// The area-light arguments of add_light.
struct AreaArguments {
    double radius;
    int shadowSamples;
    py::object u, v;
    bool twoSided;
};

Light buildLight(const py::object& position, const py::object& color, const std::string& type, double intensity,
                 const std::string& falloff, const py::object& direction, const py::object& inner,
                 const py::object& outer, const py::object& name, const AreaArguments& area) {
    Light l;
    if (type == "point") l.type = Light::Type::Point;
    else if (type == "spot") l.type = Light::Type::Spot;
    else if (type == "directional") l.type = Light::Type::Directional;
    else if (type == "rect") l.type = Light::Type::Rect;
    else refuse("add_light.type", "'point', 'spot', 'directional' or 'rect'", "'" + type + "'");
    if (l.type == Light::Type::Directional) {
        if (!position.is_none()) refuse("add_light.position", "None for a directional light (it has no position)", py::repr(position).cast<std::string>());
    } else {
        if (position.is_none()) refuse("add_light.position", "3 numbers (required for a " + type + " light)", "None");
        l.position = checked("add_light.position", toVec(position, "add_light.position"), xml::kAnyValue);
    }
    l.color = checked("add_light.color", toVec(color, "add_light.color"), xml::kNonNegative);
    l.intensity = checked("add_light.intensity", intensity, xml::kNonNegative);
    if (falloff == "inverse_square") l.falloff = Light::Falloff::InverseSquare;
    else if (falloff != "none") refuse("add_light.falloff", "'none' or 'inverse_square'", "'" + falloff + "'");
    if (l.type == Light::Type::Directional && l.falloff != Light::Falloff::None)
        refuse("add_light.falloff", "'none' for a directional light (its light does not weaken with distance)", "'" + falloff + "'");
    if (l.type == Light::Type::Point || l.type == Light::Type::Rect) {
        if (!direction.is_none()) refuse("add_light.direction", "None for a " + type + " light (only spot and directional lights have one)", py::repr(direction).cast<std::string>());
    } else {
        if (direction.is_none()) refuse("add_light.direction", "3 numbers (required for a " + type + " light)", "None");
        l.direction = loaderDirection("add_light.direction", toVec(direction, "add_light.direction"));
    }
    if (l.type != Light::Type::Spot) {
        if (!inner.is_none() || !outer.is_none()) refuse(inner.is_none() ? "add_light.outer_angle" : "add_light.inner_angle", "None for a " + type + " light (only a spot light has a cone)", "a number");
    } else {
        if (!inner.is_none()) l.innerAngleDegrees = checked("add_light.inner_angle", inner.cast<double>(), kInnerAngleRange);
        if (!outer.is_none()) l.outerAngleDegrees = checked("add_light.outer_angle", outer.cast<double>(), kOuterAngleRange);
        if (!(l.innerAngleDegrees < l.outerAngleDegrees))
            refuse("add_light.outer_angle", "greater than inner_angle (" + shown(l.innerAngleDegrees) + ")", shown(l.outerAngleDegrees));
    }
    setRadius("add_light", l, area.radius);
    if (l.type == Light::Type::Rect) {
        if (area.u.is_none() || area.v.is_none()) refuse(area.u.is_none() ? "add_light.u" : "add_light.v", "3 numbers (required for a rect light)", "None");
        setRectEdges("add_light.v", l, toVec(area.u, "add_light.u"), toVec(area.v, "add_light.v"));
        l.twoSided = area.twoSided;
    } else if (!area.u.is_none() || !area.v.is_none() || area.twoSided) {
        refuse(!area.u.is_none() ? "add_light.u" : !area.v.is_none() ? "add_light.v" : "add_light.two_sided", "left out for a " + type + " light (only a rect light has edges and faces)", "a value");
    }
    setShadowSamples("add_light", l, area.shadowSamples);
    l.name = checkedName("add_light.name", name);
    return l;
}

// ---- Textures on a Material: a file, or a numpy array ----

// A texture slot's value: a path (read as the loader reads <diffuse_texture>,
// relative to the working folder) or an (H, W, 3|4) array, uint8 (sRGB-encoded
// like a PNG's bytes; a normal map's as stored) or float (linear like an EXR's
// values), kept as the PNG or EXR file save() writes beside the scene
// (io/texture_file.h textureFromImagePixels). Checked here with the field's
// name before the image writers see it: the loader's limits (kMaxTextureTexels,
// the image side, half floats).
TextureRef textureValue(const py::object& x, TextureEncoding encoding, const std::string& field) {
    if (x.is_none()) return {};
    if (py::isinstance<py::str>(x) || py::hasattr(x, "__fspath__")) {
        std::filesystem::path path = std::filesystem::absolute(x.cast<std::filesystem::path>());
        try {
            return {path.string(), std::make_shared<const TextureData>(readTextureFile(path, encoding))};
        } catch (const TextureFileError& e) {
            throw py::value_error(field + ": texture file \"" + path.string() + "\" " + e.what());
        }
    }
    const std::string expected = "a file path or an (H, W, 3) or (H, W, 4) array of uint8 (sRGB) or floats (linear)";
    py::array any = py::array::ensure(x);
    if (!any) refuse(field, expected, py::repr(x).cast<std::string>());
    const char kind = any.dtype().kind();
    const bool eightBit = kind == 'u' && any.itemsize() == 1;
    if (!eightBit && kind != 'f') refuse(field, expected, "dtype " + py::str(any.dtype()).cast<std::string>());
    if (any.ndim() != 3 || (any.shape(2) != 3 && any.shape(2) != 4) || any.shape(0) < 1 || any.shape(1) < 1)
        refuse(field, expected, shapeText(any));
    const py::ssize_t h = any.shape(0), w = any.shape(1), channels = any.shape(2);
    if (double(h) > kImageSide.hi || double(w) > kImageSide.hi || size_t(h) * size_t(w) > kMaxTextureTexels)
        refuse(field, "at most 16384 texels a side and 2^26 (8192x8192) in all", shapeText(any));
    auto pixels = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(any);
    std::span<const float> values(pixels.data(), size_t(pixels.size()));
    for (size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]) || std::abs(values[i]) > kMaxHalf)
            refuse(field, "finite values within ±65504 (the device's half floats)",
                   shown(values[i]) + " at texel " + std::to_string(i / size_t(channels)));
    try {
        return {"", std::make_shared<const TextureData>(textureFromImagePixels(
                        int(w), int(h), int(channels), values, eightBit, encoding, field + " (array)"))};
    } catch (const TextureFileError& e) {
        throw py::value_error(field + ": the array " + e.what());
    }
}

// The texture slots, in Material::textures()' order, and how each is read
// (the loader's readTextures: colour maps sRGB-decoded, normal maps as data).
struct TextureSlot {
    const char* name;
    TextureEncoding encoding;
};
constexpr TextureSlot kTextureSlots[] = {{"diffuse_texture", TextureEncoding::Colour},
                                         {"normal_map", TextureEncoding::Data},
                                         {"emission_texture", TextureEncoding::Colour},
                                         {"roughness_texture", TextureEncoding::Data}};

// Whether the scene has a texture that to_xml() could not name: one made
// from an array (save() writes it as a file), on an object of its own (a
// model file's objects bring their own textures back with the file).
void refuseFilelessTextures(const Scene& scene, const std::string& call) {
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        const Mesh* mesh = std::get_if<Mesh>(&o.shape);
        if (mesh && mesh->source) continue;
        for (const TextureRef* t : o.material.textures())
            if (*t && t->written.empty())
                throw py::value_error(call + ": object " + std::to_string(i) + (o.name.empty() ? "" : " ('" + o.name + "')") +
                                      " has a texture made from an array, which has no file for the XML to name; "
                                      "save(path) writes it beside the scene file");
    }
}

// Scene.add_file: the objects a model file gives as the scene format's
// <file> element gives them, read by the loader itself from a one-object
// scene text (scene/mesh_objects.h readMeshObject: parts, placement by
// <matrix>, the file's materials, one object per material), so that what
// save() writes (that <file> again) loads back to the same objects.
std::vector<Object> fileObjects(const std::filesystem::path& path, const py::object& part, const py::object& transform) {
    std::string file = escapedXml(std::filesystem::absolute(path).lexically_normal().string());
    std::string element = "<file>" + file + "</file>";
    if (!part.is_none()) {
        if (!py::isinstance<py::str>(part)) throw py::type_error("add_file.part: expected a string or None, got " + py::repr(part).cast<std::string>());
        element = "<file part=\"" + escapedXml(part.cast<std::string>()) + "\">" + file + "</file>";
    }
    if (!transform.is_none()) {
        glm::dmat4 m = transformMatrix(transform, "add_file.transform");
        std::string rows;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) rows += (rows.empty() ? "" : " ") + xmlNumber(m[c][r]);
        element += "<matrix>" + rows + "</matrix>";
    }
    const std::string text =
        "<scene><camera><position x=\"0\" y=\"0\" z=\"0\"/><window_position x=\"0\" y=\"0\" z=\"-1\"/></camera>"
        "<lights><light><position x=\"0\" y=\"0\" z=\"0\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>"
        "<objects><object><properties><type>mesh</type>" + element + "</properties></object></objects></scene>";
    Scene loaded;
    try {
        py::gil_scoped_release release;
        loaded = loadSceneFromString(text, std::filesystem::current_path() / "<add_file>");
    } catch (const SceneError& e) {
        throw py::value_error("add_file: " + e.message());
    }
    for (const std::string& warning : loaded.warnings) {
        // Without the place in the made-up text ("<add_file>:1: ").
        const std::string place = "<add_file>:1: ";
        std::string w = "add_file: " + (warning.find(place) == std::string::npos
                                             ? warning
                                             : warning.substr(warning.find(place) + place.size()));
        if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
    }
    for (Object& o : loaded.objects) o.sourceLine = 0;
    return std::move(loaded.objects);
}

// whitted.Mesh: the arrays add_mesh takes, held together (from_trimesh
// fills them from a trimesh.Trimesh), checked when added.
struct MeshArrays {
    py::object vertices, faces, normals, uvs;
};

// whitted.SceneError; a strong reference kept for the process's life (never
// released by a static destructor after the interpreter has gone).
PyObject* sceneError = nullptr;

}  // namespace

void addSceneApi(py::module_& m) {
    // SceneError(ValueError): .file, .line, .message; str() is the text the CLI prints.
    sceneError = PyErr_NewExceptionWithDoc(
        "whitted.SceneError",
        "A refused scene or model file: .file, .line (0 when none applies), .message; "
        "str() is 'FILE:LINE: message', as `whitted render` prints it.",
        PyExc_ValueError, nullptr);
    if (!sceneError) throw py::error_already_set();
    m.attr("SceneError") = py::handle(sceneError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const SceneError& e) {
            py::object err = py::handle(sceneError)(e.what());
            err.attr("file") = e.file();
            err.attr("line") = e.line();
            err.attr("message") = e.message();
            PyErr_SetObject(sceneError, err.ptr());
        }
    });

    py::class_<CameraView>(m, "Camera", "The scene's pinhole camera (a view: edits change the scene)")
        .def_property(
            "position", [](const CameraView& v) { return toTuple(v.c().eye); },
            [](const CameraView& v, py::object x) {
                setCameraFrame(v.c(), &Camera::eye, checked("Camera.position", toVec(x, "Camera.position"), xml::kAnyValue),
                               "Camera.position");
                v.edited();
            },
            "the eye")
        .def_property(
            "look_at", [](const CameraView& v) { return toTuple(v.c().windowCenter); },
            [](const CameraView& v, py::object x) {
                setCameraFrame(v.c(), &Camera::windowCenter,
                               checked("Camera.look_at", toVec(x, "Camera.look_at"), xml::kAnyValue), "Camera.look_at");
                v.edited();
            },
            "the point the camera looks at (the image plane's centre)")
        .def_property(
            "up", [](const CameraView& v) { return toTuple(v.c().up); },
            [](const CameraView& v, py::object x) {
                setCameraFrame(v.c(), &Camera::up, unit("Camera.up", toVec(x, "Camera.up")), "Camera.up");
                v.edited();
            },
            "the up direction (any length but 0)")
        .def_property(
            "fov", [](const CameraView& v) { return v.c().verticalFovDegrees; },
            [](const CameraView& v, double x) {
                v.c().verticalFovDegrees = checked("Camera.fov", x, kFov);
                v.edited();
            },
            "vertical field of view in degrees")
        .def_property(
            "width", [](const CameraView& v) { return v.c().width; },
            [](const CameraView& v, int x) {
                v.c().width = int(checked("Camera.width", x, kImageSide));
                v.edited();
            },
            "image width in pixels (the render's default)")
        .def_property(
            "height", [](const CameraView& v) { return v.c().height; },
            [](const CameraView& v, int x) {
                v.c().height = int(checked("Camera.height", x, kImageSide));
                v.edited();
            },
            "image height in pixels (the render's default)")
        .def_property(
            "projection",
            [](const CameraView& v) {
                return std::string(v.c().projection == Camera::Projection::Orthographic ? "orthographic" : "perspective");
            },
            [](const CameraView& v, const std::string& p) {
                if (p != "perspective" && p != "orthographic")
                    refuse("Camera.projection", "'perspective' or 'orthographic'", "'" + p + "'");
                v.c().projection = p == "orthographic" ? Camera::Projection::Orthographic : Camera::Projection::Perspective;
                v.edited();
            },
            "'perspective' (fov) or 'orthographic' (window_height), as <projection>")
        .def_property(
            "window_height", [](const CameraView& v) { return v.c().windowHeight; },
            [](const CameraView& v, double x) {
                v.c().windowHeight = checked("Camera.window_height", x, xml::kPositive);
                v.edited();
            },
            "an orthographic camera's window height in scene units (<window_height>)")
        .def_property(
            "aperture_radius", [](const CameraView& v) { return v.c().apertureRadius; },
            [](const CameraView& v, double x) {
                v.c().apertureRadius = checked("Camera.aperture_radius", x, xml::kNonNegative);
                v.edited();
            },
            "the thin lens's radius in scene units (<aperture_radius>); 0: a pinhole, everything sharp")
        .def_property(
            "focus_distance", [](const CameraView& v) { return v.c().focusDistanceOrDefault(); },
            [](const CameraView& v, py::object x) {
                if (x.is_none()) v.c().focusDistance.reset();
                else if (!py::isinstance<py::float_>(x) && !py::isinstance<py::int_>(x))
                    refuse("Camera.focus_distance", "a number or None", py::repr(x).cast<std::string>());
                else v.c().focusDistance = checked("Camera.focus_distance", x.cast<double>(), xml::kPositive);
                v.edited();
            },
            "the distance of the plane in focus along the view (<focus_distance>); None: look_at's distance")
        .def("__repr__", [](const CameraView& v) {
            return "Camera(position=" + py::repr(toTuple(v.c().eye)).cast<std::string>() +
                   ", look_at=" + py::repr(toTuple(v.c().windowCenter)).cast<std::string>() +
                   ", fov=" + shown(v.c().verticalFovDegrees) + ")";
        });

    py::class_<ObjectView> object(m, "Object", "An object of a scene (a view: edits change the scene)");
    object
        .def_property(
            "material", [](const ObjectView& v) { return MaterialValue{v.o().material}; },
            [](const ObjectView& v, py::object m) {
                Object& o = v.o();
                o.material = materialFor(o.shape, m.is_none() ? py::cast(MaterialValue{}) : m, "Object.material");
                ++v.s->versions.materials;
            },
            "a copy of its material (a whitted.Material); assigning one copies it in")
        .def_property(
            "name", [](const ObjectView& v) { return v.o().name; },
            [](const ObjectView& v, py::object n) { v.o().name = checkedName("Object.name", n); }, "optional name (<name>)")
        .def_property_readonly("type", [](const ObjectView& v) { return std::string(shapeName(v.o().shape)); },
                               "sphere, cylinder, plane, triangle, box, mesh or csg")
        .def_property_readonly("line", [](const ObjectView& v) { return v.o().sourceLine; },
                               "line of its <object> in the scene file (0: none)")
        .def_property(
            "position", [](const ObjectView& v) { return toTuple(shapeReferencePoint(v.o().shape)); },
            [](const ObjectView& v, py::object x) {
                Object& o = v.o();
                glm::dvec3 to = checked("Object.position", toVec(x, "Object.position"), xml::kAnyValue);
                glm::dvec3 delta = to - shapeReferencePoint(o.shape);
                o.material.checkerOrigin += delta;  // the checker moves with the object (as in the editor)
                translateShape(o.shape, delta);
                ++v.s->versions.geometry;
            },
            "its <position>: a sphere's centre, a box's corner, a mesh's placement...")
        .def_property(
            "transform",
            [](const ObjectView& v) {
                v.index();  // KeyError for a removed object
                auto it = v.s->transforms.find(v.id);
                glm::dmat4 m = it == v.s->transforms.end() ? glm::dmat4(1.0) : it->second;
                py::array_t<double> a({4, 4});
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c) a.mutable_at(r, c) = m[c][r];
                return a;
            },
            [](const ObjectView& v, py::object x) {
                Object& o = v.o();
                glm::dmat4 to = transformMatrix(x, "Object.transform");
                auto it = v.s->transforms.find(v.id);
                // From where it is now: the new transform after the old one undone.
                glm::dmat4 step = it == v.s->transforms.end() ? to : to * glm::inverse(it->second);
                Shape moved = o.shape;
                try {
                    transformShape(moved, step);
                } catch (const std::invalid_argument& e) {
                    throw py::value_error(std::string("Object.transform: ") + e.what());
                }
                o.shape = std::move(moved);
                o.material.checkerOrigin = glm::dvec3(step * glm::dvec4(o.material.checkerOrigin, 1.0));
                v.s->transforms[v.id] = to;
                ++v.s->versions.geometry;
            },
            "a 4x4 affine matrix placing the object relative to how it was added or loaded (identity until set); "
            "setting it moves the shape (scene/shape_edit.h transformShape)")
        .def_property(
            "radius",
            [](const ObjectView& v) -> py::object {
                if (const auto* s = std::get_if<Sphere>(&v.o().shape)) return py::float_(s->radius);
                if (const auto* c = std::get_if<Cylinder>(&v.o().shape)) return py::float_(c->radius);
                return py::none();
            },
            [](const ObjectView& v, double r) {
                Object& o = v.o();
                r = checked("Object.radius", r, xml::kPositive);
                if (auto* s = std::get_if<Sphere>(&o.shape)) s->radius = r;
                else if (auto* c = std::get_if<Cylinder>(&o.shape)) c->radius = r;
                else throw py::attribute_error(std::string("a ") + shapeName(o.shape) + " has no radius");
                ++v.s->versions.geometry;
            },
            "a sphere's or cylinder's radius (None for other shapes)")
        .def_property(
            "operation",
            [](const ObjectView& v) -> py::object {
                const auto* c = std::get_if<Csg>(&v.o().shape);
                if (!c) return py::none();
                const char* names[] = {"union", "intersection", "difference"};
                return py::str(names[int(c->operation)]);
            },
            [](const ObjectView& v, const std::string& op) {
                auto* c = std::get_if<Csg>(&v.o().shape);
                if (!c) throw py::attribute_error(std::string("a ") + shapeName(v.o().shape) + " has no operation");
                if (op == "union") c->operation = Csg::Operation::Union;
                else if (op == "intersection") c->operation = Csg::Operation::Intersection;
                else if (op == "difference") c->operation = Csg::Operation::Difference;
                else refuse("Object.operation", "union, intersection or difference", "'" + op + "'");
                ++v.s->versions.geometry;
            },
            "a csg object's operation (None for other shapes)")
        .def_property(
            "checker_size", [](const ObjectView& v) { return v.o().material.checkerSize; },
            [](const ObjectView& v, double x) {
                Object& o = v.o();
                if (x != 0) checked("Object.checker_size", x, xml::kPositive);
                if (o.material.checkerSize == 0 && x > 0) o.material.checkerOrigin = checkerAnchor(o.shape);
                o.material.checkerSize = x;
                ++v.s->versions.materials;
            },
            "solid checker cell size (> 0), 0: no checker");
    materialFields(object);
    object.def("__repr__", [](const ObjectView& v) {
        return "Object(" + std::to_string(v.index()) + ", type='" + shapeName(v.o().shape) + "', name='" + v.o().name + "')";
    });

    py::class_<LightView>(m, "Light", "A light of a scene (a view: edits change the scene)")
        .def_property_readonly("type", [](const LightView& v) { return std::string(lightTypeName(v.l().type)); })
        .def_property(
            "name", [](const LightView& v) { return v.l().name; },
            [](const LightView& v, py::object n) { v.l().name = checkedName("Light.name", n); })
        .def_property(
            "position", [](const LightView& v) { return toTuple(v.l().position); },
            [](const LightView& v, py::object x) {
                v.l().position = checked("Light.position", toVec(x, "Light.position"), xml::kAnyValue);
                ++v.s->versions.lights;
            })
        .def_property(
            "direction", [](const LightView& v) { return toTuple(v.l().direction); },
            [](const LightView& v, py::object x) {
                v.l().direction = unit("Light.direction", toVec(x, "Light.direction"));
                ++v.s->versions.lights;
            })
        .def_property(
            "color", [](const LightView& v) { return toTuple(v.l().color); },
            [](const LightView& v, py::object x) {
                v.l().color = checked("Light.color", toVec(x, "Light.color"), xml::kNonNegative);
                ++v.s->versions.lights;
            })
        .def_property(
            "intensity", [](const LightView& v) { return v.l().intensity; },
            [](const LightView& v, double x) {
                v.l().intensity = checked("Light.intensity", x, xml::kNonNegative);
                ++v.s->versions.lights;
            })
        .def_property(
            "radius", [](const LightView& v) { return v.l().radius; },
            [](const LightView& v, double x) {
                setRadius("Light", v.l(), x);
                ++v.s->versions.lights;
            },
            "a point or spot light's sphere radius (0: a point)")
        .def_property(
            "shadow_samples", [](const LightView& v) { return v.l().shadowSamples; },
            [](const LightView& v, int x) {
                setShadowSamples("Light", v.l(), x);
                ++v.s->versions.lights;
            },
            "an area light's shadow rays per camera sample")
        .def_property(
            "u", [](const LightView& v) { return toTuple(v.l().u); },
            [](const LightView& v, py::object x) {
                setRectEdges("Light.u", v.l(), toVec(x, "Light.u"), v.l().v);
                ++v.s->versions.lights;
            },
            "a rect light's first full edge")
        .def_property(
            "v", [](const LightView& v) { return toTuple(v.l().v); },
            [](const LightView& v, py::object x) {
                setRectEdges("Light.v", v.l(), v.l().u, toVec(x, "Light.v"));
                ++v.s->versions.lights;
            },
            "a rect light's second full edge; it faces u x v")
        .def_property(
            "two_sided", [](const LightView& v) { return v.l().twoSided; },
            [](const LightView& v, bool x) {
                if (v.l().type != Light::Type::Rect && x) refuse("Light.two_sided", "False for a " + std::string(lightTypeName(v.l().type)) + " light (only a rect light has faces)", "True");
                v.l().twoSided = x;
                ++v.s->versions.lights;
            },
            "whether a rect light shines from both faces")
        .def("__repr__", [](const LightView& v) {
            return "Light(" + std::to_string(v.index()) + ", type='" + lightTypeName(v.l().type) + "')";
        });

    py::class_<MaterialValue> material(m, "Material",
                                       "A material's values (the scene format's material fields); "
                                       "Material(diffuse_color=(1, 0, 0), specular=0.5, ...)");
    material.def(py::init([](py::kwargs fields) {
        py::object made = py::cast(MaterialValue{});
        for (auto [key, value] : fields) {
            std::string k = py::str(key);
            if (k.starts_with("_") || k == "textured" || !py::hasattr(made, key))
                throw py::type_error("Material: unknown field '" + k + "'");
            made.attr(key) = value;
        }
        return made.cast<MaterialValue>();
    }));
    materialFields(material);
    for (size_t k = 0; k < std::size(kTextureSlots); ++k) {
        const TextureSlot slot = kTextureSlots[k];
        material.def_property(
            slot.name,
            [k](const MaterialValue& v) -> py::object {
                const TextureRef& t = *v.m.textures()[k];
                if (!t) return py::none();
                if (!t.written.empty()) return py::str(t.written);
                const TextureLevel& level = t.data->levels[0];
                return py::str("<array " + std::to_string(level.height) + "x" + std::to_string(level.width) + ">");
            },
            [k, slot](MaterialValue& v, py::object x) {
                *v.m.textures()[k] = textureValue(x, slot.encoding, std::string("Material.") + slot.name);
            },
            (std::string(slot.name) + ": None, a file path, or an (H, W, 3|4) array (uint8 sRGB, float linear)").c_str());
    }
    material
        .def_property(
            "checker_size", [](const MaterialValue& v) { return v.m.checkerSize; },
            [](MaterialValue& v, double x) {
                if (x != 0) checked("Material.checker_size", x, xml::kPositive);
                v.m.checkerSize = x;
            },
            "solid checker cell size (> 0), 0: no checker (anchored at the object it is given to)")
        .def_property_readonly("textured", [](const MaterialValue& v) { return v.m.textured(); },
                               "whether it has textures")
        .def("__repr__", [](const MaterialValue& v) {
            return "Material(diffuse_color=" + py::repr(toTuple(v.m.diffuseColor)).cast<std::string>() +
                   ", diffuse=" + shown(v.m.diffuse) + ", specular=" + shown(v.m.specular) +
                   ", reflection=" + shown(v.m.reflection) + ", transmission=" + shown(v.m.transmission) + ")";
        });

    py::class_<MeshArrays>(m, "Mesh", "a triangle mesh's arrays for Scene.add_mesh: vertices (N, 3), faces (M, 3), "
                                      "normals (N, 3) or None, uvs (N, 2) or None")
        .def(py::init([](py::object vertices, py::object faces, py::object normals, py::object uvs) {
                 return MeshArrays{vertices, faces, normals, uvs};
             }),
             py::arg("vertices"), py::arg("faces"), py::arg("normals") = py::none(), py::arg("uvs") = py::none())
        .def_static(
            "from_trimesh",
            [](py::object mesh, bool normals) {
                // trimesh.Trimesh's attributes (read, not imported: any object that has them will do).
                for (const char* attribute : {"vertices", "faces"})
                    if (!py::hasattr(mesh, attribute))
                        throw py::type_error(std::string("Mesh.from_trimesh: expected a trimesh.Trimesh (with .vertices and .faces), got ") +
                                             py::repr(mesh).cast<std::string>());
                py::module_ np = py::module_::import("numpy");
                MeshArrays arrays{np.attr("asarray")(mesh.attr("vertices")), np.attr("asarray")(mesh.attr("faces")),
                                  py::none(), py::none()};
                // The vertex normals trimesh has (the file's, else its own from the faces).
                if (normals) arrays.normals = np.attr("asarray")(mesh.attr("vertex_normals"));
                // Texture coordinates where its visual has them (trimesh.visual.TextureVisuals.uv).
                py::object visual = py::getattr(mesh, "visual", py::none());
                py::object uv = visual.is_none() ? py::none() : py::getattr(visual, "uv", py::none());
                if (!uv.is_none()) arrays.uvs = np.attr("asarray")(uv);
                return arrays;
            },
            py::arg("mesh"), py::arg("normals") = true,
            "the arrays of a trimesh.Trimesh: vertices, faces, vertex_normals (normals=True) and visual.uv where it has them")
        .def_readwrite("vertices", &MeshArrays::vertices)
        .def_readwrite("faces", &MeshArrays::faces)
        .def_readwrite("normals", &MeshArrays::normals)
        .def_readwrite("uvs", &MeshArrays::uvs);

    py::class_<SceneHandle, SceneRef>(m, "Scene", "A scene: load() or loads() it, or build it (Scene()), edit it, render it")
        .def(py::init([] {
                 Scene scene;
                 scene.ambientLight = glm::dvec3(0);
                 return std::make_shared<SceneHandle>(std::move(scene));
             }),
             "an empty scene: the default camera, no lights, no objects, ambient light 0")
        .def(
            "add_sphere",
            [](const SceneRef& s, py::object center, double radius, py::object material, py::object name) {
                Sphere sphere{placed(checked("add_sphere.center", toVec(center, "add_sphere.center"), xml::kAnyValue)),
                              checked("add_sphere.radius", radius, xml::kPositive)};
                return addObject(s, sphere, material, name, "add_sphere");
            },
            py::arg("center"), py::arg("radius"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_box",
            [](const SceneRef& s, py::object min, py::object size, py::object material, py::object name) {
                glm::dvec3 lo = placed(checked("add_box.min", toVec(min, "add_box.min"), xml::kAnyValue));
                glm::dvec3 sz = checked("add_box.size", toVec(size, "add_box.size"), xml::kPositive);
                glm::dvec3 hi = lo + sz;
                for (int i = 0; i < 3; ++i)
                    if (!(lo[i] < hi[i]))
                        refuse("add_box.size", std::string("large enough to register beside min in ") + "xyz"[i], shown(sz[i]));
                for (int i = 0; i < 8; ++i) {  // what <position> + <size> gives back
                    glm::dvec3 again = lo + (hi - lo);
                    if (again == hi) break;
                    hi = again;
                }
                return addObject(s, Box{lo, hi}, material, name, "add_box");
            },
            py::arg("min"), py::arg("size"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_plane",
            [](const SceneRef& s, py::object point, py::object normal, py::object material, py::object name) {
                Plane plane{placed(checked("add_plane.point", toVec(point, "add_plane.point"), xml::kAnyValue)),
                            loaderDirection("add_plane.normal", toVec(normal, "add_plane.normal"))};
                return addObject(s, plane, material, name, "add_plane");
            },
            py::arg("point"), py::arg("normal"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_cylinder",
            [](const SceneRef& s, py::object base, py::object axis, double radius, double height, py::object material,
               py::object name) {
                Cylinder c{placed(checked("add_cylinder.base", toVec(base, "add_cylinder.base"), xml::kAnyValue)),
                           loaderDirection("add_cylinder.axis", toVec(axis, "add_cylinder.axis")),
                           checked("add_cylinder.radius", radius, xml::kPositive),
                           checked("add_cylinder.height", height, xml::kPositive)};
                return addObject(s, c, material, name, "add_cylinder");
            },
            py::arg("base"), py::arg("axis"), py::arg("radius"), py::arg("height"), py::arg("material") = py::none(),
            py::arg("name") = py::none())
        .def(
            "add_triangle",
            [](const SceneRef& s, py::object a, py::object b, py::object c, py::object material, py::object name) {
                Triangle t{placed(checked("add_triangle.a", toVec(a, "add_triangle.a"), xml::kAnyValue)),
                           placed(checked("add_triangle.b", toVec(b, "add_triangle.b"), xml::kAnyValue)),
                           placed(checked("add_triangle.c", toVec(c, "add_triangle.c"), xml::kAnyValue))};
                if (degenerate(t)) refuse("add_triangle.c", "a vertex off the line through a and b", "a degenerate triangle");
                return addObject(s, t, material, name, "add_triangle");
            },
            py::arg("a"), py::arg("b"), py::arg("c"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_mesh",
            [](const SceneRef& s, py::object vertices, py::object faces, py::object normals, py::object uvs,
               py::object material, py::object name, py::object transform) {
                if (py::isinstance<MeshArrays>(vertices)) {  // add_mesh(whitted.Mesh, ...): its arrays
                    if (!faces.is_none() || !normals.is_none() || !uvs.is_none())
                        throw py::type_error("add_mesh: a whitted.Mesh brings its own faces, normals and uvs");
                    const MeshArrays& arrays = vertices.cast<const MeshArrays&>();
                    vertices = arrays.vertices, faces = arrays.faces, normals = arrays.normals, uvs = arrays.uvs;
                }
                return addObject(s, buildMesh(vertices, faces, normals, uvs, transform), material, name, "add_mesh");
            },
            py::arg("vertices"), py::arg("faces") = py::none(), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
            py::arg("material") = py::none(), py::arg("name") = py::none(), py::arg("transform") = py::none(),
            "a triangle mesh from numpy arrays: vertices (N, 3), faces (M, 3) integers, normals (N, 3), uvs (N, 2), "
            "transform 4x4 (applied to vertices and normals); degenerate faces are skipped with a warning")
        .def(
            "add_file",
            [](const SceneRef& s, const std::filesystem::path& path, py::object part, py::object transform) {
                py::list handles;
                for (Object& o : fileObjects(path, part, transform)) {
                    s->scene->objects.push_back(std::move(o));
                    s->objectIds.push_back(s->nextObjectId++);
                    handles.append(ObjectView{s, s->objectIds.back()});
                }
                ++s->versions.geometry;
                return handles;
            },
            py::arg("path"), py::arg("part") = py::none(), py::arg("transform") = py::none(),
            "a model file's objects as the scene format's <file> gives them (part: <file part>, transform: a 4x4 "
            "affine <matrix>); a list of handles, one per material of the file")
        .def(
            "add_light",
            [](const SceneRef& s, py::object position, py::object color, const std::string& type, double intensity,
               const std::string& falloff, py::object direction, py::object inner, py::object outer, py::object name,
               double radius, int shadowSamples, py::object u, py::object v, bool twoSided) {
                s->scene->lights.push_back(buildLight(position, color, type, intensity, falloff, direction, inner,
                                                      outer, name, {radius, shadowSamples, u, v, twoSided}));
                s->lightIds.push_back(s->nextLightId++);
                ++s->versions.geometry;  // the light count changed: the renderer takes the scene anew
                return LightView{s, s->lightIds.back()};
            },
            py::arg("position") = py::none(), py::arg("color") = py::make_tuple(1.0, 1.0, 1.0),
            py::arg("type") = "point", py::arg("intensity") = 1.0, py::arg("falloff") = "none",
            py::arg("direction") = py::none(), py::arg("inner_angle") = py::none(),
            py::arg("outer_angle") = py::none(), py::arg("name") = py::none(), py::arg("radius") = 0.0,
            py::arg("shadow_samples") = 1, py::arg("u") = py::none(), py::arg("v") = py::none(),
            py::arg("two_sided") = false,
            "a point, spot, directional or rect light with the fields of <light>")
        .def(
            "remove",
            [](const SceneRef& s, py::object handle) {
                if (py::isinstance<ObjectView>(handle)) {
                    const ObjectView& v = handle.cast<const ObjectView&>();
                    if (v.s != s) throw py::key_error("the object is not in this scene");
                    size_t i = v.index();
                    s->scene->objects.erase(s->scene->objects.begin() + std::ptrdiff_t(i));
                    s->objectIds.erase(s->objectIds.begin() + std::ptrdiff_t(i));
                } else if (py::isinstance<LightView>(handle)) {
                    const LightView& v = handle.cast<const LightView&>();
                    if (v.s != s) throw py::key_error("the light is not in this scene");
                    size_t i = v.index();
                    s->scene->lights.erase(s->scene->lights.begin() + std::ptrdiff_t(i));
                    s->lightIds.erase(s->lightIds.begin() + std::ptrdiff_t(i));
                } else {
                    throw py::type_error("Scene.remove: expected an Object or a Light of the scene, got " +
                                         py::repr(handle).cast<std::string>());
                }
                ++s->versions.geometry;
            },
            py::arg("handle"), "removes an object or light; its handle then raises KeyError")
        .def(py::pickle(
            [](const SceneRef& s) {
                refuseFilelessTextures(*s->scene, "pickle");
                return py::make_tuple(sceneXml(*s->scene), s->scene->sourcePath);
            },
            [](const py::tuple& state) {
                if (py::len(state) != 2) throw py::value_error("Scene.__setstate__: expected (xml, path)");
                auto path = state[1].cast<std::filesystem::path>();
                Scene scene = loadSceneFromString(state[0].cast<std::string>(), path.empty() ? "<pickled scene>" : path);
                scene.sourcePath = path;
                return std::make_shared<SceneHandle>(std::move(scene));
            }))
        .def_property_readonly("camera", [](const SceneRef& s) { return CameraView{s}; })
        .def_property_readonly("objects",
                               [](const SceneRef& s) {
                                   py::list l;
                                   for (uint64_t id : s->objectIds) l.append(ObjectView{s, id});
                                   return l;
                               })
        .def_property_readonly("lights",
                               [](const SceneRef& s) {
                                   py::list l;
                                   for (uint64_t id : s->lightIds) l.append(LightView{s, id});
                                   return l;
                               })
        .def_property(
            "ambient_light", [](const SceneRef& s) { return toTuple(s->scene->ambientLight); },
            [](const SceneRef& s, py::object x) {
                s->scene->ambientLight = checked("Scene.ambient_light", toVec(x, "Scene.ambient_light"), xml::kNonNegative);
                ++s->versions.lights;
            })
        .def_property_readonly("path", [](const SceneRef& s) { return s->scene->sourcePath; })
        .def_property_readonly("warnings", [](const SceneRef& s) { return s->scene->warnings; })
        .def(
            "save",
            [](const SceneRef& s, const std::filesystem::path& path) {
                // Textures made from arrays: written beside the file, named in it
                // (on a copy: the scene's own stay without a file).
                Scene copy = *s->scene;
                writeFilelessTextures(copy, path);
                writeSceneFile(copy, path);
            },
            py::arg("path"),
            "writes the scene file (the scene writer: what the window's Save writes), and textures made from arrays "
            "beside it")
        .def(
            "to_xml",
            [](const SceneRef& s) {
                refuseFilelessTextures(*s->scene, "Scene.to_xml");
                return sceneXml(*s->scene);
            },
            "the scene file's text")
        .def("copy", &copyHandle,
             "an independent copy with the same object ids and transforms (textures are shared, read-only)")
        .def("__copy__", &copyHandle)
        .def("__deepcopy__", [](const SceneRef& s, py::dict) { return copyHandle(s); })
        .def("__repr__", [](const SceneRef& s) {
            return "Scene('" + s->scene->sourcePath.string() + "', " + std::to_string(s->scene->objects.size()) +
                   " objects, " + std::to_string(s->scene->lights.size()) + " lights)";
        });

    m.def(
        "load",
        [](const std::filesystem::path& path) {
            Scene scene;
            {
                py::gil_scoped_release release;
                scene = loadSceneOrModel(path);
            }
            return std::make_shared<SceneHandle>(std::move(scene));
        },
        py::arg("path"), "Loads a scene file (.xml) or a model file (a quick look); raises SceneError");
    m.def(
        "loads",
        [](const std::string& xmlText, const std::filesystem::path& baseDir) {
            return std::make_shared<SceneHandle>(loadSceneFromString(xmlText, baseDir / "<string>"));
        },
        py::arg("xml"), py::arg("base_dir") = ".",
        "Loads a scene from XML text; relative file names resolve against base_dir; raises SceneError");
}

}  // namespace whitted::python

// whitted.Material, a material's values not tied to a scene, and the
// material fields an Object shares with it (the scene format's <properties>
// and the object's colours); textures from files or numpy arrays.
#include "io/texture_file.h"
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/mesh_objects.h"
#include "scene/scene_loader.h"
#include "scene/shape_edit.h"

#include <pybind11/numpy.h>

#include <cmath>
#include <filesystem>
#include <span>
#include <string>
#include <type_traits>

namespace whitted::python {
namespace {


// The two holders of material fields: an object (an edit bumps its scene's
// materials counter) and a free Material.
Material& materialOf(const ObjectView& v) { return v.o().material; }
Material& materialOf(MaterialValue& v) { return v.m; }
void materialEdited(const ObjectView& v) { ++v.s->versions.materials; }
void materialEdited(MaterialValue&) {}
std::string fieldOf(const ObjectView&, const char* name) { return std::string("Object.") + name; }
std::string fieldOf(MaterialValue&, const char* name) { return std::string("Material.") + name; }

// A material field of an object: double or colour, with its range; an edit
// bumps the materials counter only.
template <typename View, typename T>
void materialField(py::class_<View>& cls, const char* name, T Material::*member, const Range& range,
                   const char* doc) {
    if constexpr (std::is_same_v<T, double>)
        cls.def_property(
            name, [member](View& v) { return materialOf(v).*member; },
            [member, name, range](View& v, Arg<double> x) {
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
    materialField(cls, "shininess", &Material::shininess, kShininessRange, "Phong exponent");
    materialField(cls, "reflection", &Material::reflection, kColourRange, "kr");
    materialField(cls, "transmission", &Material::transmission, kColourRange, "kt");
    materialField(cls, "ior", &Material::ior, kIorRange, "index of refraction");
    materialField(cls, "texture_scale", &Material::textureScale, xml::kPositive, "a plane's texture repeat length");
    materialField(cls, "normal_strength", &Material::normalStrength, kNormalStrength, "normal map strength");
    materialField(cls, "roughness", &Material::roughness, kColourRange,
                  "glossy reflection and refraction in [0, 1] (<roughness>); 0: a mirror");
    cls.def_property(
        "fresnel", [](View& v) { return materialOf(v).fresnel; },
        [](View& v, Arg<bool> f) {
            materialOf(v).fresnel = f.get(fieldOf(v, "fresnel"));
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

}  // namespace

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

namespace {

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

// Where a checker's cells start so that the saved file anchors them the
// same: the <position> the writer writes (none for triangles and inline
// meshes, whose vertices it writes in world space).
glm::dvec3 builtCheckerAnchor(const Shape& shape) {
    const Mesh* mesh = std::get_if<Mesh>(&shape);
    if (std::holds_alternative<Triangle>(shape) || (mesh && !mesh->source)) return glm::dvec3(0);
    return checkerAnchor(shape);
}

}  // namespace

void addMaterialFields(py::class_<ObjectView>& cls) { materialFields(cls); }
void addMaterialFields(py::class_<MaterialValue>& cls) { materialFields(cls); }

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
    if (scene.environment && scene.environment->image && scene.environment->imageWritten.empty())
        throw py::value_error(call + ": the environment has an image made from an array, which has no file for the "
                                     "XML to name; save(path) writes it beside the scene file");
}

void addMaterialApi(py::module_& m) {
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
            [](MaterialValue& v, Arg<double> arg) {
                double x = arg.get("Material.checker_size");
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
}

}  // namespace whitted::python

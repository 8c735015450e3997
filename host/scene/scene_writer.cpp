#include "scene/scene_writer.h"

#include <cctype>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "io/atomic_file.h"
#include "io/image_io.h"
#include "io/texture.h"

#include <glm/gtc/packing.hpp>

#include <functional>
#include <map>
#include <set>

namespace whitted {

std::string xmlNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

std::string escapedXml(const std::string& text) {
    std::string escaped;
    for (char c : text)
        escaped += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '"' ? "&quot;" : std::string(1, c);
    return escaped;
}

namespace {

class XmlOut {
public:
    void open(const std::string& tag) { line("<" + tag + ">"), ++depth_; }
    void close(const std::string& tag) { --depth_, line("</" + tag + ">"); }
    void value(const std::string& tag, const std::string& v) { line("<" + tag + ">" + v + "</" + tag + ">"); }
    void value(const std::string& tag, double v) { value(tag, xmlNumber(v)); }
    void vector(const std::string& tag, const glm::dvec3& v) {
        line("<" + tag + " x=\"" + xmlNumber(v.x) + "\" y=\"" + xmlNumber(v.y) + "\" z=\"" + xmlNumber(v.z) + "\"/>");
    }
    void colour(const std::string& tag, const glm::dvec3& c) {
        line("<" + tag + " r=\"" + xmlNumber(c.r) + "\" g=\"" + xmlNumber(c.g) + "\" b=\"" + xmlNumber(c.b) + "\"/>");
    }
    void line(const std::string& text) { out_ << std::string(size_t(2 * depth_), ' ') << text << "\n"; }
    void setDepth(int d) { depth_ = d; }
    std::string str() const { return out_.str(); }

private:
    std::ostringstream out_;
    int depth_ = 0;
};

void writeCamera(XmlOut& x, const Camera& c) {
    x.open("camera");
    x.vector("position", c.eye);
    x.vector("window_position", c.windowCenter);
    x.vector("up", c.up);
    bool k = c.intrinsics && c.projection == Camera::Projection::Perspective;
    if (c.projection == Camera::Projection::Orthographic) {
        x.value("projection", std::string("orthographic"));
        x.value("window_height", c.windowHeight);
    } else if (!k) {
        x.value("fov", c.verticalFovDegrees);
    }
    x.value("width", std::to_string(c.width));
    x.value("height", std::to_string(c.height));
    // K instead of the fov (scene/scene.h Camera::intrinsics).
    if (k)
        x.line("<intrinsics fx=\"" + xmlNumber(c.intrinsics->fx) + "\" fy=\"" + xmlNumber(c.intrinsics->fy) + "\" cx=\"" +
               xmlNumber(c.intrinsics->cx) + "\" cy=\"" + xmlNumber(c.intrinsics->cy) + "\"/>");
    // A pinhole (the default) writes no lens.
    if (c.apertureRadius > 0) x.value("aperture_radius", c.apertureRadius);
    if (c.focusDistance) x.value("focus_distance", *c.focusDistance);
    x.close("camera");
}

// A light; what is the default (a point light of intensity 1 without
// falloff: the seed's) is left out, so the seed's lights read as before.
void writeLight(XmlOut& x, const Light& l);

// Where the scene came from and where its text goes: file paths in it
// (textures, model files) are written relative to the destination's folder.
struct FilePlaces {
    std::filesystem::path sceneFolder;  // the folder relative paths in the loaded scene start from
    std::filesystem::path destination;  // the file written (empty: unknown, paths stay as they are)
};

std::string escapedXml(const std::string& text) {
    std::string escaped;
    for (char c : text)
        escaped += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '"' ? "&quot;" : std::string(1, c);
    return escaped;
}

// An absolute file path as the written scene names it: relative to the
// folder it is written to (absolute when that is unknown or on another root).
std::string fileText(const std::filesystem::path& absolute, const FilePlaces& places) {
    if (places.destination.empty()) return escapedXml(absolute.string());
    std::filesystem::path folder = std::filesystem::absolute(places.destination).parent_path();
    std::filesystem::path relative = absolute.lexically_relative(folder);
    return escapedXml(relative.empty() ? absolute.string() : relative.generic_string());
}

// A texture's path as the loaded scene wrote it, made relative to the new file.
std::string textureText(const TextureRef& texture, const FilePlaces& places) {
    std::filesystem::path path(texture.written);
    if (places.destination.empty()) return escapedXml(texture.written);
    if (path.is_relative()) path = places.sceneFolder / path;
    return fileText(std::filesystem::absolute(path).lexically_normal(), places);
}

// `diffuseTexture`: false for a model file whose own materials apply (its
// textures come back with them, and a <diffuse_texture> would stop them applying).
void writeMaterialProperties(XmlOut& x, const Material& m, const FilePlaces& places, bool diffuseTexture = true) {
    x.value("refraction_coef", m.ior);
    x.value("transmission_coef", m.transmission);
    x.value("specular_coef", m.specular);
    x.value("diffuse_coef", m.diffuse);
    x.value("ambiente_coef", m.ambient);
    x.value("shininess", m.shininess);
    x.value("reflection_coef", m.reflection);  // kr itself; <reflective> is left out
    if (m.checkerSize > 0) {
        x.colour("checker_color", m.checkerColor);
        x.value("checker_size", m.checkerSize);
    }
    if (m.absorption != glm::dvec3(0)) x.colour("absorption", m.absorption);
    // The additions for authored scenes, only where they are not the default.
    if (m.fresnel) x.value("fresnel", "true");
    if (m.transmissionColor != glm::dvec3(1)) x.colour("transmission_color", m.transmissionColor);
    if (m.emission != glm::dvec3(0)) x.colour("emission", m.emission);
    if (m.ambientColor) x.colour("ambient_color", *m.ambientColor);
    if (m.roughness > 0) x.value("roughness", m.roughness);
    // Texture files, relative to the written file's folder. (A model file's
    // own texture has no path to write: the file is written again as its
    // <file>, without a colour, and brings it back.)
    if (diffuseTexture && m.diffuseTexture && !m.diffuseTexture.written.empty())
        x.value("diffuse_texture", textureText(m.diffuseTexture, places));
    if (m.normalMap && !m.normalMap.written.empty()) {
        x.value("normal_map", textureText(m.normalMap, places));
        x.value("normal_strength", m.normalStrength);
    }
    if (m.emissionTexture && !m.emissionTexture.written.empty())
        x.value("emission_texture", textureText(m.emissionTexture, places));
    if (m.roughness > 0 && m.roughnessTexture && !m.roughnessTexture.written.empty())
        x.value("roughness_texture", textureText(m.roughnessTexture, places));
}

void writeLight(XmlOut& x, const Light& l) {
    x.open("light");
    if (l.type == Light::Type::Spot) x.value("type", "spot");
    if (l.type == Light::Type::Directional) x.value("type", "directional");
    if (l.type == Light::Type::Rect) x.value("type", "rect");
    if (!l.name.empty()) x.value("name", escapedXml(l.name));
    if (l.type != Light::Type::Directional) x.vector("position", l.position);
    x.colour("color", l.color);
    if (l.intensity != 1.0) x.value("intensity", l.intensity);
    if (l.falloff == Light::Falloff::InverseSquare && l.type != Light::Type::Directional)
        x.value("falloff", "inverse_square");
    if (l.type == Light::Type::Spot || l.type == Light::Type::Directional) x.vector("direction", l.direction);
    if (l.type == Light::Type::Spot) {
        x.value("inner_angle", l.innerAngleDegrees);
        x.value("outer_angle", l.outerAngleDegrees);
    }
    if (l.radius > 0.0 && (l.type == Light::Type::Point || l.type == Light::Type::Spot)) x.value("radius", l.radius);
    if (l.type == Light::Type::Rect) {
        x.vector("u", l.u);
        x.vector("v", l.v);
        if (l.twoSided) x.value("two_sided", "true");
    }
    if (l.area() && l.shadowSamples != 1) x.value("shadow_samples", l.shadowSamples);
    x.close("light");
}

// Vertices relative to `origin`, the <position> written for the object.
void writeTriangleVertices(XmlOut& x, const Triangle& t, const glm::dvec3& origin) {
    x.vector("vertex", t.v0 - origin);
    x.vector("vertex", t.v1 - origin);
    x.vector("vertex", t.v2 - origin);
}

// A 3x4 affine matrix's three rows of four, as <matrix> reads them.
std::string matrixRows(const glm::dmat4& m) {
    std::string rows;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) rows += (rows.empty() ? "" : col == 0 ? "  " : " ") + xmlNumber(m[col][row]);
    return rows;
}

// One <object>: a top-level one (origin 0, its material written), or a csg
// child, its position relative to the csg object's (origin) and its
// material written only when it has its own.
void writeObject(XmlOut& x, const Shape& shape, const Material& m, bool writeMaterial, const glm::dvec3& origin,
                 const FilePlaces& places, const std::string& name = {});

void writeObject(XmlOut& x, const Object& o, const FilePlaces& places) {
    writeObject(x, o.shape, o.material, true, glm::dvec3(0), places, o.name);
}

void writeObject(XmlOut& x, const Shape& shape, const Material& m, bool writeMaterial, const glm::dvec3& origin,
                 const FilePlaces& places, const std::string& name) {
    const Mesh* mesh = std::get_if<Mesh>(&shape);
    const Mesh::FileSource* source = mesh && mesh->source ? &*mesh->source : nullptr;
    // A model file split by its own materials: written once, by its first
    // part, without a colour, so that loading applies the file's materials again.
    if (source && source->part > 0) return;
    bool fileMaterials = source && source->part == 0;
    x.open("object");
    if (!name.empty()) x.value("name", escapedXml(name));
    // Triangles and meshes are written in world space without a position,
    // unless their checker is anchored elsewhere: then at the checker's
    // origin, vertices relative to it.
    bool hasVertices = std::holds_alternative<Triangle>(shape) || std::holds_alternative<Mesh>(shape);
    glm::dvec3 vertexOrigin(0);
    if (source) {
        x.vector("position", source->position);  // a model file: its placement, not its triangles
    } else if (hasVertices && m.checkerSize > 0 && m.checkerOrigin != glm::dvec3(0)) {
        vertexOrigin = m.checkerOrigin;
        x.vector("position", vertexOrigin);
    }
    // Position first (the seed's order), for the shapes that have one.
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>)
                x.vector("position", s.center - origin);
            else if constexpr (std::is_same_v<T, Cylinder>)
                x.vector("position", s.base - origin);
            else if constexpr (std::is_same_v<T, Plane>)
                x.vector("position", s.point - origin);
            else if constexpr (std::is_same_v<T, Box>)
                x.vector("position", s.min - origin);
            else if constexpr (std::is_same_v<T, Csg>)
                x.vector("position", s.position - origin);
        },
        shape);
    // A model file's own materials come back only without a diffuse colour.
    if (writeMaterial && !fileMaterials) x.colour("diffuse_color", m.diffuseColor);
    if (writeMaterial) x.colour("specular_color", m.specularColor);
    x.open("properties");
    static const char* kTypes[] = {"sphere", "cylinder", "plane", "triangle", "box", "mesh", "csg"};
    x.value("type", kTypes[shape.index()]);
    if (writeMaterial) writeMaterialProperties(x, m, places, !fileMaterials);
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>) {
                x.value("radius", s.radius);
            } else if constexpr (std::is_same_v<T, Cylinder>) {
                x.value("radius", s.radius);
                x.value("height", s.height);
                x.vector("axis", s.axis);
            } else if constexpr (std::is_same_v<T, Plane>) {
                x.vector("normal", s.normal);
                if (m.textureScale != 1.0) x.value("texture_scale", m.textureScale);
            } else if constexpr (std::is_same_v<T, Triangle>) {
                writeTriangleVertices(x, s, vertexOrigin);
            } else if constexpr (std::is_same_v<T, Box>) {
                x.vector("size", s.max - s.min);
            } else if constexpr (std::is_same_v<T, Csg>) {
                static const char* kOperations[] = {"union", "intersection", "difference"};
                x.value("operation", kOperations[int(s.operation)]);
            } else if (source) {
                if (source->partName.empty())
                    x.value("file", fileText(source->path, places));
                else
                    x.line("<file part=\"" + escapedXml(source->partName) + "\">" + fileText(source->path, places) +
                           "</file>");
                if (source->matrix) x.value("matrix", matrixRows(*source->matrix));  // three rows of four
                if (source->scale != glm::dvec3(1)) x.vector("scale", source->scale);
                if (source->rotationDegrees != glm::dvec3(0)) x.vector("rotation", source->rotationDegrees);
            } else {
                x.open("polygons");
                for (size_t i = 0; i < s.triangles.size(); ++i) {
                    x.open("polygon");
                    writeTriangleVertices(x, s.triangles[i], vertexOrigin);
                    if (!s.uvs.empty())
                        for (const glm::dvec2& uv : s.uvs[i])
                            x.line("<uv u=\"" + xmlNumber(uv.x) + "\" v=\"" + xmlNumber(uv.y) + "\"/>");
                    if (!s.normals.empty())
                        for (const glm::dvec3& n : s.normals[i]) x.vector("normal", n);
                    x.close("polygon");
                }
                x.close("polygons");
            }
        },
        shape);
    x.close("properties");
    if (const Csg* csg = std::get_if<Csg>(&shape)) {
        x.open("objects");
        for (const CsgChild& child : csg->children)
            writeObject(x, child.shape, child.material, child.ownMaterial, csg->position, places);
        x.close("objects");
    }
    x.close("object");
}

// <prototypes> and <instances> (scenes/README.md "Instances"); an
// instance's placement as its <matrix>.
void writeInstancing(XmlOut& x, const Scene& scene, const FilePlaces& places) {
    if (!scene.prototypes.empty()) {
        x.open("prototypes");
        for (const Prototype& p : scene.prototypes) {
            x.open("prototype");
            x.value("name", escapedXml(p.name));
            x.open("objects");
            for (const Object& o : p.objects) writeObject(x, o, places);
            x.close("objects");
            x.close("prototype");
        }
        x.close("prototypes");
    }
    if (scene.instances.empty()) return;
    x.open("instances");
    for (const Instance& instance : scene.instances) {
        x.open("instance");
        x.value("prototype", escapedXml(scene.prototypes[instance.prototype].name));
        if (!instance.name.empty()) x.value("name", escapedXml(instance.name));
        x.value("matrix", matrixRows(instance.worldFromObject));
        if (const Material* m = instance.material ? &*instance.material : nullptr) {
            x.colour("diffuse_color", m->diffuseColor);
            x.colour("specular_color", m->specularColor);
            x.open("properties");
            writeMaterialProperties(x, *m, places);
            x.close("properties");
        }
        x.close("instance");
    }
    x.close("instances");
}

}  // namespace

static_assert(std::is_same_v<std::variant_alternative_t<5, Shape>, Mesh> &&
                  std::is_same_v<std::variant_alternative_t<6, Shape>, Csg>,
              "kTypes follows the Shape variant's order");

std::string sceneCameraXml(const Camera& camera, int indent) {
    XmlOut x;
    x.setDepth(indent / 2);
    writeCamera(x, camera);
    return x.str();
}

std::string sceneXml(const Scene& scene, const std::filesystem::path& destination) {
    XmlOut x;
    x.line("<?xml version=\"1.0\" encoding=\"utf-8\"?>");
    x.open("scene");
    writeCamera(x, scene.camera);
    x.colour("ambient_light", scene.ambientLight);
    FilePlaces places{scene.sourcePath.parent_path(), destination};
    if (const std::optional<Environment>& env = scene.environment) {
        std::string image = env->image ? textureText(TextureRef{env->imageWritten, env->image}, places) : "";
        std::istringstream lines(environmentXml(*env, image, 0));
        for (std::string line; std::getline(lines, line);) x.line(line);
    }
    x.open("lights");
    for (const Light& l : scene.lights) writeLight(x, l);
    x.close("lights");
    x.open("objects");
    for (const Object& o : scene.objects) writeObject(x, o, places);
    x.close("objects");
    writeInstancing(x, scene, places);
    x.close("scene");
    return x.str();
}

void writeFilelessTextures(Scene& scene, const std::filesystem::path& output) {
    std::map<const TextureData*, std::string> written;  // one file per texture, however many use it
    std::set<std::string> names;
    auto extract = [&](TextureRef& ref, const std::string& label, const char* slot) {
        if (!ref || !ref.written.empty() || ref.data->levels.empty()) return;
        if (auto it = written.find(ref.data.get()); it != written.end()) {
            ref.written = it->second;
            return;
        }
        const TextureData& data = *ref.data;
        std::string stem = output.stem().string() + "." + label + "." + slot;
        for (int k = 2; names.contains(stem); ++k) stem = output.stem().string() + "." + label + "-" + std::to_string(k) + "." + slot;
        names.insert(stem);
        std::filesystem::path file;
        if (!data.encoded.empty()) {
            file = stem + "." + data.encodedFormat;
            std::string bytes(data.encoded.begin(), data.encoded.end());
            writeTextFile(output.parent_path() / file, bytes);  // atomic; the bytes as they are
        } else {
            const TextureLevel& level = data.levels[0];
            std::vector<float> texels(level.rgba.size());
            for (size_t i = 0; i < texels.size(); ++i) texels[i] = glm::unpackHalf1x16(level.rgba[i]);
            file = stem + ".exr";
            writeImage(output.parent_path() / file, level.width, level.height, 4, texels, PixelEncoding::Float);
        }
        // Absolute: the writer makes texture paths relative to the file it writes.
        ref.written = written[ref.data.get()] = std::filesystem::absolute(output.parent_path() / file).string();
    };
    auto material = [&](Material& m, const std::string& label) {
        static constexpr const char* kSlots[] = {"diffuse_texture", "normal_map", "emission_texture",
                                                 "roughness_texture"};  // textures()' order
        for (size_t k = 0; k < m.textures().size(); ++k) extract(*m.textures()[k], label, kSlots[k]);
    };
    std::function<void(Csg&, const std::string&)> children = [&](Csg& csg, const std::string& label) {
        for (size_t k = 0; k < csg.children.size(); ++k) {
            CsgChild& child = csg.children[k];
            std::string childLabel = label + ".child" + std::to_string(k);
            material(child.material, childLabel);
            if (Csg* inner = std::get_if<Csg>(&child.shape)) children(*inner, childLabel);
        }
    };
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        Object& object = scene.objects[i];
        std::string label = object.name.empty() ? "object" + std::to_string(i) : object.name;
        for (char& c : label)
            if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
        material(object.material, label);
        if (Csg* csg = std::get_if<Csg>(&object.shape)) children(*csg, label);
    }
    if (scene.environment && scene.environment->image) {
        TextureRef image{scene.environment->imageWritten, scene.environment->image};
        extract(image, "environment", "image");
        scene.environment->imageWritten = image.written;
    }
}

void writeSceneFile(const Scene& scene, const std::filesystem::path& path) {
    writeTextFile(path, sceneXml(scene, path));
}

}  // namespace whitted

#include "scene/scene_writer.h"

#include <cstdio>
#include <sstream>
#include <type_traits>
#include <variant>

#include "io/render_record.h"  // writeTextFile: temporary file + rename

namespace whitted {
namespace {

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

class XmlOut {
public:
    void open(const std::string& tag) { line("<" + tag + ">"), ++depth_; }
    void close(const std::string& tag) { --depth_, line("</" + tag + ">"); }
    void value(const std::string& tag, const std::string& v) { line("<" + tag + ">" + v + "</" + tag + ">"); }
    void value(const std::string& tag, double v) { value(tag, number(v)); }
    void vector(const std::string& tag, const glm::dvec3& v) {
        line("<" + tag + " x=\"" + number(v.x) + "\" y=\"" + number(v.y) + "\" z=\"" + number(v.z) + "\"/>");
    }
    void colour(const std::string& tag, const glm::dvec3& c) {
        line("<" + tag + " r=\"" + number(c.r) + "\" g=\"" + number(c.g) + "\" b=\"" + number(c.b) + "\"/>");
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
    x.value("fov", c.verticalFovDegrees);
    x.value("width", std::to_string(c.width));
    x.value("height", std::to_string(c.height));
    x.close("camera");
}

// Vertices relative to `origin`, the <position> written for the object.
void writeTriangleVertices(XmlOut& x, const Triangle& t, const glm::dvec3& origin) {
    x.vector("vertex", t.v0 - origin);
    x.vector("vertex", t.v1 - origin);
    x.vector("vertex", t.v2 - origin);
}

void writeObject(XmlOut& x, const Object& o) {
    const Material& m = o.material;
    x.open("object");
    // Triangles and meshes are written in world space without a position,
    // unless their checker is anchored elsewhere: then at the checker's
    // origin, vertices relative to it.
    bool hasVertices = std::holds_alternative<Triangle>(o.shape) || std::holds_alternative<Mesh>(o.shape);
    glm::dvec3 vertexOrigin(0);
    if (hasVertices && m.checkerSize > 0 && m.checkerOrigin != glm::dvec3(0)) {
        vertexOrigin = m.checkerOrigin;
        x.vector("position", vertexOrigin);
    }
    // Position first (the seed's order), for the shapes that have one.
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>)
                x.vector("position", s.center);
            else if constexpr (std::is_same_v<T, Cylinder>)
                x.vector("position", s.base);
            else if constexpr (std::is_same_v<T, Plane>)
                x.vector("position", s.point);
            else if constexpr (std::is_same_v<T, Box>)
                x.vector("position", s.min);
        },
        o.shape);
    x.colour("diffuse_color", m.diffuseColor);
    x.colour("specular_color", m.specularColor);
    x.open("properties");
    static const char* kTypes[] = {"sphere", "cylinder", "plane", "triangle", "box", "mesh"};
    x.value("type", kTypes[o.shape.index()]);
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
    // The texture's path as the scene file wrote it (relative to its folder).
    // (A model file's own texture has no path to write: the mesh is written
    // inline with its base colour and UVs.)
    if (m.diffuseTexture && !m.diffuseTexture.written.empty()) x.value("diffuse_texture", m.diffuseTexture.written);
    if (m.normalMap && !m.normalMap.written.empty()) {
        x.value("normal_map", m.normalMap.written);
        x.value("normal_strength", m.normalStrength);
    }
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
            } else {
                x.open("polygons");
                for (size_t i = 0; i < s.triangles.size(); ++i) {
                    x.open("polygon");
                    writeTriangleVertices(x, s.triangles[i], vertexOrigin);
                    if (!s.uvs.empty())
                        for (const glm::dvec2& uv : s.uvs[i])
                            x.line("<uv u=\"" + number(uv.x) + "\" v=\"" + number(uv.y) + "\"/>");
                    x.close("polygon");
                }
                x.close("polygons");
            }
        },
        o.shape);
    x.close("properties");
    x.close("object");
}

}  // namespace

static_assert(std::is_same_v<std::variant_alternative_t<5, Shape>, Mesh>, "kTypes follows the Shape variant's order");

std::string sceneCameraXml(const Camera& camera, int indent) {
    XmlOut x;
    x.setDepth(indent / 2);
    writeCamera(x, camera);
    return x.str();
}

std::string sceneXml(const Scene& scene) {
    XmlOut x;
    x.line("<?xml version=\"1.0\" encoding=\"utf-8\"?>");
    x.open("scene");
    writeCamera(x, scene.camera);
    x.colour("ambient_light", scene.ambientLight);
    x.open("lights");
    for (const PointLight& l : scene.lights) {
        x.open("light");
        x.vector("position", l.position);
        x.colour("color", l.color);
        x.close("light");
    }
    x.close("lights");
    x.open("objects");
    for (const Object& o : scene.objects) writeObject(x, o);
    x.close("objects");
    x.close("scene");
    return x.str();
}

void writeSceneFile(const Scene& scene, const std::filesystem::path& path) {
    writeTextFile(path, sceneXml(scene));
}

}  // namespace whitted

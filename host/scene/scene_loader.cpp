#include "scene/scene_loader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

namespace whitted {

namespace {
std::string formatError(const std::string& file, int line, const std::string& message) {
    return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
}
}  // namespace

SceneError::SceneError(std::string file, int line, std::string message)
    : std::runtime_error(formatError(file, line, message)),
      file_(std::move(file)),
      line_(line),
      message_(std::move(message)) {}

namespace {

using tinyxml2::XMLElement;

constexpr double kMaxMagnitude = 1e6;

std::string tag(const std::string& name) { return "<" + name + ">"; }

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
    return s;
}

std::string trimmed(const char* text) {
    std::string s = text ? text : "";
    auto notSpace = [](unsigned char c) { return !std::isspace(c); };
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), notSpace));
    s.erase(std::find_if(s.rbegin(), s.rend(), notSpace).base(), s.end());
    return s;
}

// Shortens a number for messages: 1e+09 -> 1e+09, 0.5 -> 0.5.
std::string show(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// Reading one file: every error carries its name and the element's line.
class Parser {
public:
    explicit Parser(std::string file) : file_(std::move(file)) {}

    [[noreturn]] void fail(const XMLElement* e, const std::string& message) const {
        throw SceneError(file_, e ? e->GetLineNum() : 0, message);
    }
    void warn(const XMLElement* e, const std::string& message, Scene& scene) const {
        scene.warnings.push_back(formatError(file_, e ? e->GetLineNum() : 0, message));
    }

    // The children of `e`, checked against the allowed names: an unknown
    // name or a repeated singular one is refused. Names in `repeatable` may
    // occur many times.
    std::map<std::string, std::vector<const XMLElement*>> children(const XMLElement* e,
                                                                   const std::vector<std::string>& allowed,
                                                                   const std::set<std::string>& repeatable = {}) const {
        std::map<std::string, std::vector<const XMLElement*>> found;
        for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
            std::string name = c->Name();
            if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
                fail(c, "unknown element " + tag(name) + " in " + tag(e->Name()) + "; expected one of: " + joined(allowed));
            auto& list = found[name];
            if (!list.empty() && !repeatable.count(name)) fail(c, "duplicate " + tag(name) + " in " + tag(e->Name()));
            list.push_back(c);
        }
        return found;
    }

    // A number in the element's text (or the given attribute text).
    double number(const XMLElement* e, const std::string& what, const char* text) const {
        std::string s = trimmed(text);
        double v = 0;
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec == std::errc::invalid_argument || end != s.data() + s.size())
            fail(e, what + " must be a number, got \"" + s + "\"");
        if (ec == std::errc::result_out_of_range || !std::isfinite(v))
            fail(e, what + " must be a finite number, got \"" + s + "\"");
        if (std::abs(v) > kMaxMagnitude) fail(e, what + " must be within ±1e6, got " + s);
        return v;
    }
    double number(const XMLElement* e) const { return number(e, tag(e->Name()), e->GetText()); }

    double numberInRange(const XMLElement* e, double lo, double hi, bool openLo = false) const {
        double v = number(e);
        if (openLo ? !(v > lo) : !(v >= lo))
            fail(e, tag(e->Name()) + " must be " + (openLo ? "> " : ">= ") + show(lo) + ", got " + show(v));
        if (v > hi) fail(e, tag(e->Name()) + " must be <= " + show(hi) + ", got " + show(v));
        return v;
    }
    double coefficient(const XMLElement* e) const {
        double v = number(e);
        if (v < 0 || v > 1) fail(e, tag(e->Name()) + " must be in [0, 1], got " + show(v));
        return v;
    }
    double positive(const XMLElement* e) const {
        double v = number(e);
        if (!(v > 0)) fail(e, tag(e->Name()) + " must be > 0, got " + show(v));
        return v;
    }

    int integer(const XMLElement* e, int lo, int hi) const {
        std::string s = trimmed(e->GetText());
        int v = 0;
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc() || end != s.data() + s.size())
            fail(e, tag(e->Name()) + " must be an integer, got \"" + s + "\"");
        if (v < lo || v > hi)
            fail(e, tag(e->Name()) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + s);
        return v;
    }

    bool boolean(const XMLElement* e) const {
        std::string s = trimmed(e->GetText());
        std::string lower = s;
        std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
        if (lower == "true" || lower == "1") return true;
        if (lower == "false" || lower == "0") return false;
        fail(e, tag(e->Name()) + " must be true or false, got \"" + s + "\"");
    }

    // Components of a vector or colour, from attributes (<p x=".." .../>)
    // or from child elements (<p><x>..</x>...</p>), not a mix of the two.
    std::vector<double> components(const XMLElement* e, const std::vector<std::string>& names,
                                   const std::vector<std::string>& optional = {}) const {
        std::vector<std::string> all = names;
        all.insert(all.end(), optional.begin(), optional.end());
        bool hasAttributes = e->FirstAttribute() != nullptr;
        bool hasChildren = e->FirstChildElement() != nullptr;
        if (hasAttributes && hasChildren) fail(e, tag(e->Name()) + " mixes attributes and child elements");
        std::vector<double> values;
        if (hasAttributes) {
            for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
                if (std::find(all.begin(), all.end(), a->Name()) == all.end())
                    fail(e, "unknown attribute \"" + std::string(a->Name()) + "\" on " + tag(e->Name()) +
                                "; expected " + joined(all));
            for (const std::string& n : all) {
                const char* text = e->Attribute(n.c_str());
                if (!text) {
                    if (std::find(optional.begin(), optional.end(), n) != optional.end()) continue;
                    fail(e, tag(e->Name()) + " is missing attribute \"" + n + "\"");
                }
                values.push_back(number(e, tag(e->Name()) + " attribute \"" + n + "\"", text));
            }
        } else {
            auto found = children(e, all);
            for (const std::string& n : all) {
                auto it = found.find(n);
                if (it == found.end()) {
                    if (std::find(optional.begin(), optional.end(), n) != optional.end()) continue;
                    fail(e, tag(e->Name()) + " is missing " + tag(n));
                }
                values.push_back(number(it->second[0]));
            }
        }
        return values;
    }

    glm::dvec3 vector(const XMLElement* e) const {
        auto v = components(e, {"x", "y", "z"});
        return {v[0], v[1], v[2]};
    }
    glm::dvec3 unitVector(const XMLElement* e) const {
        glm::dvec3 v = vector(e);
        double len = glm::length(v);
        if (!(len > 1e-12)) fail(e, tag(e->Name()) + " must not be the zero vector");
        return v / len;
    }
    // A colour; channels in [0, maxChannel]; alpha accepted in [0,1], unused.
    glm::dvec3 color(const XMLElement* e, double maxChannel) const {
        auto v = components(e, {"r", "g", "b"}, {"a"});
        for (size_t i = 0; i < v.size(); ++i) {
            double hi = i < 3 ? maxChannel : 1.0;
            if (v[i] < 0 || v[i] > hi)
                fail(e, tag(e->Name()) + " channels must be in [0, " + show(hi) + "], got " + show(v[i]));
        }
        return {v[0], v[1], v[2]};
    }

private:
    std::string file_;
};

const XMLElement* only(const std::map<std::string, std::vector<const XMLElement*>>& found, const std::string& name) {
    auto it = found.find(name);
    return it == found.end() ? nullptr : it->second.front();
}

const XMLElement* required(const Parser& p, const XMLElement* parent,
                           const std::map<std::string, std::vector<const XMLElement*>>& found, const std::string& name,
                           const std::string& why = "") {
    const XMLElement* e = only(found, name);
    if (!e) p.fail(parent, tag(parent->Name()) + " is missing " + tag(name) + why);
    return e;
}

// ---- Camera ----------------------------------------------------------------

Camera readCamera(const Parser& p, const XMLElement* e) {
    auto c = p.children(e, {"position", "window_position", "fov", "window_height", "up", "width", "height"});
    Camera camera;
    camera.eye = p.vector(required(p, e, c, "position"));
    camera.windowCenter = p.vector(required(p, e, c, "window_position"));
    glm::dvec3 forward = camera.windowCenter - camera.eye;
    double distance = glm::length(forward);
    if (!(distance > 1e-9)) p.fail(e, "camera <position> and <window_position> coincide");
    if (auto up = only(c, "up")) {
        camera.up = p.unitVector(up);
        if (glm::length(glm::cross(forward / distance, camera.up)) < 1e-6)
            p.fail(up, "camera <up> is parallel to the viewing direction");
    } else if (glm::length(glm::cross(forward / distance, camera.up)) < 1e-6) {
        p.fail(e, "camera looks straight up or down; give an <up> vector that is not vertical");
    }
    const XMLElement* fov = only(c, "fov");
    const XMLElement* windowHeight = only(c, "window_height");
    if (fov && windowHeight) p.fail(windowHeight, "<camera> has both <fov> and <window_height>; give one");
    if (fov) {
        camera.verticalFovDegrees = p.number(fov);
        if (!(camera.verticalFovDegrees > 0 && camera.verticalFovDegrees < 180))
            p.fail(fov, "<fov> must be in (0, 180) degrees, got " + show(camera.verticalFovDegrees));
    }
    if (windowHeight) {
        double h = p.positive(windowHeight);
        camera.verticalFovDegrees = glm::degrees(2.0 * std::atan(h / 2.0 / distance));
    }
    if (auto w = only(c, "width")) camera.width = p.integer(w, 1, 16384);
    if (auto h = only(c, "height")) camera.height = p.integer(h, 1, 16384);
    return camera;
}

// ---- Objects ---------------------------------------------------------------

const std::vector<std::string> kTypes = {"sphere", "cylinder", "mesh", "plane", "triangle", "box"};
const std::vector<std::string> kMaterialProperties = {"type",           "refraction_coef", "transmission_coef",
                                                      "specular_coef",  "diffuse_coef",    "ambiente_coef",
                                                      "reflective",     "shininess",       "reflection_coef"};
// Shape properties and the types they apply to.
const std::map<std::string, std::set<std::string>> kShapeProperties = {
    {"radius", {"sphere", "cylinder"}}, {"height", {"cylinder"}}, {"axis", {"cylinder"}},
    {"polygons", {"mesh"}},             {"normal", {"plane"}},    {"vertex", {"triangle"}},
    {"size", {"box"}}};

bool degenerate(const Triangle& t) {
    glm::dvec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0;
    double scale = std::max(glm::dot(e1, e1), glm::dot(e2, e2));
    return !(glm::length(glm::cross(e1, e2)) > 1e-12 * scale) || scale == 0;
}

Triangle readTriangle(const Parser& p, const XMLElement* parent, const std::vector<const XMLElement*>& vertices,
                      glm::dvec3 offset) {
    if (vertices.size() != 3)
        p.fail(parent, tag(parent->Name()) + " has " + std::to_string(vertices.size()) + " <vertex>, expected 3");
    return {offset + p.vector(vertices[0]), offset + p.vector(vertices[1]), offset + p.vector(vertices[2])};
}

Mesh readMesh(const Parser& p, const XMLElement* polygons, glm::dvec3 offset, Scene& scene) {
    auto found = p.children(polygons, {"polygon"}, {"polygon"});
    Mesh mesh;
    auto it = found.find("polygon");
    if (it == found.end()) p.fail(polygons, "<polygons> has no <polygon>; a mesh needs at least one");
    for (const XMLElement* polygon : it->second) {
        auto v = p.children(polygon, {"vertex"}, {"vertex"});
        Triangle t = readTriangle(p, polygon, v["vertex"], offset);
        if (degenerate(t)) {
            p.warn(polygon, "degenerate polygon skipped", scene);
            continue;
        }
        mesh.triangles.push_back(t);
    }
    if (mesh.triangles.empty()) p.fail(polygons, "every <polygon> of the mesh is degenerate");
    return mesh;
}

Material readMaterial(const Parser& p, const XMLElement* object,
                      const std::map<std::string, std::vector<const XMLElement*>>& o,
                      const std::map<std::string, std::vector<const XMLElement*>>& props) {
    Material m;
    if (auto e = only(o, "diffuse_color")) m.diffuseColor = p.color(e, 1.0);
    if (auto e = only(o, "specular_color")) m.specularColor = p.color(e, 1.0);
    if (auto e = only(props, "ambiente_coef")) m.ambient = p.coefficient(e);
    if (auto e = only(props, "diffuse_coef")) m.diffuse = p.coefficient(e);
    if (auto e = only(props, "specular_coef")) m.specular = p.coefficient(e);
    if (auto e = only(props, "transmission_coef")) m.transmission = p.coefficient(e);
    if (auto e = only(props, "refraction_coef")) m.ior = p.numberInRange(e, 0.1, 10.0);
    if (auto e = only(props, "shininess")) m.shininess = p.numberInRange(e, 0.0, 1e5, true);
    const XMLElement* reflective = only(props, "reflective");
    const XMLElement* reflection = only(props, "reflection_coef");
    bool isReflective = reflective && p.boolean(reflective);
    if (reflection) {
        if (reflective && !isReflective)
            p.fail(reflection, "<reflection_coef> contradicts <reflective>false</reflective>");
        m.reflection = p.coefficient(reflection);
    } else if (isReflective) {
        m.reflection = m.specular;
    }
    (void)object;
    return m;
}

Object readObject(const Parser& p, const XMLElement* e, Scene& scene) {
    auto o = p.children(e, {"position", "diffuse_color", "specular_color", "properties"});
    const XMLElement* propsElement = required(p, e, o, "properties");

    std::vector<std::string> allowed = kMaterialProperties;
    for (const auto& [name, types] : kShapeProperties) allowed.push_back(name);
    auto props = p.children(propsElement, allowed, {"vertex"});
    const XMLElement* typeElement = required(p, propsElement, props, "type");
    std::string type = trimmed(typeElement->GetText());
    if (std::find(kTypes.begin(), kTypes.end(), type) == kTypes.end())
        p.fail(typeElement, "unknown object type \"" + type + "\"; expected one of: " + joined(kTypes));
    for (const auto& [name, elements] : props) {
        auto it = kShapeProperties.find(name);
        if (it != kShapeProperties.end() && !it->second.count(type))
            p.fail(elements.front(), tag(name) + " does not apply to type " + type);
    }
    auto need = [&](const std::string& name) {
        return required(p, propsElement, props, name, " (required for type " + type + ")");
    };

    Object object;
    object.sourceLine = e->GetLineNum();
    object.material = readMaterial(p, e, o, props);
    const XMLElement* positionElement = only(o, "position");
    bool positionOptional = type == "mesh" || type == "triangle";
    if (!positionElement && !positionOptional) p.fail(e, "<object> is missing <position>");
    glm::dvec3 position = positionElement ? p.vector(positionElement) : glm::dvec3(0);

    if (type == "sphere") {
        object.shape = Sphere{position, p.positive(need("radius"))};
    } else if (type == "cylinder") {
        double radius = p.positive(need("radius"));
        double height = p.positive(need("height"));
        glm::dvec3 axis = only(props, "axis") ? p.unitVector(only(props, "axis")) : glm::dvec3(0, 1, 0);
        object.shape = Cylinder{position, axis, radius, height};
    } else if (type == "plane") {
        object.shape = Plane{position, p.unitVector(need("normal"))};
    } else if (type == "box") {
        const XMLElement* sizeElement = need("size");
        glm::dvec3 size = p.vector(sizeElement);
        if (!(size.x > 0 && size.y > 0 && size.z > 0))
            p.fail(sizeElement, "<size> components must be > 0, got " + show(size.x) + ", " + show(size.y) + ", " +
                                    show(size.z));
        object.shape = Box{position, position + size};
    } else if (type == "triangle") {
        auto it = props.find("vertex");
        std::vector<const XMLElement*> vertices = it == props.end() ? std::vector<const XMLElement*>{} : it->second;
        Triangle t = readTriangle(p, propsElement, vertices, position);
        if (degenerate(t)) p.fail(propsElement, "degenerate triangle: its vertices are collinear");
        object.shape = t;
    } else {
        object.shape = readMesh(p, need("polygons"), position, scene);
    }
    return object;
}

Scene parse(const tinyxml2::XMLDocument& doc, const std::filesystem::path& name) {
    Parser p(name.string());
    const XMLElement* root = doc.RootElement();
    if (!root) p.fail(nullptr, "no root element; expected <scene>");
    if (std::string(root->Name()) != "scene")
        p.fail(root, "root element is <" + std::string(root->Name()) + ">, expected <scene>");
    auto s = p.children(root, {"camera", "lights", "objects", "ambient_light"});

    Scene scene;
    scene.sourcePath = name;
    scene.camera = readCamera(p, required(p, root, s, "camera"));
    if (auto a = only(s, "ambient_light")) scene.ambientLight = p.color(a, kMaxMagnitude);

    const XMLElement* lights = required(p, root, s, "lights");
    auto lightList = p.children(lights, {"light"}, {"light"});
    for (const XMLElement* l : lightList["light"]) {
        auto c = p.children(l, {"position", "color"});
        scene.lights.push_back({p.vector(required(p, l, c, "position")), p.color(required(p, l, c, "color"), kMaxMagnitude)});
    }
    if (scene.lights.empty()) p.warn(lights, "scene has no lights; only ambient light will show", scene);

    const XMLElement* objects = required(p, root, s, "objects");
    auto objectList = p.children(objects, {"object"}, {"object"});
    for (const XMLElement* o : objectList["object"]) scene.objects.push_back(readObject(p, o, scene));
    if (scene.objects.empty()) p.warn(objects, "scene has no objects; the image will be black", scene);
    return scene;
}

}  // namespace

Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name) {
    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
        // ErrorStr() is "Error=NAME ErrorID=N (0xN) Line number=N: detail";
        // the name and the detail are what a reader needs.
        std::string detail = doc.ErrorStr();
        size_t at = detail.find("Line number=");
        at = at == std::string::npos ? std::string::npos : detail.find(": ", at);
        detail = at == std::string::npos ? "" : ": " + detail.substr(at + 2);
        throw SceneError(name.string(), doc.ErrorLineNum(),
                         std::string("malformed XML (") + doc.ErrorName() + ")" + detail);
    }
    return parse(doc, name);
}

Scene loadScene(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in || std::filesystem::is_directory(path))
        throw SceneError(path.string(), 0, std::string("cannot read file: ") +
                                               (std::filesystem::exists(path) ? "not a readable file" : "no such file"));
    std::stringstream text;
    text << in.rdbuf();
    return loadSceneFromString(text.str(), path);
}

}  // namespace whitted

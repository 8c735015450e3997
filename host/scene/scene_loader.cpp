#include "scene/scene_loader.h"

#include "io/mesh_file.h"
#include "io/texture_file.h"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <tuple>
#include <utility>
#include <vector>

namespace whitted {

namespace {

std::string located(const std::string& file, int line, const std::string& message) {
    if (line > 0) return file + ":" + std::to_string(line) + ": " + message;
    return file + ": " + message;
}

}  // namespace

SceneError::SceneError(std::string file, int line, std::string message)
    : std::runtime_error(located(file, line, message)),
      file_(std::move(file)),
      line_(line),
      message_(std::move(message)) {}

namespace {

using tinyxml2::XMLElement;
using tinyxml2::XMLNode;
using tinyxml2::XMLText;

// Limits of the format (README "Scene files").
constexpr double kMaxMagnitude = 1e6;
constexpr int kMaxImageSize = 16384;
// Below this length a direction (or the eye-to-window vector) counts as zero.
constexpr double kMinLength = 1e-12;
// |cross(a, b)| of unit vectors below this counts as parallel.
constexpr double kParallelTolerance = 1e-6;
// A triangle is degenerate when |cross(e1, e2)| <= this times its longest
// squared edge (zero area relative to its size).
constexpr double kDegenerateTolerance = 1e-12;
// Stray text is quoted in messages up to this many characters.
constexpr size_t kMaxQuotedText = 30;

// ---- Text helpers -----------------------------------------------------------

std::string tag(std::string_view name) {
    return "<" + std::string(name) + ">";
}

std::string trimmed(std::string_view s) {
    auto isSpace = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return std::string(s);
}

std::string inQuotes(std::string_view text) {
    if (text.size() > kMaxQuotedText) return "\"" + std::string(text.substr(0, kMaxQuotedText)) + "...\"";
    return "\"" + std::string(text) + "\"";
}

// "a, b, c"; with `lastSeparator` " or " the last pair reads "b or c".
std::string joined(const std::vector<std::string>& names, const std::string& lastSeparator = ", ") {
    std::string s;
    for (size_t i = 0; i < names.size(); ++i) {
        if (i > 0) s += i + 1 == names.size() ? lastSeparator : ", ";
        s += names[i];
    }
    return s;
}

// A range bound as people write it: 0.1, 10, 100000.
std::string showBound(double v) {
    std::array<char, 32> buffer{};
    std::snprintf(buffer.data(), buffer.size(), "%g", v);
    return buffer.data();
}

// ---- Value ranges -------------------------------------------------------------

// The values a number may take. Every number is also within ±kMaxMagnitude.
struct Range {
    double lo = -kMaxMagnitude;
    double hi = kMaxMagnitude;
    bool loOpen = false;
    bool hiOpen = false;

    bool contains(double v) const { return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi); }

    // "> 0" or ">= 0" when the upper end is only the ±1e6 limit, else
    // "in [0, 1]" with open ends as parentheses.
    std::string describe() const {
        if (hi == kMaxMagnitude && !hiOpen) return (loOpen ? "> " : ">= ") + showBound(lo);
        return std::string("in ") + (loOpen ? "(" : "[") + showBound(lo) + ", " + showBound(hi) + (hiOpen ? ")" : "]");
    }
};

constexpr Range kAnyValue{};
constexpr Range kPositive{0, kMaxMagnitude, true, false};
constexpr Range kNonNegative{0, kMaxMagnitude, false, false};
constexpr Range kUnitInterval{0, 1, false, false};  // coefficients, material colours, alpha
constexpr Range kIorRange{0.1, 10, false, false};
constexpr Range kShininessRange{0, 1e5, true, false};
constexpr Range kFovRange{0, 180, true, true};

// ---- Number parsing -------------------------------------------------------------

enum class NumberKind { Finite, NotANumber, NotFinite, Overflow };

struct ParsedNumber {
    NumberKind kind;
    double value;
};

// std::from_chars does not take the leading '+' people may write.
std::string_view withoutPlus(std::string_view s) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    return s;
}

// The whole of `text` as a decimal number. std::from_chars is locale-free and
// tells trailing garbage apart. Underflow reads as the (tiny or zero) value
// strtod gives.
ParsedNumber parseNumber(const std::string& text) {
    std::string_view s = withoutPlus(text);
    double value = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || end != s.data() + s.size() || ec == std::errc::invalid_argument)
        return {NumberKind::NotANumber, 0};
    if (ec == std::errc::result_out_of_range) {
        value = std::strtod(std::string(s).c_str(), nullptr);
        if (std::isinf(value)) return {NumberKind::Overflow, value};
    }
    if (!std::isfinite(value)) return {NumberKind::NotFinite, value};
    return {NumberKind::Finite, value};
}

// ---- Geometry checks -------------------------------------------------------------

bool parallel(const glm::dvec3& unitA, const glm::dvec3& unitB) {
    return glm::length(glm::cross(unitA, unitB)) < kParallelTolerance;
}

bool degenerate(const Triangle& t) {
    glm::dvec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0, e3 = t.v2 - t.v1;
    double scale = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
    return !(glm::length(glm::cross(e1, e2)) > kDegenerateTolerance * scale);
}

// ---- Diagnostics -------------------------------------------------------------------

// Errors and warnings of one file, each placed at the line of an XML node.
class Diagnostics {
public:
    Diagnostics(std::string file, std::vector<std::string>& warnings) : file_(std::move(file)), warnings_(&warnings) {}

    [[noreturn]] void fail(const XMLNode* at, const std::string& message) const {
        throw SceneError(file_, at ? at->GetLineNum() : 0, message);
    }
    void warn(const XMLNode* at, const std::string& message) const {
        warnings_->push_back(located(file_, at ? at->GetLineNum() : 0, message));
    }

    // Elements of the format carry no attributes except the compact vector
    // and colour form, which is checked on its own.
    void refuseAttributes(const XMLElement* e) const {
        if (const tinyxml2::XMLAttribute* a = e->FirstAttribute())
            fail(e, "unknown attribute \"" + std::string(a->Name()) + "\" on " + tag(e->Name()) + "; " +
                        tag(e->Name()) + " takes no attributes");
    }
    void refuseText(const XMLText* text, const XMLElement* parent) const {
        std::string content = trimmed(text->Value());
        if (!content.empty()) fail(text, "unexpected text " + inQuotes(content) + " in " + tag(parent->Name()));
    }

private:
    std::string file_;
    std::vector<std::string>* warnings_;
};

// ---- Element reader ----------------------------------------------------------------

// A child element name allowed in a container; `repeatable` ones may occur
// more than once.
struct ChildRule {
    std::string_view name;
    bool repeatable = false;
};

// The children of one container element, checked up front against the names
// the format allows there (Mitsuba's check_attributes): an unknown name, a
// repeated singular name, stray text or an attribute is refused, so a typo is
// never silently ignored. Reading a child marks it used; what was never read
// is what the caller did not expect (pbrt's ReportUnused), see firstUnused().
class ElementReader {
public:
    ElementReader(const Diagnostics& diag, const XMLElement* element, const std::vector<ChildRule>& rules)
        : diag_(diag), element_(element) {
        for (const ChildRule& rule : rules) slots_.push_back({rule, {}, false});
        diag.refuseAttributes(element);
        for (const XMLNode* node = element->FirstChild(); node; node = node->NextSibling()) {
            if (const XMLText* text = node->ToText()) diag.refuseText(text, element);
            const XMLElement* child = node->ToElement();
            if (!child) continue;
            Slot* slot = find(child->Name());
            if (!slot)
                diag.fail(child,
                          "unknown element " + tag(child->Name()) + " in " + tag(element->Name()) + "; " + expected());
            if (!slot->rule.repeatable && !slot->elements.empty())
                diag.fail(child, "duplicate " + tag(child->Name()) + " in " + tag(element->Name()));
            slot->elements.push_back(child);
        }
    }

    const XMLElement* element() const { return element_; }

    const XMLElement* optional(std::string_view name) {
        Slot& slot = declared(name);
        slot.used = true;
        return slot.elements.empty() ? nullptr : slot.elements.front();
    }
    const XMLElement* required(std::string_view name) {
        const XMLElement* child = optional(name);
        if (!child) diag_.fail(element_, tag(element_->Name()) + " is missing " + tag(name));
        return child;
    }
    const std::vector<const XMLElement*>& all(std::string_view name) {
        Slot& slot = declared(name);
        slot.used = true;
        return slot.elements;
    }

    // The first child, in document order, whose name was never read.
    const XMLElement* firstUnused() const {
        for (const XMLElement* child = element_->FirstChildElement(); child; child = child->NextSiblingElement())
            if (!find(child->Name())->used) return child;
        return nullptr;
    }

private:
    struct Slot {
        ChildRule rule;
        std::vector<const XMLElement*> elements;
        bool used;
    };

    Slot* find(std::string_view name) {
        auto it = std::find_if(slots_.begin(), slots_.end(), [&](const Slot& s) { return s.rule.name == name; });
        return it == slots_.end() ? nullptr : &*it;
    }
    const Slot* find(std::string_view name) const {
        auto it = std::find_if(slots_.begin(), slots_.end(), [&](const Slot& s) { return s.rule.name == name; });
        return it == slots_.end() ? nullptr : &*it;
    }

    // Reading a name the rules do not list is a bug in this file, not in the scene.
    Slot& declared(std::string_view name) {
        Slot* slot = find(name);
        if (!slot) throw std::logic_error("scene loader reads undeclared <" + std::string(name) + ">");
        return *slot;
    }

    std::string expected() const {
        std::vector<std::string> names;
        for (const Slot& s : slots_) names.emplace_back(s.rule.name);
        if (names.size() == 1) return "expected " + names[0];
        return "expected one of: " + joined(names);
    }

    const Diagnostics& diag_;
    const XMLElement* element_;
    std::vector<Slot> slots_;
};

// ---- The schema ----------------------------------------------------------------------

const std::vector<std::string> kTypeNames = {"sphere", "cylinder", "mesh", "plane", "triangle", "box", "csg"};
// The types a csg object's child may have: closed solids.
const std::vector<std::string> kCsgChildTypes = {"sphere", "cylinder", "box", "csg"};
// The material elements of an <object> and of its <properties>: a csg child
// with none of them takes the csg object's material.
const std::vector<std::string_view> kObjectMaterialElements = {"diffuse_color", "specular_color"};
const std::vector<std::string_view> kMaterialProperties = {
    "refraction_coef", "transmission_coef", "specular_coef", "diffuse_coef", "ambiente_coef", "reflective",
    "shininess",       "reflection_coef",   "checker_color", "checker_size", "absorption",
    "diffuse_texture", "texture_scale",   "normal_map",    "normal_strength"};

// <properties>: the seed's material elements, the extensions, then the
// shape elements (each applies to some types only; see readShape).
const std::vector<ChildRule> kPropertyRules = {{"type"},
                                               {"refraction_coef"},
                                               {"transmission_coef"},
                                               {"specular_coef"},
                                               {"diffuse_coef"},
                                               {"ambiente_coef"},
                                               {"reflective"},
                                               {"shininess"},
                                               {"reflection_coef"},
                                               {"checker_color"},
                                               {"checker_size"},
                                               {"absorption"},
                                               {"diffuse_texture"},
                                               {"texture_scale"},
                                               {"normal_map"},
                                               {"normal_strength"},
                                               {"radius"},
                                               {"height"},
                                               {"axis"},
                                               {"normal"},
                                               {"size"},
                                               {"vertex", true},
                                               {"polygons"},
                                               {"file"},
                                               {"scale"},
                                               {"rotation"},
                                               {"operation"}};

// One number of a vector or colour.
struct Component {
    std::string_view name;
    Range range;
    bool optional = false;
};

// ---- The loader --------------------------------------------------------------------

// Reads one parsed document into a Scene; every method refuses bad input
// through diag_ with the line of the element at fault.
class SceneReader {
public:
    SceneReader(const std::filesystem::path& name, Scene& scene) : diag_(name.string(), scene.warnings), scene_(scene) {
        scene_.sourcePath = name;
    }

    void read(const tinyxml2::XMLDocument& doc) {
        const XMLElement* root = doc.RootElement();
        if (!root) diag_.fail(nullptr, "no root element; expected <scene>");
        if (std::string_view(root->Name()) != "scene")
            diag_.fail(root, "root element is " + tag(root->Name()) + ", expected <scene>");
        if (const XMLElement* second = root->NextSiblingElement())
            diag_.fail(second, "second root element " + tag(second->Name()) + "; a scene file holds one <scene>");
        // tinyxml2 keeps text beside the root element ("junk <scene>...")
        // without complaint.
        for (const XMLNode* node = doc.FirstChild(); node; node = node->NextSibling())
            if (const XMLText* text = node->ToText(); text && !trimmed(text->Value()).empty())
                diag_.fail(text, "unexpected text " + inQuotes(trimmed(text->Value())) + " outside <scene>");

        ElementReader s(diag_, root, {{"camera"}, {"lights"}, {"objects"}, {"ambient_light"}});
        scene_.camera = readCamera(s.required("camera"));
        readLights(s.required("lights"));
        readObjects(s.required("objects"));
        if (const XMLElement* ambient = s.optional("ambient_light"))
            scene_.ambientLight = colour(ambient, kNonNegative);
    }

private:
    // ---- Values ----

    // The text of a value element such as <radius>, trimmed and joined over
    // its text nodes (a comment may sit inside); elements inside are refused.
    std::string valueText(const XMLElement* e) const {
        diag_.refuseAttributes(e);
        std::string text;
        for (const XMLNode* node = e->FirstChild(); node; node = node->NextSibling()) {
            if (const XMLElement* child = node->ToElement())
                diag_.fail(child, "unknown element " + tag(child->Name()) + " in " + tag(e->Name()) + "; " +
                                      tag(e->Name()) + " holds a value, not elements");
            if (const XMLText* part = node->ToText()) text += part->Value();
        }
        return trimmed(text);
    }

    // `label` names the number in messages: "<radius>", "attribute x of <position>".
    double number(const XMLNode* at, const std::string& label, const std::string& text, Range range) const {
        ParsedNumber n = parseNumber(text);
        switch (n.kind) {
            case NumberKind::NotANumber:
                diag_.fail(at, label + " must be a number, got " + inQuotes(text));
            case NumberKind::NotFinite:
                diag_.fail(at, label + " must be a finite number, got " + inQuotes(text));
            case NumberKind::Overflow:
                diag_.fail(at, label + " must be within ±1e6, got " + text);
            case NumberKind::Finite:
                break;
        }
        if (std::abs(n.value) > kMaxMagnitude) diag_.fail(at, label + " must be within ±1e6, got " + text);
        if (!range.contains(n.value)) diag_.fail(at, label + " must be " + range.describe() + ", got " + text);
        return n.value;
    }
    double number(const XMLElement* e, Range range = kAnyValue) const {
        return number(e, tag(e->Name()), valueText(e), range);
    }

    int integer(const XMLElement* e, int lo, int hi) const {
        std::string text = valueText(e);
        std::string_view digits = withoutPlus(text);
        int value = 0;
        auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (digits.empty() || end != digits.data() + digits.size() || ec == std::errc::invalid_argument)
            diag_.fail(e, tag(e->Name()) + " must be an integer, got " + inQuotes(text));
        if (ec == std::errc::result_out_of_range || value < lo || value > hi)
            diag_.fail(e, tag(e->Name()) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                              "], got " + text);
        return value;
    }

    bool boolean(const XMLElement* e) const {
        std::string text = valueText(e);
        std::string lower = text;
        std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
        if (lower == "true" || lower == "1") return true;
        if (lower == "false" || lower == "0") return false;
        diag_.fail(e, tag(e->Name()) + " must be true or false, got " + inQuotes(text));
    }

    // The numbers of a vector or colour, in the order of `wanted`, from
    // one of two forms: attributes (<p x=".." y=".." z=".."/>) or child
    // elements (<p><x>..</x>...</p>). A left-out optional component reads 0.
    std::array<double, 4> components(const XMLElement* e, const std::vector<Component>& wanted) const {
        std::vector<std::string> names;
        for (const Component& c : wanted) names.emplace_back(c.name);
        std::array<double, 4> values{};

        if (e->FirstAttribute() && e->FirstChildElement())
            diag_.fail(e, tag(e->Name()) + " mixes attributes and child elements; use one form");
        if (e->FirstAttribute()) {
            for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
                if (std::find(names.begin(), names.end(), a->Name()) == names.end())
                    diag_.fail(e, "unknown attribute \"" + std::string(a->Name()) + "\" on " + tag(e->Name()) +
                                      "; expected " + joined(names));
            for (const XMLNode* node = e->FirstChild(); node; node = node->NextSibling())
                if (const XMLText* text = node->ToText()) diag_.refuseText(text, e);
            for (size_t i = 0; i < wanted.size(); ++i) {
                const Component& c = wanted[i];
                const char* text = e->Attribute(std::string(c.name).c_str());
                if (!text) {
                    if (c.optional) continue;
                    diag_.fail(e, tag(e->Name()) + " is missing attribute \"" + std::string(c.name) + "\"");
                }
                values[i] =
                    number(e, "attribute " + std::string(c.name) + " of " + tag(e->Name()), trimmed(text), c.range);
            }
            return values;
        }

        std::vector<ChildRule> rules;
        for (const Component& c : wanted) rules.push_back({c.name});
        ElementReader children(diag_, e, rules);
        for (size_t i = 0; i < wanted.size(); ++i) {
            const Component& c = wanted[i];
            const XMLElement* child = c.optional ? children.optional(c.name) : children.required(c.name);
            if (child) values[i] = number(child, tag(c.name) + " of " + tag(e->Name()), valueText(child), c.range);
        }
        return values;
    }

    glm::dvec3 vector(const XMLElement* e, Range range = kAnyValue) const {
        auto v = components(e, {{"x", range}, {"y", range}, {"z", range}});
        return {v[0], v[1], v[2]};
    }

    glm::dvec3 direction(const XMLElement* e) const {
        glm::dvec3 v = vector(e);
        double length = glm::length(v);
        if (!(length > kMinLength)) diag_.fail(e, tag(e->Name()) + " must not be the zero vector");
        return v / length;
    }

    // r, g, b within `channel`; the seed's alpha is accepted in [0, 1] and unused.
    glm::dvec3 colour(const XMLElement* e, Range channel) const {
        auto v = components(e, {{"r", channel}, {"g", channel}, {"b", channel}, {"a", kUnitInterval, true}});
        return {v[0], v[1], v[2]};
    }

    // ---- Camera ----

    Camera readCamera(const XMLElement* e) const {
        ElementReader c(diag_, e,
                        {{"position"}, {"window_position"}, {"up"}, {"fov"}, {"window_height"}, {"width"}, {"height"}});
        Camera camera;
        camera.eye = vector(c.required("position"));
        camera.windowCenter = vector(c.required("window_position"));
        glm::dvec3 forward = camera.windowCenter - camera.eye;
        double distance = glm::length(forward);
        if (!(distance > kMinLength)) diag_.fail(e, "camera <position> and <window_position> coincide");
        forward /= distance;

        // The image frame needs an up that is not along the view.
        if (const XMLElement* up = c.optional("up")) {
            camera.up = direction(up);
            if (parallel(forward, camera.up)) diag_.fail(up, "camera <up> is parallel to the viewing direction");
        } else if (parallel(forward, camera.up)) {
            diag_.fail(
                e, "camera looks along the default <up> (0, 1, 0); give an <up> not parallel to the viewing direction");
        }

        // The field of view, given directly or as the window's height at its
        // distance from the eye.
        const XMLElement* fov = c.optional("fov");
        const XMLElement* windowHeight = c.optional("window_height");
        if (fov && windowHeight)
            diag_.fail(laterOf(fov, windowHeight), "<camera> has both <fov> and <window_height>; give one");
        if (fov) camera.verticalFovDegrees = number(fov, kFovRange);
        if (windowHeight) {
            double height = number(windowHeight, kPositive);
            camera.verticalFovDegrees = glm::degrees(2.0 * std::atan(height / 2.0 / distance));
            if (!kFovRange.contains(camera.verticalFovDegrees))
                diag_.fail(windowHeight, "<window_height> gives a field of view of " +
                                             showBound(camera.verticalFovDegrees) + " degrees; it must be " +
                                             kFovRange.describe());
        }

        if (const XMLElement* width = c.optional("width")) camera.width = integer(width, 1, kMaxImageSize);
        if (const XMLElement* height = c.optional("height")) camera.height = integer(height, 1, kMaxImageSize);
        return camera;
    }

    // Of two siblings, the one that comes second in the document.
    static const XMLElement* laterOf(const XMLElement* a, const XMLElement* b) {
        for (const XMLElement* e = a; e; e = e->NextSiblingElement())
            if (e == b) return b;
        return a;
    }

    // ---- Lights ----

    void readLights(const XMLElement* e) {
        ElementReader lights(diag_, e, {{"light", true}});
        for (const XMLElement* light : lights.all("light")) {
            ElementReader l(diag_, light, {{"position"}, {"color"}});
            glm::dvec3 position = vector(l.required("position"));
            glm::dvec3 color = colour(l.required("color"), kNonNegative);
            scene_.lights.push_back({position, color});
        }
        if (scene_.lights.empty()) diag_.warn(e, "scene has no lights; only ambient light will show");
    }

    // ---- Objects ----

    void readObjects(const XMLElement* e) {
        ElementReader objects(diag_, e, {{"object", true}});
        for (const XMLElement* object : objects.all("object"))
            for (Object& o : readObject(object)) scene_.objects.push_back(std::move(o));
        if (scene_.objects.empty()) diag_.warn(e, "scene has no objects; the image will be black");
    }

    // A top-level <object> (csg == nullptr), or a child of a csg object:
    // then its position is relative to csg->origin, it must be a closed
    // solid, and without material elements it takes csg->material.
    struct CsgParent {
        glm::dvec3 origin;
        const Material* material;
        int depth;  // of the parent: 1 for a top-level csg object
    };

    // One object, or for a model file with materials of its own, used when
    // the scene gives the object no colour (README "Model files"), one per
    // material of the file (a csg child is one object: meshes are refused there).
    std::vector<Object> readObject(const XMLElement* e, const CsgParent* csg = nullptr) {
        ElementReader object(diag_, e,
                             {{"position"}, {"diffuse_color"}, {"specular_color"}, {"properties"}, {"objects"}});
        ElementReader properties(diag_, object.required("properties"), kPropertyRules);
        wantFileMaterials_ = !e->FirstChildElement("diffuse_color") &&
                             !properties.element()->FirstChildElement("diffuse_texture");
        fileMaterials_.clear();
        fileTriangleMaterials_.clear();

        const XMLElement* typeElement = properties.required("type");
        std::string type = valueText(typeElement);
        if (std::find(kTypeNames.begin(), kTypeNames.end(), type) == kTypeNames.end())
            diag_.fail(typeElement, "<type> must be " + joined(kTypeNames, " or ") + ", got " + inQuotes(type));
        if (csg && std::find(kCsgChildTypes.begin(), kCsgChildTypes.end(), type) == kCsgChildTypes.end())
            diag_.fail(typeElement, "a csg child cannot be of type " + type +
                                        "; it must be a closed solid: " + joined(kCsgChildTypes, " or "));
        if (csg && type == "csg" && csg->depth + 1 > int(kCsgMaxDepth))
            diag_.fail(e, "csg objects nested " + std::to_string(csg->depth + 1) + " deep; at most " +
                              std::to_string(kCsgMaxDepth) + " levels (the shader's evaluation stack)");
        glm::dvec3 origin = csg ? csg->origin : glm::dvec3(0);

        Object result;
        result.sourceLine = e->GetLineNum();
        bool ownMaterial = !csg || hasMaterial(e);
        result.material = ownMaterial ? readMaterial(object, properties) : *csg->material;
        if (type == "csg") {
            result.shape = readCsg(object, properties, origin, result.material, csg ? csg->depth + 1 : 1);
        } else {
            if (const XMLElement* objects = object.optional("objects"))
                diag_.fail(objects, "<objects> does not apply to type " + type + "; only a csg object has children");
            result.shape = readShape(type, object, properties, origin);
        }
        readTextures(type, properties, result);
        // A checker is anchored at the object's position (the origin without one).
        const XMLElement* position = object.optional("position");
        if (ownMaterial && position && result.material.checkerSize > 0)
            result.material.checkerOrigin = origin + vector(position);

        // The shape readers took what their type uses; anything left over
        // belongs to another type.
        if (const XMLElement* extra = properties.firstUnused())
            diag_.fail(extra, tag(extra->Name()) + " does not apply to type " + type);
        if (fileMaterials_.empty()) return {std::move(result)};
        return splitByFileMaterial(std::move(result));
    }

    // A model file's triangles grouped by their material, each group an
    // object with the scene's material but the file's base colour and
    // texture (the texture where the file has texture coordinates).
    std::vector<Object> splitByFileMaterial(Object whole) {
        const Mesh& mesh = std::get<Mesh>(whole.shape);
        std::vector<Object> parts;
        for (uint32_t k = 0; k < fileMaterials_.size(); ++k) {
            Object part;
            part.sourceLine = whole.sourceLine;
            part.material = whole.material;
            part.material.diffuseColor = fileMaterials_[k].baseColour;
            Mesh piece;
            for (size_t i = 0; i < mesh.triangles.size(); ++i) {
                if (fileTriangleMaterials_[i] != k) continue;
                piece.triangles.push_back(mesh.triangles[i]);
                if (!mesh.normals.empty()) piece.normals.push_back(mesh.normals[i]);
                if (!mesh.uvs.empty()) piece.uvs.push_back(mesh.uvs[i]);
                if (!mesh.tangents.empty()) piece.tangents.push_back(mesh.tangents[i]);
            }
            if (piece.triangles.empty()) continue;
            if (fileMaterials_[k].baseColourTexture && !piece.uvs.empty())
                part.material.diffuseTexture = {"", fileMaterials_[k].baseColourTexture};
            if (fileMaterials_[k].normalTexture && !piece.uvs.empty() && !part.material.normalMap)
                part.material.normalMap = {"", fileMaterials_[k].normalTexture};
            if (mesh.source) {
                piece.source = mesh.source;
                piece.source->part = int(parts.size());
            }
            part.shape = std::move(piece);
            parts.push_back(std::move(part));
        }
        return parts;
    }

    // ---- Textures ----

    // <diffuse_texture> and <normal_map> on every type but triangle (which
    // has no texture coordinates; a mesh of one polygon with <uv> has),
    // <normal_strength> with a <normal_map>, <texture_scale> on
    // planes only (README "Textures"). Left unread elsewhere, they are
    // reported as not applying to the type.
    void readTextures(const std::string& type, ElementReader& properties, Object& object) {
        if (type == "triangle") return;
        for (auto [name, encoding, target] : {std::tuple("diffuse_texture", TextureEncoding::Colour,
                                                         &object.material.diffuseTexture),
                                              std::tuple("normal_map", TextureEncoding::Data,
                                                         &object.material.normalMap)}) {
            const XMLElement* e = properties.optional(name);
            if (!e) continue;
            if (const Mesh* mesh = std::get_if<Mesh>(&object.shape); mesh && mesh->uvs.empty())
                diag_.fail(e, tag(name) + " on a mesh needs texture coordinates: the mesh file has none, or "
                                          "the <polygon>s have no <uv>");
            *target = readTexture(e, encoding);
        }
        if (const XMLElement* e = properties.optional("normal_strength")) {
            if (!object.material.normalMap)
                diag_.fail(e, "<normal_strength> needs <normal_map> beside it in <properties>");
            object.material.normalStrength = number(e, kNonNegative);
        }
        if (type == "plane")
            if (const XMLElement* e = properties.optional("texture_scale"))
                object.material.textureScale = number(e, kPositive);
    }

    // A texture file, its path relative to the scene file's folder; each
    // file is read once per scene.
    TextureRef readTexture(const XMLElement* e, TextureEncoding encoding) {
        std::string written = valueText(e);
        if (written.empty()) diag_.fail(e, tag(e->Name()) + " is empty; expected the path of an image file");
        std::filesystem::path path(written);
        if (path.is_relative()) path = scene_.sourcePath.parent_path() / path;
        auto& cached = textures_[{path, encoding}];
        if (!cached) {
            try {
                cached = std::make_shared<const TextureData>(readTextureFile(path, encoding));
            } catch (const TextureFileError& error) {
                diag_.fail(e, "texture file \"" + written + "\" " + error.what());
            }
        }
        return {written, cached};
    }

    // Whether an <object> (already checked by readObject's readers) gives
    // any material element.
    static bool hasMaterial(const XMLElement* object) {
        auto has = [](const XMLElement* e, std::string_view name) {
            return e && e->FirstChildElement(std::string(name).c_str()) != nullptr;
        };
        const XMLElement* properties = object->FirstChildElement("properties");
        return std::any_of(kObjectMaterialElements.begin(), kObjectMaterialElements.end(),
                           [&](std::string_view n) { return has(object, n); }) ||
               std::any_of(kMaterialProperties.begin(), kMaterialProperties.end(),
                           [&](std::string_view n) { return has(properties, n); });
    }

    static size_t leafCount(const Csg& csg) {
        size_t count = 0;
        for (const CsgChild& child : csg.children)
            count += std::holds_alternative<Csg>(child.shape) ? leafCount(std::get<Csg>(child.shape)) : 1;
        return count;
    }

    // A csg object (README "CSG"): <operation> in <properties>, its children
    // in <objects>, placed relative to its <position> (the parent's origin
    // without one). The leaves of a top-level csg object are limited by the
    // shader's fixed-size state (device_types.h).
    Csg readCsg(ElementReader& object, ElementReader& properties, const glm::dvec3& origin, const Material& material,
                int depth) {
        const XMLElement* e = object.element();
        Csg csg;
        const XMLElement* operation = properties.optional("operation");
        if (!operation) diag_.fail(e, "<object> is missing <operation> (required for type csg)");
        std::string op = valueText(operation);
        if (op == "union")
            csg.operation = Csg::Operation::Union;
        else if (op == "intersection")
            csg.operation = Csg::Operation::Intersection;
        else if (op == "difference")
            csg.operation = Csg::Operation::Difference;
        else
            diag_.fail(operation, "<operation> must be union, intersection or difference, got " + inQuotes(op));
        const XMLElement* position = object.optional("position");
        csg.position = origin + (position ? vector(position) : glm::dvec3(0));
        const XMLElement* objectsElement = object.optional("objects");
        if (!objectsElement) diag_.fail(e, "<object> is missing <objects> (required for type csg)");
        ElementReader objects(diag_, objectsElement, {{"object", true}});
        if (objects.all("object").size() < 2)
            diag_.fail(objectsElement, "<objects> of a csg object holds " +
                                           std::to_string(objects.all("object").size()) +
                                           " <object>; a csg object needs at least two");
        CsgParent parent{csg.position, &material, depth};
        for (const XMLElement* child : objects.all("object")) {
            Object o = std::move(readObject(child, &parent).front());  // one: no mesh children
            csg.children.push_back({std::move(o.shape), o.material, hasMaterial(child), o.sourceLine});
        }
        if (depth == 1 && leafCount(csg) > kCsgMaxLeaves)
            diag_.fail(e, "csg object has " + std::to_string(leafCount(csg)) +
                              " leaf shapes (spheres, cylinders, boxes) in all; at most " +
                              std::to_string(kCsgMaxLeaves) + " (the shader's span arrays)");
        return csg;
    }

    Material readMaterial(ElementReader& object, ElementReader& properties) const {
        Material m;
        if (const XMLElement* c = object.optional("diffuse_color")) m.diffuseColor = colour(c, kUnitInterval);
        if (const XMLElement* c = object.optional("specular_color")) m.specularColor = colour(c, kUnitInterval);
        if (const XMLElement* k = properties.optional("ambiente_coef")) m.ambient = number(k, kUnitInterval);
        if (const XMLElement* k = properties.optional("diffuse_coef")) m.diffuse = number(k, kUnitInterval);
        if (const XMLElement* k = properties.optional("specular_coef")) m.specular = number(k, kUnitInterval);
        if (const XMLElement* k = properties.optional("transmission_coef")) m.transmission = number(k, kUnitInterval);
        if (const XMLElement* k = properties.optional("refraction_coef")) m.ior = number(k, kIorRange);
        if (const XMLElement* k = properties.optional("shininess")) m.shininess = number(k, kShininessRange);

        // The seed's <reflective> switch mirrors with ks; <reflection_coef>
        // sets kr itself and must not contradict an explicit false.
        const XMLElement* reflective = properties.optional("reflective");
        const XMLElement* reflection = properties.optional("reflection_coef");
        bool isReflective = reflective && boolean(reflective);
        if (reflection) {
            if (reflective && !isReflective)
                diag_.fail(reflection, "<reflection_coef> contradicts <reflective>false</reflective>");
            m.reflection = number(reflection, kUnitInterval);
        } else if (isReflective) {
            m.reflection = m.specular;
        }

        // A checker takes its second colour and its cell size together.
        const XMLElement* checkerColor = properties.optional("checker_color");
        const XMLElement* checkerSize = properties.optional("checker_size");
        if (checkerColor && !checkerSize)
            diag_.fail(checkerColor, "<checker_color> needs <checker_size> beside it in <properties>");
        if (checkerSize && !checkerColor)
            diag_.fail(checkerSize, "<checker_size> needs <checker_color> beside it in <properties>");
        if (checkerColor) {
            m.checkerColor = colour(checkerColor, kUnitInterval);
            m.checkerSize = number(checkerSize, kPositive);
        }
        if (const XMLElement* a = properties.optional("absorption")) m.absorption = colour(a, kNonNegative);
        return m;
    }

    Shape readShape(const std::string& type, ElementReader& object, ElementReader& properties,
                    const glm::dvec3& origin) {
        // What the type requires is reported against <object>.
        auto missing = [&](std::string_view name) {
            diag_.fail(object.element(), "<object> is missing " + tag(name) + " (required for type " + type + ")");
        };
        auto need = [&](std::string_view name) {
            const XMLElement* e = properties.optional(name);
            if (!e) missing(name);
            return e;
        };

        // Only meshes and triangles, whose vertices are relative to it, may
        // leave the position out.
        const XMLElement* positionElement = object.optional("position");
        if (!positionElement && type != "mesh" && type != "triangle") missing("position");
        glm::dvec3 position = origin + (positionElement ? vector(positionElement) : glm::dvec3(0));

        if (type == "sphere") return Sphere{position, number(need("radius"), kPositive)};
        if (type == "cylinder") {
            double radius = number(need("radius"), kPositive);
            double height = number(need("height"), kPositive);
            const XMLElement* axis = properties.optional("axis");
            return Cylinder{position, axis ? direction(axis) : glm::dvec3(0, 1, 0), radius, height};
        }
        if (type == "plane") return Plane{position, direction(need("normal"))};
        if (type == "box") {
            const XMLElement* sizeElement = need("size");
            Box box{position, position + vector(sizeElement, kPositive)};
            // A size far below the position's magnitude vanishes when added.
            for (int i = 0; i < 3; ++i)
                if (!(box.min[i] < box.max[i]))
                    diag_.fail(sizeElement, std::string("<size> ") + "xyz"[i] +
                                                " is too small to register beside the <position>; the box would be flat");
            return box;
        }
        if (type == "triangle") {
            if (properties.all("vertex").empty()) missing("vertex");
            Triangle t = readTriangle(properties.element(), properties.all("vertex"), position);
            if (degenerate(t))
                diag_.fail(object.element(), "<object> of type triangle is degenerate: its vertices are collinear");
            return t;
        }
        return readMeshObject(object, properties, position);
    }

    Triangle readTriangle(const XMLElement* parent, const std::vector<const XMLElement*>& vertices,
                          const glm::dvec3& offset) const {
        if (vertices.size() != 3)
            diag_.fail(parent,
                       tag(parent->Name()) + " has " + std::to_string(vertices.size()) + " <vertex>, expected 3");
        return {offset + vector(vertices[0]), offset + vector(vertices[1]), offset + vector(vertices[2])};
    }

    // ---- Meshes ----

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

    static glm::dmat3 rotationXyz(const glm::dvec3& degrees) {
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
    Placement readPlacement(ElementReader& properties, const glm::dvec3& position) const {
        Placement placement;
        placement.offset = position;
        glm::dvec3 scale(1.0), rotation(0.0);
        if (const XMLElement* e = properties.optional("scale")) {
            scale = e->FirstAttribute() || e->FirstChildElement() ? vector(e, kPositive)
                                                                  : glm::dvec3(number(e, kPositive));
            placement.identity = false;
        }
        if (const XMLElement* e = properties.optional("rotation")) {
            rotation = vector(e);
            placement.identity = false;
        }
        placement.scale = scale;
        placement.rotationDegrees = rotation;
        glm::dmat3 r = rotationXyz(rotation);
        placement.linear = r * glm::dmat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
        placement.normalLinear = r * glm::dmat3(1 / scale.x, 0, 0, 0, 1 / scale.y, 0, 0, 0, 1 / scale.z);
        return placement;
    }

    static std::string outOfRange(const glm::dvec3& v) {
        std::array<char, 96> text{};
        std::snprintf(text.data(), text.size(), "(%g, %g, %g)", v.x, v.y, v.z);
        return std::string("<scale> and <rotation> take vertex ") + text.data() +
               " beyond ±1e6 of the object's <position>";
    }

    // A mesh has either inline <polygons> or a model <file>.
    Mesh readMeshObject(ElementReader& object, ElementReader& properties, const glm::dvec3& position) {
        const XMLElement* polygons = properties.optional("polygons");
        const XMLElement* file = properties.optional("file");
        if (polygons && file)
            diag_.fail(laterOf(polygons, file), "<properties> has both <polygons> and <file>; a mesh takes one");
        if (!polygons && !file)
            diag_.fail(object.element(), "<object> is missing <polygons> or <file> (required for type mesh)");
        Placement placement = readPlacement(properties, position);
        return polygons ? readMesh(polygons, placement) : readMeshFile(file, placement);
    }

    // Degenerate polygons are dropped with a warning; a mesh needs at least
    // one that is not.
    Mesh readMesh(const XMLElement* e, const Placement& placement) {
        ElementReader polygons(diag_, e, {{"polygon", true}});
        if (polygons.all("polygon").empty()) diag_.fail(e, "<polygons> has no <polygon>; a mesh needs at least one");
        Mesh mesh;
        std::optional<bool> withUv;  // from the first polygon
        for (const XMLElement* polygon : polygons.all("polygon")) {
            ElementReader vertices(diag_, polygon, {{"vertex", true}, {"uv", true}});
            Triangle local = readTriangle(polygon, vertices.all("vertex"), glm::dvec3(0));
            // Texture coordinates: one <uv u=".." v=".."/> per vertex, in
            // the vertices' order, on every polygon or on none.
            const std::vector<const XMLElement*>& uvs = vertices.all("uv");
            if (!uvs.empty() && uvs.size() != 3)
                diag_.fail(polygon,
                           "<polygon> has " + std::to_string(uvs.size()) + " <uv>, expected 3 (one per <vertex>)");
            if (withUv && *withUv == uvs.empty())
                diag_.fail(polygon, uvs.empty() ? "<polygon> has no <uv>, but the first <polygon> has"
                                                : "<polygon> has <uv>, but the first <polygon> has none");
            withUv = !uvs.empty();
            std::array<glm::dvec2, 3> uv{};
            for (size_t k = 0; k < uvs.size(); ++k) {
                auto c = components(uvs[k], {{"u", kAnyValue}, {"v", kAnyValue}});
                uv[k] = {c[0], c[1]};
            }
            for (const glm::dvec3& v : {local.v0, local.v1, local.v2})
                if (!placement.inRange(v)) diag_.fail(polygon, outOfRange(v));
            Triangle t{placement.point(local.v0), placement.point(local.v1), placement.point(local.v2)};
            if (degenerate(t)) {
                diag_.warn(polygon, "degenerate polygon skipped");
                continue;
            }
            mesh.triangles.push_back(t);
            if (!uvs.empty()) mesh.uvs.push_back(uv);
        }
        if (mesh.triangles.empty()) diag_.fail(e, "every <polygon> in <polygons> is degenerate");
        return mesh;
    }

    // A model file (host/io/mesh_file.h), its path relative to the scene
    // file's folder. Degenerate triangles are dropped with one warning.
    Mesh readMeshFile(const XMLElement* e, const Placement& placement) {
        std::string written = valueText(e);
        if (written.empty()) diag_.fail(e, "<file> is empty; expected the path of a model file");
        std::filesystem::path path(written);
        if (path.is_relative()) path = scene_.sourcePath.parent_path() / path;
        std::string name = "mesh file \"" + written + "\"";
        MeshFileData data;
        try {
            // Tangents where a normal map may apply: the scene's or the file's.
            bool tangents = wantFileMaterials_ || e->Parent()->FirstChildElement("normal_map");
            data = whitted::readMeshFile(path, wantFileMaterials_ ? MeshFileMaterials::Read : MeshFileMaterials::Ignore,
                                         tangents);
        } catch (const MeshFileError& error) {
            diag_.fail(e, name + " " + error.what());
        }

        Mesh mesh;
        size_t skipped = 0;
        for (size_t i = 0; i < data.triangles.size(); ++i) {
            const auto& v = data.triangles[i];
            for (const glm::dvec3& p : v)
                if (!placement.inRange(p)) diag_.fail(e, name + ": " + outOfRange(p));
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
            if (!data.triangleMaterials.empty()) fileTriangleMaterials_.push_back(data.triangleMaterials[i]);
            if (!data.normals.empty()) {
                const auto& n = data.normals[i];
                mesh.normals.push_back({placement.normal(n[0]), placement.normal(n[1]), placement.normal(n[2])});
            }
        }
        if (mesh.triangles.empty()) diag_.fail(e, "every triangle in " + name + " is degenerate");
        mesh.source = Mesh::FileSource{std::filesystem::absolute(path).lexically_normal(), placement.offset,
                                       placement.scale, placement.rotationDegrees};
        if (!data.triangleMaterials.empty()) fileMaterials_ = std::move(data.materials);
        if (skipped > 0)
            diag_.warn(e, name + ": " + std::to_string(skipped) + " degenerate triangle" + (skipped > 1 ? "s" : "") +
                              " skipped");
        return mesh;
    }

    Diagnostics diag_;
    Scene& scene_;
    std::map<std::pair<std::filesystem::path, TextureEncoding>, std::shared_ptr<const TextureData>> textures_;
    // The object being read: whether a model file's materials apply, and
    // those read with each kept triangle's index into them.
    bool wantFileMaterials_ = false;
    std::vector<MeshFileMaterial> fileMaterials_;
    std::vector<uint32_t> fileTriangleMaterials_;
};

// tinyxml2's ErrorStr() is "Error=NAME ErrorID=N (0xN) Line number=L: detail"
// (the detail is optional); the line goes in front, so keep the name and the
// detail.
std::string xmlErrorMessage(const tinyxml2::XMLDocument& doc) {
    std::string message = std::string("malformed XML: ") + doc.ErrorName();
    std::string full = doc.ErrorStr();
    size_t lineField = full.find("Line number=");
    size_t detail = lineField == std::string::npos ? std::string::npos : full.find(": ", lineField);
    if (detail != std::string::npos) message += " (" + full.substr(detail + 2) + ")";
    // tinyxml2's catch-all: a node that starts on this line did not parse and
    // said nothing more; mostly an element the file ends inside, or a '<'
    // that starts no valid tag.
    else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING)
        message += " (a tag that starts on this line is invalid or never closed)";
    return message;
}

// The line of xml[offset], counting from 1.
int lineOf(std::string_view xml, size_t offset) {
    return 1 + int(std::count(xml.begin(), xml.begin() + std::ptrdiff_t(offset), '\n'));
}

}  // namespace

Scene loadSceneFromString(std::string_view xml, const std::filesystem::path& name) {
    // tinyxml2 reads UTF-8 only, and stops at a NUL byte: it would take
    // whatever came before it as the whole file.
    if (xml.starts_with("\xFF\xFE") || xml.starts_with("\xFE\xFF"))
        throw SceneError(name.string(), 1, "the file is UTF-16; a scene file is UTF-8 XML text");
    if (size_t nul = xml.find('\0'); nul != std::string_view::npos)
        throw SceneError(name.string(), lineOf(xml, nul), "NUL byte; a scene file is UTF-8 XML text, not binary data");
    // Nothing but XML whitespace, after a UTF-8 byte order mark if any
    // (tinyxml2 calls most of these XML_ERROR_EMPTY_DOCUMENT).
    std::string_view content = xml.starts_with("\xEF\xBB\xBF") ? xml.substr(3) : xml;
    if (content.find_first_not_of(" \t\r\n") == std::string_view::npos)
        throw SceneError(name.string(), 1, "the file is empty, expected a <scene> document");
    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
        throw SceneError(name.string(), doc.ErrorLineNum(), xmlErrorMessage(doc));
    Scene scene;
    SceneReader(name, scene).read(doc);
    return scene;
}

Scene loadScene(const std::filesystem::path& path) {
    auto cannotRead = [&](const std::string& reason) {
        return SceneError(path.string(), 0, "cannot read file: " + reason);
    };
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw cannotRead("it is a directory");
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw cannotRead(errno ? std::generic_category().message(errno) : "cannot open it");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw cannotRead("read error");
    return loadSceneFromString(text, path);
}

}  // namespace whitted

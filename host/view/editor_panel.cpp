#include "view/editor_panel.h"

#include "scene/scene_loader.h"

#include <imgui/imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <variant>

namespace whitted {
namespace {

// ImGui edits floats; the scene keeps doubles.
bool editVector(const char* label, glm::dvec3& v, float speed) {
    float f[3] = {float(v.x), float(v.y), float(v.z)};
    if (!ImGui::DragFloat3(label, f, speed)) return false;
    v = glm::dvec3(f[0], f[1], f[2]);
    return true;
}

bool editColour(const char* label, glm::dvec3& c, bool hdr) {
    float f[3] = {float(c.r), float(c.g), float(c.b)};
    bool edited = hdr ? ImGui::ColorEdit3(label, f, ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_Float)
                      : ImGui::ColorEdit3(label, f);
    if (!edited) return false;
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(double(f[i]), 0.0, hdr ? 1e6 : 1.0);
    return true;
}

bool editScalar(const char* label, double& v, double lo, double hi) {
    float f = float(v);
    if (!ImGui::SliderFloat(label, &f, float(lo), float(hi))) return false;
    v = std::clamp(double(f), lo, hi);
    return true;
}

}  // namespace

void drawOverlay(const OverlayInfo& info) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                             ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs;
    if (ImGui::Begin("##overlay", nullptr, flags)) {
        ImGui::Text("%u / %u spp   %.1f ms/frame   %.2f Mrays/s", info.samples, info.target, info.frameMs,
                    info.raysPerSecond / 1e6);
        ImGui::Text("%s   [%s]", info.device.c_str(), info.layer.c_str());
        if (!info.status.empty()) ImGui::TextUnformatted(info.status.c_str());
    }
    ImGui::End();

    // A refused reload: a red banner across the bottom until a good one.
    if (!info.error.empty()) {
        const ImGuiViewport* vp = ImGui::GetMainViewport();
        ImGui::SetNextWindowPos(ImVec2(0, vp->Size.y), ImGuiCond_Always, ImVec2(0, 1));
        ImGui::SetNextWindowSize(ImVec2(vp->Size.x, 0), ImGuiCond_Always);
        ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.75f, 0.05f, 0.05f, 1.0f));
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 1, 1, 1));
        if (ImGui::Begin("##error", nullptr, flags)) {
            ImGui::TextUnformatted("Scene not reloaded (showing the last good one):");
            ImGui::TextWrapped("%s", info.error.c_str());
        }
        ImGui::End();
        ImGui::PopStyleColor(2);
    }
}

// The parts of one model file split by its own materials (scenes/README.md "Model
// files") are one object to the user: an edit of a part (its placement, its
// material apart from the file's colour and textures) is applied to the
// others, so the scene writer, which names the file once, saves what the
// window shows. `moved` is how far the edited part's shape moved.
static void syncModelParts(Scene& scene, int object, const glm::dvec3& moved) {
    const Object& edited = scene.objects[object];
    const Mesh* mesh = std::get_if<Mesh>(&edited.shape);
    if (!mesh || !mesh->source || mesh->source->part < 0) return;
    for (int j = 0; j < int(scene.objects.size()); ++j) {
        Object& other = scene.objects[j];
        const Mesh* part = std::get_if<Mesh>(&other.shape);
        if (j == object || !part || !part->source || part->source->part < 0 ||
            part->source->path != mesh->source->path || other.sourceLine != edited.sourceLine)
            continue;
        if (moved != glm::dvec3(0)) translateShape(other.shape, moved);
        Material own = other.material;
        other.material = edited.material;
        other.material.diffuseColor = own.diffuseColor;
        for (size_t k = 0; k < own.textures().size(); ++k) *other.material.textures()[k] = *own.textures()[k];
    }
}

// The lists of lights and objects: a click selects one of them.
static void drawSelectionLists(const Scene& scene, EditorState& state) {
    if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen))
        for (int i = 0; i < int(scene.lights.size()); ++i) {
            char label[32];
            static const char* kTypes[] = {"point", "spot", "directional"};
            std::snprintf(label, sizeof label, "light %d: %s", i,
                          scene.lights[i].name.empty() ? kTypes[int(scene.lights[i].type)]
                                                       : scene.lights[i].name.c_str());
            if (ImGui::Selectable(label, state.selectedLight == i)) {
                state.selectedLight = i;
                state.selectedObject = -1;
            }
        }
    if (ImGui::CollapsingHeader("Objects", ImGuiTreeNodeFlags_DefaultOpen))
        for (int i = 0; i < int(scene.objects.size()); ++i) {
            const Object& o = scene.objects[i];
            char label[96];
            if (o.name.empty())
                std::snprintf(label, sizeof label, "%d: %s (line %d)", i, shapeName(o.shape), o.sourceLine);
            else
                std::snprintf(label, sizeof label, "%d: %s, %s (line %d)", i, o.name.c_str(), shapeName(o.shape),
                              o.sourceLine);
            if (ImGui::Selectable(label, state.selectedObject == i)) {
                state.selectedObject = i;
                state.selectedLight = -1;
            }
        }
}

// The selected light's fields. Returns whether one changed.
static bool editLight(Light& l, int index) {
    bool changed = false;
    ImGui::Text("light %d", index);
    // The light's type and what it uses (scenes/README.md "Lights"); the
    // ranges are the loader's, so that Save writes a loadable file.
    int type = int(l.type);
    if (ImGui::Combo("type", &type, "point\0spot\0directional\0rect\0")) {
        l.type = Light::Type(type);
        changed = true;
    }
    if (l.type != Light::Type::Directional) changed |= editVector("position", l.position, 0.02f);
    changed |= editColour("colour", l.color, true);
    float intensity = float(l.intensity);
    if (ImGui::DragFloat("intensity", &intensity, 0.01f, 0.0f, 1e5f)) {
        l.intensity = std::max(double(intensity), 0.0);
        changed = true;
    }
    if (l.type != Light::Type::Directional) {
        bool inverseSquare = l.falloff == Light::Falloff::InverseSquare;
        if (ImGui::Checkbox("inverse-square falloff", &inverseSquare)) {
            l.falloff = inverseSquare ? Light::Falloff::InverseSquare : Light::Falloff::None;
            changed = true;
        }
    }
    if (l.type == Light::Type::Spot || l.type == Light::Type::Directional) {
        glm::dvec3 d = l.direction;
        if (editVector("direction", d, 0.01f) && glm::length(d) > 1e-6) {
            l.direction = glm::normalize(d);
            changed = true;
        }
    }
    if (l.type == Light::Type::Spot) {
        changed |= editScalar("inner angle", l.innerAngleDegrees, 0, 89.9);
        changed |= editScalar("outer angle", l.outerAngleDegrees, 0.1, 90);
        // 0 <= inner < outer <= 90: the outer angle gives way.
        if (l.outerAngleDegrees <= l.innerAngleDegrees)
            l.outerAngleDegrees = std::min(l.innerAngleDegrees + 0.1, 90.0);
    }
    // An area light (scenes/README.md "Area lights"): a sphere's radius,
    // a rectangle's edges (kept spanning an area) and faces, the shadow
    // rays per camera sample.
    if (l.type == Light::Type::Point || l.type == Light::Type::Spot)
        changed |= editScalar("radius", l.radius, 0, 10);
    if (l.type == Light::Type::Rect) {
        glm::dvec3 u = l.u, v = l.v;
        if (editVector("edge u", u, 0.01f) && rectEdgesSpan(u, l.v)) {
            l.u = u;
            changed = true;
        }
        if (editVector("edge v", v, 0.01f) && rectEdgesSpan(l.u, v)) {
            l.v = v;
            changed = true;
        }
        if (ImGui::Checkbox("two-sided", &l.twoSided)) changed = true;
    }
    if (l.area() && ImGui::SliderInt("shadow samples", &l.shadowSamples, 1, kMaxShadowSamples)) {
        l.shadowSamples = std::clamp(l.shadowSamples, 1, kMaxShadowSamples);
        changed = true;
    }
    return changed;
}

// The selected object's placement and the fields of its shape. Returns
// whether one changed.
static bool editShape(Object& o) {
    bool changed = false;
    glm::dvec3 p = shapeReferencePoint(o.shape);
    if (editVector("position", p, 0.02f)) {
        o.material.checkerOrigin += p - shapeReferencePoint(o.shape);  // the checker moves with the object
        translateShape(o.shape, p - shapeReferencePoint(o.shape));
        changed = true;
    }
    if (auto* sphere = std::get_if<Sphere>(&o.shape)) {
        float r = float(sphere->radius);
        if (ImGui::DragFloat("radius", &r, 0.01f, 1e-3f, 1e3f)) {
            sphere->radius = std::max(double(r), 1e-3);
            changed = true;
        }
    }
    if (auto* csg = std::get_if<Csg>(&o.shape)) {
        // The csg object's operation (scenes/README.md "CSG").
        int op = int(csg->operation);
        if (ImGui::Combo("operation", &op, "union\0intersection\0difference\0")) {
            csg->operation = Csg::Operation(op);
            changed = true;
        }
    }
    return changed;
}

// The selected object's material. Returns whether a field changed.
static bool editMaterial(Object& o) {
    bool changed = false;
    Material& m = o.material;
    const Mesh* mesh = std::get_if<Mesh>(&o.shape);
    bool filePart = mesh && mesh->source && mesh->source->part >= 0;
    if (filePart)  // the model file's colour, per part: not saved, so not edited
        ImGui::TextDisabled("diffuse colour: the model file's");
    else
        changed |= editColour("diffuse colour", m.diffuseColor, false);
    changed |= editColour("specular colour", m.specularColor, false);
    changed |= editScalar("ambient ka", m.ambient, 0, 1);
    changed |= editScalar("diffuse kd", m.diffuse, 0, 1);
    changed |= editScalar("specular ks", m.specular, 0, 1);
    changed |= editScalar("shininess", m.shininess, 1, 1000);
    changed |= editScalar("reflection kr", m.reflection, 0, 1);
    changed |= editScalar("transmission kt", m.transmission, 0, 1);
    changed |= editScalar("IOR (refraction_coef)", m.ior, 1, 3);
    changed |= editScalar("roughness", m.roughness, 0, 1);
    // The checker (<checker_color>, <checker_size>): switched on, size
    // 1 from checkerAnchor; switched off, size 0.
    bool checker = m.checkerSize > 0;
    if (ImGui::Checkbox("checker", &checker)) {
        if (checker) {
            m.checkerSize = 1.0;
            m.checkerOrigin = checkerAnchor(o.shape);
        } else {
            m.checkerSize = 0.0;
        }
        changed = true;
    }
    if (m.checkerSize > 0) {
        changed |= editColour("checker colour", m.checkerColor, false);
        float size = float(m.checkerSize);
        if (ImGui::DragFloat("checker size", &size, 0.01f, 1e-3f, 1e3f)) {
            m.checkerSize = std::max(double(size), 1e-3);
            changed = true;
        }
    }
    // Beer-Lambert sigma per unit length (<absorption>): any value >= 0.
    changed |= editColour("absorption", m.absorption, true);
    // The additions for authored scenes (scenes/README.md "Materials").
    if (ImGui::Checkbox("fresnel (kr is F0)", &m.fresnel)) changed = true;
    changed |= editColour("transmission colour", m.transmissionColor, false);
    changed |= editColour("emission", m.emission, true);
    bool ambientColour = m.ambientColor.has_value();
    if (ImGui::Checkbox("own ambient colour", &ambientColour)) {
        m.ambientColor = ambientColour ? std::optional<glm::dvec3>(m.diffuseColor) : std::nullopt;
        changed = true;
    }
    if (m.ambientColor) changed |= editColour("ambient colour", *m.ambientColor, false);
    // Texture controls (scenes/README.md "Textures"): a plane's repeat length, a
    // normal map's strength.
    if (std::holds_alternative<Plane>(o.shape) && m.textured()) {
        float scale = float(m.textureScale);
        if (ImGui::DragFloat("texture scale", &scale, 0.01f, 1e-3f, 1e3f)) {
            m.textureScale = std::max(double(scale), 1e-3);
            changed = true;
        }
    }
    if (m.normalMap) changed |= editScalar("normal strength", m.normalStrength, 0, 4);
    return changed;
}

// The selected object: its shape, then its material; an edit reaches the
// other parts of the same model file. Returns whether a field changed.
static bool editObject(Scene& scene, int index) {
    Object& o = scene.objects[index];
    ImGui::Text("object %d: %s", index, shapeName(o.shape));
    if (!o.name.empty()) ImGui::TextUnformatted(o.name.c_str());
    const glm::dvec3 before = shapeReferencePoint(o.shape);
    bool changed = editShape(o);
    changed |= editMaterial(o);
    if (changed) syncModelParts(scene, index, shapeReferencePoint(o.shape) - before);
    return changed;
}

// The camera's thin lens (scenes/README.md "Depth of field"): aperture 0 is a
// pinhole; the focus distance, once edited, no longer follows the window's
// distance. Returns whether the lens changed.
static bool editCameraLens(Camera& c) {
    bool changed = editScalar("aperture radius", c.apertureRadius, 0, 1);
    double focus = c.focusDistanceOrDefault();
    if (editScalar("focus distance", focus, 0.01, 100)) {
        c.focusDistance = focus;
        changed = true;
    }
    return changed;
}

// The environment (scenes/README.md "Environment"): its colours, rotation,
// intensity, visibility and shadow samples; its kind and image stay.
static bool editEnvironment(Environment& e) {
    bool changed = false;
    if (e.kind == Environment::Kind::Color) changed |= editColour("colour", e.color, true);
    if (e.kind == Environment::Kind::Gradient) {
        changed |= editColour("zenith", e.zenith, true);
        changed |= editColour("horizon", e.horizon, true);
        changed |= editColour("ground", e.ground, true);
    }
    changed |= editScalar("rotation", e.rotationDegrees, -360, 360);
    changed |= editScalar("intensity", e.intensity, 0, 16);
    changed |= ImGui::Checkbox("seen by the camera", &e.visible);
    int samples = e.shadowSamples;
    if (ImGui::SliderInt("shadow samples", &samples, 0, 64)) {
        e.shadowSamples = std::clamp(samples, 0, 256);
        changed = true;
    }
    return changed;
}

EditorResult drawEditorPanel(Scene& scene, EditorState& state) {
    EditorResult result;
    if (!state.visible) return result;
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    // Anchored to the top right corner, sized to what it shows.
    ImGui::SetNextWindowPos(ImVec2(vp->Size.x - 8, 8), ImGuiCond_Always, ImVec2(1, 0));
    ImGui::SetNextWindowBgAlpha(0.85f);
    // No taller than the window: a long list of fields scrolls instead.
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(vp->Size.x, std::max(vp->Size.y - 16, 64.0f)));
    if (!ImGui::Begin("Scene (F1 hides)", &state.visible, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::End();
        return result;
    }
    if (ImGui::Button("Save")) result.saveRequested = true;
    ImGui::SameLine();
    ImGui::TextDisabled("writes the scene file");
    drawSelectionLists(scene, state);

    ImGui::Separator();
    if (state.selectedLight >= 0 && state.selectedLight < int(scene.lights.size()))
        result.changed = editLight(scene.lights[state.selectedLight], state.selectedLight);
    else if (state.selectedObject >= 0 && state.selectedObject < int(scene.objects.size()))
        result.changed = editObject(scene, state.selectedObject);
    else
        ImGui::TextDisabled("select a light or an object");
    if (scene.environment && ImGui::CollapsingHeader("Environment"))
        result.changed |= editEnvironment(*scene.environment);
    // The camera's lens last, so that it moves nothing above.
    ImGui::Separator();
    if (ImGui::CollapsingHeader("Camera lens")) result.lensChanged = editCameraLens(scene.camera);
    ImGui::End();
    return result;
}

namespace {

struct FieldName {
    const char* name;
    ObjectField field;
};
constexpr FieldName kFieldNames[] = {
    {"ior", ObjectField::Ior},
    {"kt", ObjectField::Kt},
    {"kr", ObjectField::Kr},
    {"ks", ObjectField::Ks},
    {"kd", ObjectField::Kd},
    {"ka", ObjectField::Ka},
    {"x", ObjectField::X},
    {"y", ObjectField::Y},
    {"z", ObjectField::Z},
    {"operation", ObjectField::Operation},
    {"checker_size", ObjectField::CheckerSize},
    {"checker_r", ObjectField::CheckerR},
    {"checker_g", ObjectField::CheckerG},
    {"checker_b", ObjectField::CheckerB},
    {"absorption_r", ObjectField::AbsorptionR},
    {"absorption_g", ObjectField::AbsorptionG},
    {"absorption_b", ObjectField::AbsorptionB},
    {"texture_scale", ObjectField::TextureScale},
    {"normal_strength", ObjectField::NormalStrength},
};

std::string fieldName(ObjectField field) {
    for (const FieldName& f : kFieldNames)
        if (f.field == field) return f.name;
    return "?";
}

std::optional<std::string> noObject(const Scene& scene, int object) {
    if (object >= 0 && object < int(scene.objects.size())) return std::nullopt;
    return "no object " + std::to_string(object) + " (the scene has " + std::to_string(scene.objects.size()) + ")";
}

// The fields that apply to some objects only: why this one has none.
std::optional<std::string> fieldKindError(const Object& o, ObjectField field) {
    if (field == ObjectField::Operation && !std::holds_alternative<Csg>(o.shape))
        return std::string("operation applies to csg objects only");
    if (field == ObjectField::TextureScale && !std::holds_alternative<Plane>(o.shape))
        return std::string("texture_scale applies to planes only");
    if (field == ObjectField::NormalStrength && !o.material.normalMap)
        return std::string("normal_strength needs a normal map");
    return std::nullopt;
}

void setCheckedField(Object& o, ObjectField field, double value) {
    Material& m = o.material;
    switch (field) {
        case ObjectField::Ior: m.ior = value; return;
        case ObjectField::Kt: m.transmission = value; return;
        case ObjectField::Kr: m.reflection = value; return;
        case ObjectField::Ks: m.specular = value; return;
        case ObjectField::Kd: m.diffuse = value; return;
        case ObjectField::Ka: m.ambient = value; return;
        case ObjectField::Operation: std::get<Csg>(o.shape).operation = Csg::Operation(int(value)); return;
        // The checker's size (0 removes it; a new one starts at the
        // reference point), its colour and the absorption, one channel at a time.
        case ObjectField::CheckerSize:
            if (m.checkerSize == 0 && value > 0) m.checkerOrigin = checkerAnchor(o.shape);
            m.checkerSize = value;
            return;
        case ObjectField::CheckerR: m.checkerColor.r = value; return;
        case ObjectField::CheckerG: m.checkerColor.g = value; return;
        case ObjectField::CheckerB: m.checkerColor.b = value; return;
        case ObjectField::AbsorptionR: m.absorption.r = value; return;
        case ObjectField::AbsorptionG: m.absorption.g = value; return;
        case ObjectField::AbsorptionB: m.absorption.b = value; return;
        case ObjectField::TextureScale: m.textureScale = value; return;
        case ObjectField::NormalStrength: m.normalStrength = value; return;
        case ObjectField::X:
        case ObjectField::Y:
        case ObjectField::Z: {
            int axis = field == ObjectField::X ? 0 : field == ObjectField::Y ? 1 : 2;
            glm::dvec3 p = shapeReferencePoint(o.shape), target = p;
            target[axis] = value;
            m.checkerOrigin += target - p;
            translateShape(o.shape, target - p);
            return;
        }
    }
}

}  // namespace

std::optional<ObjectField> objectFieldNamed(const std::string& name) {
    for (const FieldName& f : kFieldNames)
        if (name == f.name) return f.field;
    return std::nullopt;
}

std::string unknownObjectField(const std::string& name) {
    return "unknown field '" + name +
           "' (ior, kt, kr, ks, kd, ka, x, y, z, operation, checker_size, checker_r|g|b, absorption_r|g|b, "
           "texture_scale, normal_strength)";
}

std::optional<std::string> objectFieldValueError(ObjectField field, double value) {
    if (!std::isfinite(value)) return std::string("value is not finite");
    auto within = [&](double low, double high, const std::string& range) -> std::optional<std::string> {
        if (value < low || value > high) return fieldName(field) + " must be " + range;
        return std::nullopt;
    };
    switch (field) {
        case ObjectField::Ior: return within(0.1, 10, "in [0.1, 10]");
        case ObjectField::Operation:
            if (value != 0 && value != 1 && value != 2)
                return std::string("operation must be 0 (union), 1 (intersection) or 2 (difference)");
            return std::nullopt;
        case ObjectField::CheckerSize:
        case ObjectField::AbsorptionR:
        case ObjectField::AbsorptionG:
        case ObjectField::AbsorptionB: return within(0, 1e6, "in [0, 1e6]");
        case ObjectField::TextureScale:
            if (!(value > 0) || value > 1e6) return std::string("texture_scale must be > 0");
            return std::nullopt;
        case ObjectField::NormalStrength: return within(0, 1e6, ">= 0");
        case ObjectField::Kt:
        case ObjectField::Kr:
        case ObjectField::Ks:
        case ObjectField::Kd:
        case ObjectField::Ka:
        case ObjectField::CheckerR:
        case ObjectField::CheckerG:
        case ObjectField::CheckerB: return within(0, 1, "in [0, 1]");
        case ObjectField::X:
        case ObjectField::Y:
        case ObjectField::Z: break;
    }
    return std::nullopt;
}

std::optional<std::string> setObjectField(Scene& scene, int object, ObjectField field, double value) {
    if (auto error = noObject(scene, object)) return error;
    Object& o = scene.objects[object];
    if (auto error = fieldKindError(o, field)) return error;
    if (auto error = objectFieldValueError(field, value)) return error;
    glm::dvec3 before = shapeReferencePoint(o.shape);
    setCheckedField(o, field, value);
    syncModelParts(scene, object, shapeReferencePoint(o.shape) - before);
    return std::nullopt;
}

std::optional<std::string> setObjectField(Scene& scene, int object, const std::string& field, double value) {
    std::optional<ObjectField> known = objectFieldNamed(field);
    if (!known) {
        if (auto error = noObject(scene, object)) return error;
        return unknownObjectField(field);
    }
    return setObjectField(scene, object, *known, value);
}

}  // namespace whitted

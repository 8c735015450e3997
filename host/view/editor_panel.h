// The live window's ImGui panels: the overlay (samples per pixel, frame
// time, rays per second, device, the layer shown, the reload error) and the
// scene editor (lights and objects; position, colours, coefficients; Save).
#pragma once

#include <optional>
#include <string>

#include "scene/scene.h"
#include "scene/shape_edit.h"  // translateShape, shapeReferencePoint, checkerAnchor, shapeName

namespace whitted {

struct OverlayInfo {
    std::string device;
    std::string layer;     // name of the image shown
    uint32_t samples = 0;  // completed samples per pixel
    uint32_t target = 0;
    double frameMs = 0;
    double raysPerSecond = 0;
    std::string error;   // the last refused reload, empty when fine
    std::string status;  // the last event (saved, reloaded, ...)
};

void drawOverlay(const OverlayInfo& info);

// Editor state kept between frames.
struct EditorState {
    bool visible = true;
    int selectedLight = -1;
    int selectedObject = -1;
};

// What the user did in the editor this frame.
struct EditorResult {
    bool changed = false;        // the scene was edited; re-upload it
    bool saveRequested = false;  // "Save" was pressed
    bool lensChanged = false;    // the camera's lens (aperture radius, focus distance) was edited
};

EditorResult drawEditorPanel(Scene& scene, EditorState& state);

// One field of an object, as the panel sets it: ior, kt, kr, ks, kd, ka (the
// material), checker_size (0: no checker), checker_r|g|b (its colour),
// absorption_r|g|b (sigma per unit length), x, y, z (moves the shape so its
// reference point has that coordinate) or a csg object's operation (0 union,
// 1 intersection, 2 difference), texture_scale (planes), normal_strength
// (with a normal map).
enum class ObjectField {
    Ior, Kt, Kr, Ks, Kd, Ka, X, Y, Z, Operation, CheckerSize, CheckerR, CheckerG, CheckerB,
    AbsorptionR, AbsorptionG, AbsorptionB, TextureScale, NormalStrength,
};

// The field of that name, if there is one; unknownObjectField is the
// error text for a name that is none (it lists the names).
std::optional<ObjectField> objectFieldNamed(const std::string& name);
std::string unknownObjectField(const std::string& name);
// A value the field never takes, whatever the object (not finite, or out
// of its range): the error text.
std::optional<std::string> objectFieldValueError(ObjectField field, double value);

// Sets the field; returns an error text for a bad index, a field the
// object does not have, or a bad value (the scene is then unchanged).
std::optional<std::string> setObjectField(Scene& scene, int object, ObjectField field, double value);
std::optional<std::string> setObjectField(Scene& scene, int object, const std::string& field, double value);

}  // namespace whitted

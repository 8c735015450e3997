// whitted.Light, a light of a scene as a view (edits change the scene), and
// the light Scene.add_light makes: the fields of <light>, checked as the XML
// loader checks them.
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/scene_loader.h"

#include <string>

namespace whitted::python {

const char* lightTypeName(Light::Type t) {
    switch (t) {
        case Light::Type::Spot: return "spot";
        case Light::Type::Directional: return "directional";
        case Light::Type::Rect: return "rect";
        case Light::Type::Point: break;
    }
    return "point";
}

namespace {

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
void setShadowSamples(const std::string& prefix, Light& l, long long samples) {
    if (samples < 1 || samples > kMaxShadowSamples) refuse(prefix + ".shadow_samples", "in 1.." + std::to_string(kMaxShadowSamples), std::to_string(samples));
    if (samples != 1 && !l.area()) refuse(prefix + ".shadow_samples", "1 for a light without area (a point or spot light of radius 0, a directional light)", std::to_string(samples));
    l.shadowSamples = int(samples);
}

}  // namespace

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
        if (!inner.is_none()) l.innerAngleDegrees = checked("add_light.inner_angle", typed<double>(inner, "add_light.inner_angle"), kInnerAngleRange);
        if (!outer.is_none()) l.outerAngleDegrees = checked("add_light.outer_angle", typed<double>(outer, "add_light.outer_angle"), kOuterAngleRange);
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

void addLightApi(py::module_& m) {
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
            [](const LightView& v, Arg<double> x) {
                v.l().intensity = checked("Light.intensity", x, xml::kNonNegative);
                ++v.s->versions.lights;
            })
        .def_property(
            "radius", [](const LightView& v) { return v.l().radius; },
            [](const LightView& v, Arg<double> x) {
                setRadius("Light", v.l(), x.get("Light.radius"));
                ++v.s->versions.lights;
            },
            "a point or spot light's sphere radius (0: a point)")
        .def_property(
            "shadow_samples", [](const LightView& v) { return v.l().shadowSamples; },
            [](const LightView& v, Arg<long long> x) {
                setShadowSamples("Light", v.l(), x.get("Light.shadow_samples"));
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
            [](const LightView& v, Arg<bool> arg) {
                bool x = arg.get("Light.two_sided");
                if (v.l().type != Light::Type::Rect && x) refuse("Light.two_sided", "False for a " + std::string(lightTypeName(v.l().type)) + " light (only a rect light has faces)", "True");
                v.l().twoSided = x;
                ++v.s->versions.lights;
            },
            "whether a rect light shines from both faces")
        .def("__repr__", [](const LightView& v) {
            return "Light(" + std::to_string(v.index()) + ", type='" + lightTypeName(v.l().type) + "')";
        });
}

}  // namespace whitted::python

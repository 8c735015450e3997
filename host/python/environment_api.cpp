// whitted.Environment and Scene.environment (host/python/README.md, scenes/README.md "Environment"): the
// scene file's <environment>, checked as the loader checks it.
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/scene_loader.h"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>
#include <string>

namespace whitted::python {
namespace {

// A value, not tied to a scene: scene.environment = e stores a copy.
struct EnvironmentValue {
    Environment e;
};

constexpr Range kRotationRange{-360, 360, false, false};

// Environment(color=, gradient=(zenith, horizon, ground), image=path or (H, W, 3) float array, rotation=,
// intensity=, visible=, shadow_samples=): exactly one of color, gradient and image.
EnvironmentValue makeEnvironment(const py::object& color, const py::object& gradient, const py::object& image,
                                 const Arg<double>& rotation, const Arg<double>& intensity, const Arg<bool>& visible,
                                 const Arg<long long>& shadowSamples) {
    int kinds = (color.is_none() ? 0 : 1) + (gradient.is_none() ? 0 : 1) + (image.is_none() ? 0 : 1);
    if (kinds != 1)
        throw py::value_error("Environment: give exactly one of color, gradient or image, got " +
                              std::to_string(kinds));
    EnvironmentValue v;
    Environment& e = v.e;
    if (!color.is_none()) {
        e.kind = Environment::Kind::Color;
        e.color = checked("Environment.color", toVec(color, "Environment.color"), xml::kNonNegative);
    } else if (!gradient.is_none()) {
        e.kind = Environment::Kind::Gradient;
        py::sequence g = gradient;
        if (py::isinstance<py::str>(gradient) || py::len(g) != 3)
            throw py::value_error("Environment.gradient: expected (zenith, horizon, ground), three colours");
        e.zenith = checked("Environment.gradient[0]", toVec(g[0], "Environment.gradient[0]"), xml::kNonNegative);
        e.horizon = checked("Environment.gradient[1]", toVec(g[1], "Environment.gradient[1]"), xml::kNonNegative);
        e.ground = checked("Environment.gradient[2]", toVec(g[2], "Environment.gradient[2]"), xml::kNonNegative);
    } else {
        e.kind = Environment::Kind::Image;
        TextureRef t = textureValue(image, TextureEncoding::Colour, "Environment.image");
        e.image = t.data;
        e.imageWritten = t.written;
    }
    e.rotationDegrees = checked("Environment.rotation", rotation, kRotationRange);
    e.intensity = checked("Environment.intensity", intensity, xml::kNonNegative);
    e.visible = visible.get("Environment.visible");
    long long samples = shadowSamples.get("Environment.shadow_samples");
    if (samples < 0 || samples > kMaxShadowSamples)
        refuse("Environment.shadow_samples", "in [0, " + std::to_string(kMaxShadowSamples) + "]",
               std::to_string(samples));
    e.shadowSamples = int(samples);
    return v;
}

const char* kindName(Environment::Kind k) {
    return k == Environment::Kind::Color ? "color" : k == Environment::Kind::Gradient ? "gradient" : "image";
}

}  // namespace

void addEnvironmentApi(py::module_& m) {
    py::class_<EnvironmentValue>(m, "Environment",
                                 "The world around the scene (scenes/README.md \"Environment\"): what rays that leave "
                                 "the scene see, and the light it gives")
        .def(py::init(&makeEnvironment), py::kw_only(), py::arg("color") = py::none(),
             py::arg("gradient") = py::none(), py::arg("image") = py::none(), py::arg("rotation") = 0.0,
             py::arg("intensity") = 1.0, py::arg("visible") = true, py::arg("shadow_samples") = 1,
             "color: (r, g, b) radiance >= 0; gradient: (zenith, horizon, ground) colours, linear in the "
             "direction's y; image: an equirectangular file path or an (H, W, 3) float array (linear); rotation: "
             "degrees about +y; intensity >= 0; visible: seen by camera rays; shadow_samples 0..256 (0: no light)")
        .def_property_readonly("kind", [](const EnvironmentValue& v) { return kindName(v.e.kind); })
        .def_property_readonly("color", [](const EnvironmentValue& v) { return toTuple(v.e.color); })
        .def_property_readonly("gradient",
                               [](const EnvironmentValue& v) {
                                   return py::make_tuple(toTuple(v.e.zenith), toTuple(v.e.horizon),
                                                         toTuple(v.e.ground));
                               })
        .def_property_readonly("image", [](const EnvironmentValue& v) { return v.e.imageWritten; })
        .def_property_readonly("rotation", [](const EnvironmentValue& v) { return v.e.rotationDegrees; })
        .def_property_readonly("intensity", [](const EnvironmentValue& v) { return v.e.intensity; })
        .def_property_readonly("visible", [](const EnvironmentValue& v) { return v.e.visible; })
        .def_property_readonly("shadow_samples", [](const EnvironmentValue& v) { return v.e.shadowSamples; })
        .def("__repr__", [](const EnvironmentValue& v) {
            return std::string("whitted.Environment(") + kindName(v.e.kind) + ", intensity=" + shown(v.e.intensity) +
                   ", rotation=" + shown(v.e.rotationDegrees) + ")";
        });

    auto scene = py::reinterpret_borrow<py::class_<SceneHandle, SceneRef>>(m.attr("Scene"));
    scene.def_property(
        "environment",
        [](const SceneRef& s) -> py::object {
            if (!s->scene->environment) return py::none();
            return py::cast(EnvironmentValue{*s->scene->environment});
        },
        [](const SceneRef& s, const py::object& x) {
            if (x.is_none())
                s->scene->environment.reset();
            else
                s->scene->environment = x.cast<const EnvironmentValue&>().e;
            ++s->versions.geometry;  // a full upload: the environment's image and distribution go with it
        },
        "The scene's Environment (a copy), or None: rays that leave the scene see black");
}

}  // namespace whitted::python

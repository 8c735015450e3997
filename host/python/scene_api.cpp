// whitted.load, loads, SceneError, and the editable Scene: camera, objects
// (placement and the material fields the window's editor panel edits, and
// a few more), lights, save, copy. Every setter checks its value against
// the scene format's range (the XML reader's) and raises ValueError naming
// the field and the range before anything reaches a device.
#include "app/quick_look.h"
#include "python/python_api.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "scene/xml_reader.h"
#include "view/editor_panel.h"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <cmath>
#include <string>

namespace whitted::python {

SceneHandle::SceneHandle(Scene s) : scene(std::make_shared<Scene>(std::move(s))) {
    static std::atomic<uint64_t> next{1};
    id = next++;
}

namespace {

using xml::Range;
constexpr Range kColourRange = xml::kUnitInterval;
constexpr Range kIor{0.1, 10, false, false};          // the loader's refraction_coef
constexpr Range kShininess{0, 1e5, true, false};      // the loader's shininess
constexpr Range kFov{0, 180, true, true};             // the loader's fov
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
struct ObjectView {
    SceneRef s;
    size_t index;
    Object& o() const {
        if (index >= s->scene->objects.size()) throw py::index_error("the object is no longer in its scene");
        return s->scene->objects[index];
    }
    std::string field(const char* name) const { return std::string("Object.") + name; }
};
struct LightView {
    SceneRef s;
    size_t index;
    Light& l() const {
        if (index >= s->scene->lights.size()) throw py::index_error("the light is no longer in its scene");
        return s->scene->lights[index];
    }
};

const char* lightTypeName(Light::Type t) {
    switch (t) {
        case Light::Type::Spot: return "spot";
        case Light::Type::Directional: return "directional";
        case Light::Type::Point: break;
    }
    return "point";
}

// A material field of an object: double or colour, with its range; an edit
// bumps the materials counter only.
template <typename T>
void materialField(py::class_<ObjectView>& cls, const char* name, T Material::*member, const Range& range,
                   const char* doc) {
    if constexpr (std::is_same_v<T, double>)
        cls.def_property(
            name, [member](const ObjectView& v) { return v.o().material.*member; },
            [member, name, range](const ObjectView& v, double x) {
                v.o().material.*member = checked(v.field(name), x, range);
                ++v.s->versions.materials;
            },
            doc);
    else
        cls.def_property(
            name, [member](const ObjectView& v) { return toTuple(v.o().material.*member); },
            [member, name, range](const ObjectView& v, py::object x) {
                v.o().material.*member = checked(v.field(name), toVec(x, v.field(name)), range);
                ++v.s->versions.materials;
            },
            doc);
}

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
        .def("__repr__", [](const CameraView& v) {
            return "Camera(position=" + py::repr(toTuple(v.c().eye)).cast<std::string>() +
                   ", look_at=" + py::repr(toTuple(v.c().windowCenter)).cast<std::string>() +
                   ", fov=" + shown(v.c().verticalFovDegrees) + ")";
        });

    py::class_<ObjectView> object(m, "Object", "An object of a scene (a view: edits change the scene)");
    object
        .def_property(
            "name", [](const ObjectView& v) { return v.o().name; },
            [](const ObjectView& v, const std::string& n) { v.o().name = n; }, "optional name (<name>)")
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
            "fresnel", [](const ObjectView& v) { return v.o().material.fresnel; },
            [](const ObjectView& v, bool f) {
                v.o().material.fresnel = f;
                ++v.s->versions.materials;
            },
            "reflection as Schlick's Fresnel term with kr as F0")
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
    materialField(object, "diffuse_color", &Material::diffuseColor, kColourRange, "Cd");
    materialField(object, "specular_color", &Material::specularColor, kColourRange, "Cs");
    materialField(object, "checker_color", &Material::checkerColor, kColourRange, "the checker's second colour");
    materialField(object, "absorption", &Material::absorption, xml::kNonNegative, "Beer-Lambert sigma per unit length");
    materialField(object, "transmission_color", &Material::transmissionColor, kColourRange, "tints refracted light");
    materialField(object, "emission", &Material::emission, xml::kNonNegative, "added where a ray hits");
    materialField(object, "ambient", &Material::ambient, kColourRange, "ka");
    materialField(object, "diffuse", &Material::diffuse, kColourRange, "kd");
    materialField(object, "specular", &Material::specular, kColourRange, "ks");
    materialField(object, "shininess", &Material::shininess, kShininess, "Phong exponent");
    materialField(object, "reflection", &Material::reflection, kColourRange, "kr");
    materialField(object, "transmission", &Material::transmission, kColourRange, "kt");
    materialField(object, "ior", &Material::ior, kIor, "index of refraction");
    materialField(object, "texture_scale", &Material::textureScale, xml::kPositive, "a plane's texture repeat length");
    materialField(object, "normal_strength", &Material::normalStrength, kNormalStrength, "normal map strength");
    object.def("__repr__", [](const ObjectView& v) {
        return "Object(" + std::to_string(v.index) + ", type='" + shapeName(v.o().shape) + "', name='" + v.o().name + "')";
    });

    py::class_<LightView>(m, "Light", "A light of a scene (a view: edits change the scene)")
        .def_property_readonly("type", [](const LightView& v) { return std::string(lightTypeName(v.l().type)); })
        .def_property(
            "name", [](const LightView& v) { return v.l().name; },
            [](const LightView& v, const std::string& n) { v.l().name = n; })
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
        .def("__repr__", [](const LightView& v) {
            return "Light(" + std::to_string(v.index) + ", type='" + lightTypeName(v.l().type) + "')";
        });

    py::class_<SceneHandle, SceneRef>(m, "Scene", "A scene: load() or loads() it, edit it, render it")
        .def_property_readonly("camera", [](const SceneRef& s) { return CameraView{s}; })
        .def_property_readonly("objects",
                               [](const SceneRef& s) {
                                   py::list l;
                                   for (size_t i = 0; i < s->scene->objects.size(); ++i) l.append(ObjectView{s, i});
                                   return l;
                               })
        .def_property_readonly("lights",
                               [](const SceneRef& s) {
                                   py::list l;
                                   for (size_t i = 0; i < s->scene->lights.size(); ++i) l.append(LightView{s, i});
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
            "save", [](const SceneRef& s, const std::filesystem::path& path) { writeSceneFile(*s->scene, path); },
            py::arg("path"), "writes the scene file (the scene writer: what the window's Save writes)")
        .def(
            "to_xml", [](const SceneRef& s) { return sceneXml(*s->scene); }, "the scene file's text")
        .def(
            "copy", [](const SceneRef& s) { return std::make_shared<SceneHandle>(*s->scene); },
            "an independent copy (textures are shared, read-only)")
        .def("__copy__", [](const SceneRef& s) { return std::make_shared<SceneHandle>(*s->scene); })
        .def("__deepcopy__", [](const SceneRef& s, py::dict) { return std::make_shared<SceneHandle>(*s->scene); })
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

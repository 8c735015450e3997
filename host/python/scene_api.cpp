// whitted.load, loads, SceneError, and the editable Scene: its camera,
// objects and lights as views (camera_api.cpp, object_api.cpp,
// light_api.cpp), what builds it (scene_build_api.cpp), save, to_xml,
// pickle, copy. Every setter checks its value against the scene format's
// range (the XML reader's) and raises ValueError naming the field and the
// range before anything reaches a device.
#include "io/texture_file.h"
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/quick_look.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <atomic>
#include <string>

namespace whitted::python {

SceneHandle::SceneHandle(Scene s) : scene(std::make_shared<Scene>(std::move(s))) {
    static std::atomic<uint64_t> next{1};
    id = next++;
    for (size_t i = 0; i < scene->objects.size(); ++i) objectIds.push_back(nextObjectId++);
    for (size_t i = 0; i < scene->lights.size(); ++i) lightIds.push_back(nextLightId++);
}

size_t indexOf(const std::vector<uint64_t>& ids, uint64_t id, const char* what) {
    auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) throw py::key_error(std::string("the ") + what + " was removed from its scene");
    return size_t(it - ids.begin());
}

namespace {

// Scene.copy(): an independent scene (a new handle, so a renderer uploads
// it afresh) that keeps the original's object and light ids, the ids still
// to come and each object's transform, so its masks and legend number the
// objects as the original's do.
SceneRef copyHandle(const SceneRef& s) {
    auto c = std::make_shared<SceneHandle>(*s->scene);
    c->objectIds = s->objectIds;
    c->lightIds = s->lightIds;
    c->nextObjectId = s->nextObjectId;
    c->nextLightId = s->nextLightId;
    c->transforms = s->transforms;
    return c;
}

// whitted.SceneError; a strong reference kept for the process's life (never
// released by a static destructor after the interpreter has gone).
PyObject* sceneError = nullptr;

// Scene's own fields and methods: its views, saving, copying.
void addSceneFields(py::class_<SceneHandle, SceneRef>& scene) {
    scene
        .def(py::pickle(
            [](const SceneRef& s) {
                refuseFilelessTextures(*s->scene, "pickle");
                return py::make_tuple(sceneXml(*s->scene), s->scene->sourcePath);
            },
            [](const py::tuple& state) {
                if (py::len(state) != 2) throw py::value_error("Scene.__setstate__: expected (xml, path)");
                auto path = state[1].cast<std::filesystem::path>();
                Scene scene = loadSceneFromString(state[0].cast<std::string>(), path.empty() ? "<pickled scene>" : path);
                scene.sourcePath = path;
                return std::make_shared<SceneHandle>(std::move(scene));
            }))
        .def_property_readonly("camera", [](const SceneRef& s) { return CameraView{s}; })
        .def_property_readonly("objects",
                               [](const SceneRef& s) {
                                   py::list l;
                                   for (uint64_t id : s->objectIds) l.append(ObjectView{s, id});
                                   return l;
                               })
        .def_property_readonly("lights",
                               [](const SceneRef& s) {
                                   py::list l;
                                   for (uint64_t id : s->lightIds) l.append(LightView{s, id});
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
            "save",
            [](const SceneRef& s, const std::filesystem::path& path) {
                // Textures made from arrays: written beside the file, named in it
                // (on a copy: the scene's own stay without a file).
                Scene copy = *s->scene;
                writeFilelessTextures(copy, path);
                writeSceneFile(copy, path);
            },
            py::arg("path"),
            "writes the scene file (the scene writer: what the window's Save writes), and textures made from arrays "
            "beside it")
        .def(
            "to_xml",
            [](const SceneRef& s) {
                refuseFilelessTextures(*s->scene, "Scene.to_xml");
                return sceneXml(*s->scene);
            },
            "the scene file's text")
        .def("copy", &copyHandle,
             "an independent copy with the same object ids and transforms (textures are shared, read-only)")
        .def("__copy__", &copyHandle)
        .def("__deepcopy__", [](const SceneRef& s, py::dict) { return copyHandle(s); })
        .def("__repr__", [](const SceneRef& s) {
            return "Scene('" + s->scene->sourcePath.string() + "', " + std::to_string(s->scene->objects.size()) +
                   " objects, " + std::to_string(s->scene->lights.size()) + " lights)";
        });
}

}  // namespace

void addSceneErrorApi(py::module_& m) {
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
}

void addSceneApi(py::module_& m) {
    py::class_<SceneHandle, SceneRef> scene(m, "Scene",
                                            "A scene: load() or loads() it, or build it (Scene()), edit it, render it");
    scene.def(py::init([] {
                  Scene empty;
                  empty.ambientLight = glm::dvec3(0);
                  return std::make_shared<SceneHandle>(std::move(empty));
              }),
              "an empty scene: the default camera, no lights, no objects, ambient light 0");
    addSceneBuilders(scene);
    addSceneFields(scene);

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

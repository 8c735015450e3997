// The Python module `whitted` (host/python/README.md): the scene side
// (scene_api.cpp) and the renderer side (render_api.cpp), registered by
// module.cpp. The top layer: it links the layers below but app and view (no
// command line, no window; host/CMakeLists.txt).
#pragma once

#include "scene/scene.h"

#include <pybind11/pybind11.h>

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

namespace whitted::python {

namespace py = pybind11;

// What the Python side edited since a renderer uploaded the scene: each
// setter bumps the counter of what it changes (render_api.cpp uploads only
// what moved).
struct Versions {
    uint64_t camera = 0, geometry = 0, materials = 0, lights = 0;
    bool operator==(const Versions&) const = default;
};

// A Scene of the module: the C++ scene, shared with the object, light and
// camera views handed out, and its edit counters. `id` is unique per scene
// (a copy gets a new one). objectIds and lightIds run beside scene->objects
// and scene->lights: the handle of each (scene_api.cpp's views hold it, so
// a view survives the removal of others); an id is never reused within
// the handle's life.
struct SceneHandle {
    std::shared_ptr<Scene> scene;
    Versions versions;
    uint64_t id = 0;
    std::vector<uint64_t> objectIds, lightIds;
    uint64_t nextObjectId = 0, nextLightId = 0;
    // Object.transform as last set, by object id (absent: the identity):
    // relative to the object as it was added or loaded.
    std::map<uint64_t, glm::dmat4> transforms;
    explicit SceneHandle(Scene s);
};
using SceneRef = std::shared_ptr<SceneHandle>;

// whitted.Camera: a scene's camera (scene.camera), or a detached one
// (Camera.copy(): a scene of its own holding only the camera).
struct CameraView {
    SceneRef s;
    Camera& c() const { return s->scene->camera; }
    void edited() const { ++s->versions.camera; }
};

void addSceneApi(py::module_& m);
void addCameraApi(py::module_& m);  // after addSceneApi: adds to its Camera class
void addRenderApi(py::module_& m);

}  // namespace whitted::python

// The Python module `whitted` (host/python/README.md): one binding function
// per class, each in its file (camera_api.cpp, object_api.cpp, light_api.cpp,
// material_api.cpp, mesh_api.cpp, scene_api.cpp with scene_build_api.cpp,
// render_api.cpp), registered by module.cpp; the views they share and what
// one class's file lends another. The top layer: it links the layers below
// but app and view (no command line, no window; host/CMakeLists.txt).
#pragma once

#include "io/texture_file.h"
#include "scene/scene.h"

#include <pybind11/pybind11.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
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
// and scene->lights: the handle of each (the views hold it, so
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

// Object and light views hold the handle's id of what they show: one
// removed raises KeyError, the others keep working.
size_t indexOf(const std::vector<uint64_t>& ids, uint64_t id, const char* what);
struct ObjectView {
    SceneRef s;
    uint64_t id;
    size_t index() const { return indexOf(s->objectIds, id, "object"); }
    Object& o() const { return s->scene->objects[index()]; }
};
struct LightView {
    SceneRef s;
    uint64_t id;
    size_t index() const { return indexOf(s->lightIds, id, "light"); }
    Light& l() const { return s->scene->lights[index()]; }
};

// whitted.Material: a material's values, not tied to a scene; an object
// takes a copy (Object.material = m).
struct MaterialValue {
    Material m;
};

// whitted.Mesh: the arrays add_mesh takes, held together (from_trimesh
// fills them from a trimesh.Trimesh), checked when added.
struct MeshArrays {
    py::object vertices, faces, normals, uvs;
};

// material_api.cpp: the material fields on Object and on Material; the
// material an object is given (a copy, its checker anchored on the shape);
// the refusal of textures made from arrays where a file must name them.
void addMaterialFields(py::class_<ObjectView>& cls);
void addMaterialFields(py::class_<MaterialValue>& cls);
Material materialFor(const Shape& shape, const py::object& material, const std::string& field);
// A texture from a path (read as the loader reads one, relative to the working folder) or an (H, W, 3|4)
// array, uint8 (sRGB-encoded) or float (linear), checked against the loader's limits; None: no texture.
TextureRef textureValue(const py::object& x, TextureEncoding encoding, const std::string& field);
void refuseFilelessTextures(const Scene& scene, const std::string& call);

// light_api.cpp: a light of add_light's arguments, checked as the loader checks <light>.
const char* lightTypeName(Light::Type t);
struct AreaArguments {
    double radius;
    long long shadowSamples;
    py::object u, v;
    bool twoSided;
};
Light buildLight(const py::object& position, const py::object& color, const std::string& type, double intensity,
                 const std::string& falloff, const py::object& direction, const py::object& inner,
                 const py::object& outer, const py::object& name, const AreaArguments& area);

// mesh_api.cpp: add_mesh's arrays as a mesh; add_file's objects.
Mesh buildMesh(const py::object& vertices, const py::object& faces, const py::object& normals, const py::object& uvs,
               const py::object& transform);
std::vector<Object> fileObjects(const std::filesystem::path& path, const py::object& part, const py::object& transform);

// The classes, in the order module.cpp registers them (a class is
// registered before a signature names it).
void addSceneErrorApi(py::module_& m);
void addCameraApi(py::module_& m);
void addMaterialApi(py::module_& m);
void addObjectApi(py::module_& m);
void addLightApi(py::module_& m);
void addMeshApi(py::module_& m);
void addSceneApi(py::module_& m);  // Scene, load, loads
// environment_api.cpp: whitted.Environment, and Scene.environment on the class addSceneApi registered.
void addEnvironmentApi(py::module_& m);
void addSceneBuilders(py::class_<SceneHandle, SceneRef>& scene);  // scene_build_api.cpp: add_*, remove
void addRenderApi(py::module_& m);

}  // namespace whitted::python

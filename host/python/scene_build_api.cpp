// Scene.add_sphere, add_box, add_plane, add_cylinder, add_triangle,
// add_mesh, add_file, add_light and remove: a scene built from Python, each
// value checked as the XML loader checks it before anything is added
// (host/python/README.md "Building a scene").
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/mesh_objects.h"
#include "scene/shape_edit.h"

#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <string>

namespace whitted::python {
namespace {

using SceneClass = py::class_<SceneHandle, SceneRef>;

ObjectView addObject(const SceneRef& s, Shape shape, const py::object& material, const py::object& name,
                     const std::string& call) {
    Object o;
    o.material = materialFor(shape, material, call + ".material");
    o.shape = std::move(shape);
    o.name = checkedName(call + ".name", name);
    s->scene->objects.push_back(std::move(o));
    s->objectIds.push_back(s->nextObjectId++);
    ++s->versions.geometry;  // a new renderer scene: geometry, BVH, materials, lights
    return ObjectView{s, s->objectIds.back()};
}

// The shapes of the scene format's fields.
void addShapeBuilders(SceneClass& scene) {
    scene
        .def(
            "add_sphere",
            [](const SceneRef& s, py::object center, Arg<double> radius, py::object material, py::object name) {
                Sphere sphere{placed(checked("add_sphere.center", toVec(center, "add_sphere.center"), xml::kAnyValue)),
                              checked("add_sphere.radius", radius, xml::kPositive)};
                return addObject(s, sphere, material, name, "add_sphere");
            },
            py::arg("center"), py::arg("radius"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_box",
            [](const SceneRef& s, py::object min, py::object size, py::object material, py::object name) {
                glm::dvec3 lo = placed(checked("add_box.min", toVec(min, "add_box.min"), xml::kAnyValue));
                glm::dvec3 sz = checked("add_box.size", toVec(size, "add_box.size"), xml::kPositive);
                glm::dvec3 hi = lo + sz;
                for (int i = 0; i < 3; ++i)
                    if (!(lo[i] < hi[i]))
                        refuse("add_box.size", std::string("large enough to register beside min in ") + "xyz"[i], shown(sz[i]));
                for (int i = 0; i < 8; ++i) {  // what <position> + <size> gives back
                    glm::dvec3 again = lo + (hi - lo);
                    if (again == hi) break;
                    hi = again;
                }
                return addObject(s, Box{lo, hi}, material, name, "add_box");
            },
            py::arg("min"), py::arg("size"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_plane",
            [](const SceneRef& s, py::object point, py::object normal, py::object material, py::object name) {
                Plane plane{placed(checked("add_plane.point", toVec(point, "add_plane.point"), xml::kAnyValue)),
                            loaderDirection("add_plane.normal", toVec(normal, "add_plane.normal"))};
                return addObject(s, plane, material, name, "add_plane");
            },
            py::arg("point"), py::arg("normal"), py::arg("material") = py::none(), py::arg("name") = py::none())
        .def(
            "add_cylinder",
            [](const SceneRef& s, py::object base, py::object axis, Arg<double> radius, Arg<double> height, py::object material,
               py::object name) {
                Cylinder c{placed(checked("add_cylinder.base", toVec(base, "add_cylinder.base"), xml::kAnyValue)),
                           loaderDirection("add_cylinder.axis", toVec(axis, "add_cylinder.axis")),
                           checked("add_cylinder.radius", radius, xml::kPositive),
                           checked("add_cylinder.height", height, xml::kPositive)};
                return addObject(s, c, material, name, "add_cylinder");
            },
            py::arg("base"), py::arg("axis"), py::arg("radius"), py::arg("height"), py::arg("material") = py::none(),
            py::arg("name") = py::none())
        .def(
            "add_triangle",
            [](const SceneRef& s, py::object a, py::object b, py::object c, py::object material, py::object name) {
                Triangle t{placed(checked("add_triangle.a", toVec(a, "add_triangle.a"), xml::kAnyValue)),
                           placed(checked("add_triangle.b", toVec(b, "add_triangle.b"), xml::kAnyValue)),
                           placed(checked("add_triangle.c", toVec(c, "add_triangle.c"), xml::kAnyValue))};
                if (degenerate(t)) refuse("add_triangle.c", "a vertex off the line through a and b", "a degenerate triangle");
                return addObject(s, t, material, name, "add_triangle");
            },
            py::arg("a"), py::arg("b"), py::arg("c"), py::arg("material") = py::none(), py::arg("name") = py::none());
}

// Meshes from arrays and model files, lights, and their removal.
void addMeshAndLightBuilders(SceneClass& scene) {
    scene
        .def(
            "add_mesh",
            [](const SceneRef& s, py::object vertices, py::object faces, py::object normals, py::object uvs,
               py::object material, py::object name, py::object transform) {
                if (py::isinstance<MeshArrays>(vertices)) {  // add_mesh(whitted.Mesh, ...): its arrays
                    if (!faces.is_none() || !normals.is_none() || !uvs.is_none())
                        throw py::type_error("add_mesh: a whitted.Mesh brings its own faces, normals and uvs");
                    const MeshArrays& arrays = vertices.cast<const MeshArrays&>();
                    vertices = arrays.vertices, faces = arrays.faces, normals = arrays.normals, uvs = arrays.uvs;
                }
                return addObject(s, buildMesh(vertices, faces, normals, uvs, transform), material, name, "add_mesh");
            },
            py::arg("vertices"), py::arg("faces") = py::none(), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
            py::arg("material") = py::none(), py::arg("name") = py::none(), py::arg("transform") = py::none(),
            "a triangle mesh from numpy arrays: vertices (N, 3), faces (M, 3) integers, normals (N, 3), uvs (N, 2), "
            "transform 4x4 (applied to vertices and normals); degenerate faces are skipped with a warning")
        .def(
            "add_file",
            [](const SceneRef& s, const std::filesystem::path& path, py::object part, py::object transform) {
                py::list handles;
                for (Object& o : fileObjects(path, part, transform)) {
                    s->scene->objects.push_back(std::move(o));
                    s->objectIds.push_back(s->nextObjectId++);
                    handles.append(ObjectView{s, s->objectIds.back()});
                }
                ++s->versions.geometry;
                return handles;
            },
            py::arg("path"), py::arg("part") = py::none(), py::arg("transform") = py::none(),
            "a model file's objects as the scene format's <file> gives them (part: <file part>, transform: a 4x4 "
            "affine <matrix>); a list of handles, one per material of the file")
        .def(
            "add_light",
            [](const SceneRef& s, py::object position, py::object color, Arg<std::string> type,
               Arg<double> intensity, Arg<std::string> falloff, py::object direction, py::object inner,
               py::object outer, py::object name, Arg<double> radius, Arg<long long> shadowSamples, py::object u,
               py::object v, Arg<bool> twoSided) {
                // In the order of the arguments, so that the first wrong one is named.
                std::string t = type.get("add_light.type");
                double i = intensity.get("add_light.intensity");
                std::string f = falloff.get("add_light.falloff");
                AreaArguments area{radius.get("add_light.radius"), shadowSamples.get("add_light.shadow_samples"), u, v,
                                   twoSided.get("add_light.two_sided")};
                s->scene->lights.push_back(buildLight(position, color, t, i, f, direction, inner, outer, name, area));
                s->lightIds.push_back(s->nextLightId++);
                ++s->versions.geometry;  // the light count changed: the renderer takes the scene anew
                return LightView{s, s->lightIds.back()};
            },
            py::arg("position") = py::none(), py::arg("color") = py::make_tuple(1.0, 1.0, 1.0),
            py::arg("type") = "point", py::arg("intensity") = 1.0, py::arg("falloff") = "none",
            py::arg("direction") = py::none(), py::arg("inner_angle") = py::none(),
            py::arg("outer_angle") = py::none(), py::arg("name") = py::none(), py::arg("radius") = 0.0,
            py::arg("shadow_samples") = 1, py::arg("u") = py::none(), py::arg("v") = py::none(),
            py::arg("two_sided") = false,
            "a point, spot, directional or rect light with the fields of <light>")
        .def(
            "remove",
            [](const SceneRef& s, py::object handle) {
                if (py::isinstance<ObjectView>(handle)) {
                    const ObjectView& v = handle.cast<const ObjectView&>();
                    if (v.s != s) throw py::key_error("the object is not in this scene");
                    size_t i = v.index();
                    s->scene->objects.erase(s->scene->objects.begin() + std::ptrdiff_t(i));
                    s->objectIds.erase(s->objectIds.begin() + std::ptrdiff_t(i));
                } else if (py::isinstance<LightView>(handle)) {
                    const LightView& v = handle.cast<const LightView&>();
                    if (v.s != s) throw py::key_error("the light is not in this scene");
                    size_t i = v.index();
                    s->scene->lights.erase(s->scene->lights.begin() + std::ptrdiff_t(i));
                    s->lightIds.erase(s->lightIds.begin() + std::ptrdiff_t(i));
                } else {
                    throw py::type_error("Scene.remove: expected an Object or a Light of the scene, got " +
                                         py::repr(handle).cast<std::string>());
                }
                ++s->versions.geometry;
            },
            py::arg("handle"), "removes an object or light; its handle then raises KeyError");
}

}  // namespace

void addSceneBuilders(SceneClass& scene) {
    addShapeBuilders(scene);
    addMeshAndLightBuilders(scene);
}

}  // namespace whitted::python

// whitted.Mesh (add_mesh's arrays held together, from numpy or a
// trimesh.Trimesh), the mesh add_mesh builds of them, and the objects
// add_file reads from a model file.
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/mesh_objects.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"

#include <pybind11/numpy.h>

#include <array>
#include <cmath>
#include <optional>
#include <string>

namespace whitted::python {

Mesh buildMesh(const py::object& vertices, const py::object& faces, const py::object& normals, const py::object& uvs,
               const py::object& transform) {
    auto V = floatRows(vertices, 3, "add_mesh.vertices");
    const py::ssize_t n = V.shape(0);
    py::array anyFaces = py::array::ensure(faces);
    if (!anyFaces || (anyFaces.dtype().kind() != 'i' && anyFaces.dtype().kind() != 'u'))
        refuse("add_mesh.faces", "an (M, 3) array of integers", anyFaces ? "dtype " + py::str(anyFaces.dtype()).cast<std::string>() : py::repr(faces).cast<std::string>());
    auto F = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(anyFaces);
    if (F.ndim() != 2 || F.shape(1) != 3 || F.shape(0) == 0) refuse("add_mesh.faces", "an (M, 3) array of integers, M >= 1", shapeText(F));
    std::optional<Rows> N, UV;
    if (!normals.is_none()) {
        N = floatRows(normals, 3, "add_mesh.normals");
        if (N->shape(0) != n) refuse("add_mesh.normals", "one per vertex, (" + std::to_string(n) + ", 3)", shapeText(*N));
    }
    if (!uvs.is_none()) {
        UV = floatRows(uvs, 2, "add_mesh.uvs");
        if (UV->shape(0) != n) refuse("add_mesh.uvs", "one per vertex, (" + std::to_string(n) + ", 2)", shapeText(*UV));
    }
    std::optional<glm::dmat4> M;
    if (!transform.is_none()) M = transformMatrix(transform, "add_mesh.transform");
    const glm::dmat3 normalLinear = M ? glm::transpose(glm::inverse(glm::dmat3(*M))) : glm::dmat3(1.0);
    const bool flip = M && glm::determinant(glm::dmat3(*M)) < 0;

    std::vector<glm::dvec3> world(static_cast<size_t>(n)), normal(N ? static_cast<size_t>(n) : 0);
    std::vector<glm::dvec2> uv(UV ? static_cast<size_t>(n) : 0);
    for (py::ssize_t i = 0; i < n; ++i) {
        const std::string at = "[" + std::to_string(i) + "]";
        glm::dvec3 v = checked("add_mesh.vertices" + at, row3(V, i), xml::kAnyValue);
        if (M) {
            v = glm::dvec3(*M * glm::dvec4(v, 1.0));
            checked("add_mesh.vertices" + at + " transformed", v, xml::kAnyValue);
        }
        world[size_t(i)] = v;
        if (N) {
            // As the loader: a unit normal as given, any other divided by its length.
            glm::dvec3 nv = checked("add_mesh.normals" + at, row3(*N, i), xml::kAnyValue);
            if (std::abs(glm::length(nv) - 1.0) > 1e-9) nv = loaderDirection("add_mesh.normals" + at, nv);
            if (M) nv = glm::normalize(normalLinear * nv);
            normal[size_t(i)] = nv;
        }
        if (UV) {
            for (int k = 0; k < 2; ++k)
                if (!(std::abs(UV->at(i, k)) <= xml::kMaxMagnitude))
                    refuse("add_mesh.uvs" + at, "2 numbers each " + xml::kAnyValue.describe(), "(" + shown(UV->at(i, 0)) + ", " + shown(UV->at(i, 1)) + ")");
            uv[size_t(i)] = {UV->at(i, 0), UV->at(i, 1)};
        }
    }
    Mesh mesh;
    size_t skipped = 0;
    for (py::ssize_t f = 0; f < F.shape(0); ++f) {
        std::array<size_t, 3> idx{};
        for (int k = 0; k < 3; ++k) {
            int64_t j = F.at(f, k);
            if (j < 0 || j >= n)
                refuse("add_mesh.faces[" + std::to_string(f) + "]", "vertex indices in [0, " + std::to_string(n - 1) + "]", std::to_string(j));
            idx[size_t(k)] = size_t(j);
        }
        if (flip) std::swap(idx[1], idx[2]);
        Triangle t{world[idx[0]], world[idx[1]], world[idx[2]]};
        if (degenerate(t)) {
            ++skipped;
            continue;
        }
        mesh.triangles.push_back(t);
        if (N) mesh.normals.push_back({normal[idx[0]], normal[idx[1]], normal[idx[2]]});
        if (UV) mesh.uvs.push_back({uv[idx[0]], uv[idx[1]], uv[idx[2]]});
    }
    if (mesh.triangles.empty()) refuse("add_mesh.faces", "at least one face that is not degenerate", "none");
    if (skipped > 0) {
        std::string text = "add_mesh: " + std::to_string(skipped) + " degenerate face(s) skipped";
        if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) throw py::error_already_set();
    }
    return mesh;
}

// Scene.add_file: the objects a model file gives as the scene format's
// <file> element gives them, read by the loader itself from a one-object
// scene text (scene/mesh_objects.h readMeshObject: parts, placement by
// <matrix>, the file's materials, one object per material), so that what
// save() writes (that <file> again) loads back to the same objects.
std::vector<Object> fileObjects(const std::filesystem::path& path, const py::object& part, const py::object& transform) {
    std::string file = escapedXml(std::filesystem::absolute(path).lexically_normal().string());
    std::string element = "<file>" + file + "</file>";
    if (!part.is_none()) {
        if (!py::isinstance<py::str>(part)) throw py::type_error("add_file.part: expected a string or None, got " + py::repr(part).cast<std::string>());
        element = "<file part=\"" + escapedXml(part.cast<std::string>()) + "\">" + file + "</file>";
    }
    if (!transform.is_none()) {
        glm::dmat4 m = transformMatrix(transform, "add_file.transform");
        std::string rows;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) rows += (rows.empty() ? "" : " ") + xmlNumber(m[c][r]);
        element += "<matrix>" + rows + "</matrix>";
    }
    const std::string text =
        "<scene><camera><position x=\"0\" y=\"0\" z=\"0\"/><window_position x=\"0\" y=\"0\" z=\"-1\"/></camera>"
        "<lights><light><position x=\"0\" y=\"0\" z=\"0\"/><color r=\"1\" g=\"1\" b=\"1\"/></light></lights>"
        "<objects><object><properties><type>mesh</type>" + element + "</properties></object></objects></scene>";
    Scene loaded;
    try {
        py::gil_scoped_release release;
        loaded = loadSceneFromString(text, std::filesystem::current_path() / "<add_file>");
    } catch (const SceneError& e) {
        throw py::value_error("add_file: " + e.message());
    }
    for (const std::string& warning : loaded.warnings) {
        // Without the place in the made-up text ("<add_file>:1: ").
        const std::string place = "<add_file>:1: ";
        std::string w = "add_file: " + (warning.find(place) == std::string::npos
                                             ? warning
                                             : warning.substr(warning.find(place) + place.size()));
        if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
    }
    for (Object& o : loaded.objects) o.sourceLine = 0;
    return std::move(loaded.objects);
}

void addMeshApi(py::module_& m) {
    py::class_<MeshArrays>(m, "Mesh", "a triangle mesh's arrays for Scene.add_mesh: vertices (N, 3), faces (M, 3), "
                                      "normals (N, 3) or None, uvs (N, 2) or None")
        .def(py::init([](py::object vertices, py::object faces, py::object normals, py::object uvs) {
                 return MeshArrays{vertices, faces, normals, uvs};
             }),
             py::arg("vertices"), py::arg("faces"), py::arg("normals") = py::none(), py::arg("uvs") = py::none())
        .def_static(
            "from_trimesh",
            [](py::object mesh, bool normals) {
                // trimesh.Trimesh's attributes (read, not imported: any object that has them will do).
                for (const char* attribute : {"vertices", "faces"})
                    if (!py::hasattr(mesh, attribute))
                        throw py::type_error(std::string("Mesh.from_trimesh: expected a trimesh.Trimesh (with .vertices and .faces), got ") +
                                             py::repr(mesh).cast<std::string>());
                py::module_ np = py::module_::import("numpy");
                MeshArrays arrays{np.attr("asarray")(mesh.attr("vertices")), np.attr("asarray")(mesh.attr("faces")),
                                  py::none(), py::none()};
                // The vertex normals trimesh has (the file's, else its own from the faces).
                if (normals) arrays.normals = np.attr("asarray")(mesh.attr("vertex_normals"));
                // Texture coordinates where its visual has them (trimesh.visual.TextureVisuals.uv).
                py::object visual = py::getattr(mesh, "visual", py::none());
                py::object uv = visual.is_none() ? py::none() : py::getattr(visual, "uv", py::none());
                if (!uv.is_none()) arrays.uvs = np.attr("asarray")(uv);
                return arrays;
            },
            py::arg("mesh"), py::arg("normals") = true,
            "the arrays of a trimesh.Trimesh: vertices, faces, vertex_normals (normals=True) and visual.uv where it has them")
        .def_readwrite("vertices", &MeshArrays::vertices)
        .def_readwrite("faces", &MeshArrays::faces)
        .def_readwrite("normals", &MeshArrays::normals)
        .def_readwrite("uvs", &MeshArrays::uvs);
}

}  // namespace whitted::python

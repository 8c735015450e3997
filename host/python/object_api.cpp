// whitted.Object: an object of a scene as a view (edits change the scene):
// its name, its placement (position, transform, a sphere's or cylinder's
// radius, a csg object's operation) and its material's fields.
#include "python/arguments.h"
#include "python/python_api.h"
#include "scene/shape_edit.h"

#include <pybind11/numpy.h>

#include <stdexcept>
#include <string>

namespace whitted::python {
namespace {

using ObjectClass = py::class_<ObjectView>;

// Where the object is and its shape's size: a move re-packs the geometry.
void addPlacement(ObjectClass& object) {
    object
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
            "transform",
            [](const ObjectView& v) {
                v.index();  // KeyError for a removed object
                auto it = v.s->transforms.find(v.id);
                glm::dmat4 m = it == v.s->transforms.end() ? glm::dmat4(1.0) : it->second;
                py::array_t<double> a({4, 4});
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c) a.mutable_at(r, c) = m[c][r];
                return a;
            },
            [](const ObjectView& v, py::object x) {
                Object& o = v.o();
                glm::dmat4 to = transformMatrix(x, "Object.transform");
                auto it = v.s->transforms.find(v.id);
                // From where it is now: the new transform after the old one undone.
                glm::dmat4 step = it == v.s->transforms.end() ? to : to * glm::inverse(it->second);
                Shape moved = o.shape;
                try {
                    transformShape(moved, step);
                } catch (const std::invalid_argument& e) {
                    throw py::value_error(std::string("Object.transform: ") + e.what());
                }
                o.shape = std::move(moved);
                o.material.checkerOrigin = glm::dvec3(step * glm::dvec4(o.material.checkerOrigin, 1.0));
                v.s->transforms[v.id] = to;
                ++v.s->versions.geometry;
            },
            "a 4x4 affine matrix placing the object relative to how it was added or loaded (identity until set); "
            "setting it moves the shape (scene/shape_edit.h transformShape)")
        .def_property(
            "radius",
            [](const ObjectView& v) -> py::object {
                if (const auto* s = std::get_if<Sphere>(&v.o().shape)) return py::float_(s->radius);
                if (const auto* c = std::get_if<Cylinder>(&v.o().shape)) return py::float_(c->radius);
                return py::none();
            },
            [](const ObjectView& v, Arg<double> x) {
                Object& o = v.o();
                double r = checked("Object.radius", x, xml::kPositive);
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
            [](const ObjectView& v, Arg<std::string> x) {
                std::string op = x.get("Object.operation");
                auto* c = std::get_if<Csg>(&v.o().shape);
                if (!c) throw py::attribute_error(std::string("a ") + shapeName(v.o().shape) + " has no operation");
                if (op == "union") c->operation = Csg::Operation::Union;
                else if (op == "intersection") c->operation = Csg::Operation::Intersection;
                else if (op == "difference") c->operation = Csg::Operation::Difference;
                else refuse("Object.operation", "union, intersection or difference", "'" + op + "'");
                ++v.s->versions.geometry;
            },
            "a csg object's operation (None for other shapes)");
}

// The name, what it is, and its material as a whole.
void addIdentity(ObjectClass& object) {
    object
        .def_property(
            "material", [](const ObjectView& v) { return MaterialValue{v.o().material}; },
            [](const ObjectView& v, py::object m) {
                Object& o = v.o();
                o.material = materialFor(o.shape, m.is_none() ? py::cast(MaterialValue{}) : m, "Object.material");
                ++v.s->versions.materials;
            },
            "a copy of its material (a whitted.Material); assigning one copies it in")
        .def_property(
            "name", [](const ObjectView& v) { return v.o().name; },
            [](const ObjectView& v, py::object n) { v.o().name = checkedName("Object.name", n); }, "optional name (<name>)")
        .def_property_readonly("type", [](const ObjectView& v) { return std::string(shapeName(v.o().shape)); },
                               "sphere, cylinder, plane, triangle, box, mesh or csg")
        .def_property_readonly("line", [](const ObjectView& v) { return v.o().sourceLine; },
                               "line of its <object> in the scene file (0: none)")
        .def_property(
            "checker_size", [](const ObjectView& v) { return v.o().material.checkerSize; },
            [](const ObjectView& v, Arg<double> arg) {
                Object& o = v.o();
                double x = arg.get("Object.checker_size");
                if (x != 0) checked("Object.checker_size", x, xml::kPositive);
                if (o.material.checkerSize == 0 && x > 0) o.material.checkerOrigin = checkerAnchor(o.shape);
                o.material.checkerSize = x;
                ++v.s->versions.materials;
            },
            "solid checker cell size (> 0), 0: no checker");
}

}  // namespace

void addObjectApi(py::module_& m) {
    ObjectClass object(m, "Object", "An object of a scene (a view: edits change the scene)");
    addIdentity(object);
    addPlacement(object);
    addMaterialFields(object);
    object.def("__repr__", [](const ObjectView& v) {
        return "Object(" + std::to_string(v.index()) + ", type='" + shapeName(v.o().shape) + "', name='" + v.o().name + "')";
    });
}

}  // namespace whitted::python

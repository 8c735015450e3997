// The checks every binding of the module applies to what Python hands it:
// numbers, vectors, names and matrices, each checked against the scene
// format's range (the XML reader's) with errors that name the field
// ("Object.diffuse: must be in [0, 1], got 2"). A value out of range raises
// ValueError; a value of the wrong type TypeError.
#pragma once

#include "scene/scene.h"
#include "scene/xml_reader.h"

#include <glm/glm.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <type_traits>

namespace whitted::python {

namespace py = pybind11;

using xml::Range;
constexpr Range kColourRange = xml::kUnitInterval;
constexpr Range kNormalStrength{0, 4, false, false};  // the editor panel's slider
constexpr Range kImageSide{1, 16384, false, false};   // gpu::kMaxImageSide

// "Object.diffuse: must be in [0, 1], got 2" (ValueError).
[[noreturn]] void refuse(const std::string& field, const std::string& expected, const std::string& got);
// A double as Python prints it.
std::string shown(double v);

double checked(const std::string& field, double v, const Range& r);
glm::dvec3 checked(const std::string& field, const glm::dvec3& v, const Range& r);
// A direction of any length but 0, made unit.
glm::dvec3 unit(const std::string& field, const glm::dvec3& v);

// The name of a Python value's type, for messages: "str", "NoneType".
std::string typeName(const py::handle& x);

// A Python value as a T (double, long long, bool or std::string), converted
// as pybind11 converts an argument of that type, or TypeError naming the
// field: "Light.intensity: expected a number, got str".
template <typename T>
T typed(const py::handle& x, const std::string& field) {
    py::detail::make_caster<T> caster;
    if (!caster.load(x, true)) {
        const char* expected = std::is_same_v<T, bool> ? "True or False"
                               : std::is_integral_v<T> ? "an integer"
                               : std::is_floating_point_v<T> ? "a number"
                                                             : "a string";
        throw py::type_error(field + ": expected " + expected + ", got " + typeName(x));
    }
    return py::detail::cast_op<T>(std::move(caster));
}

// An argument or a property's new value as it came, for typed() to convert
// with the field's name (pybind11's own TypeError names no field);
// signatures show it as a T.
template <typename T>
struct Arg {
    py::object value;
    T get(const std::string& field) const { return typed<T>(value, field); }
};
template <typename T>
double checked(const std::string& field, const Arg<T>& x, const Range& r) {
    return checked(field, double(x.get(field)), r);
}

// Vectors and colours cross as tuples of three numbers (any sequence of
// three but a string): TypeError for another type, ValueError for another length.
glm::dvec3 toVec(const py::handle& h, const std::string& field);
py::tuple toTuple(const glm::dvec3& v);

// ---- Building: the shapes of the scene format, checked as the loader checks them ----
//
// What is stored is what the scene writer writes and the loader reads back
// bit for bit (Scene.save): positions as the loader places them (origin +
// <position>, which turns -0 into 0), directions divided by their length
// until that changes nothing (the loader's xml::direction divides again),
// a box's corner as <position> + <size> would give it again.

// A name the saved file gives back as it is (None: no name).
std::string checkedName(const std::string& field, const py::object& name);
inline glm::dvec3 placed(const glm::dvec3& v) { return glm::dvec3(0) + v; }
glm::dvec3 loaderDirection(const std::string& field, glm::dvec3 v);

// "shape (2, 3)": an array's shape as numpy prints it.
std::string shapeText(const py::array& a);

using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;
// An (N, columns) array of floats, N >= 1, or ValueError naming the field.
Rows floatRows(const py::object& x, py::ssize_t columns, const std::string& field);
inline glm::dvec3 row3(const Rows& a, py::ssize_t i) { return {a.at(i, 0), a.at(i, 1), a.at(i, 2)}; }
// A 4x4 affine transform (the last row 0 0 0 1), finite, within ±1e6, its
// 3x3 part invertible: the XML format's <matrix>.
glm::dmat4 transformMatrix(const py::object& x, const std::string& field);

}  // namespace whitted::python

namespace pybind11::detail {
// Arg<T> takes any value; typed() converts it.
template <typename T>
struct type_caster<whitted::python::Arg<T>> {
    PYBIND11_TYPE_CASTER(whitted::python::Arg<T>, make_caster<T>::name);
    bool load(handle src, bool) {
        value.value = reinterpret_borrow<object>(src);
        return true;
    }
    static handle cast(const whitted::python::Arg<T>& a, return_value_policy, handle) { return a.value.inc_ref(); }
};
}  // namespace pybind11::detail

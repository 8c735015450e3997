// The module's argument checks (arguments.h).
#include "python/arguments.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace whitted::python {

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

glm::dvec3 unit(const std::string& field, const glm::dvec3& v) {
    glm::dvec3 f = checked(field, v, xml::kAnyValue);
    if (glm::length(f) < 1e-12) refuse(field, "a non-zero direction", "(0, 0, 0)");
    return glm::normalize(f);
}

std::string typeName(const py::handle& x) { return py::type::handle_of(x).attr("__name__").cast<std::string>(); }

glm::dvec3 toVec(const py::handle& h, const std::string& field) {
    if (!py::isinstance<py::sequence>(h) || py::isinstance<py::str>(h) || py::isinstance<py::bytes>(h))
        throw py::type_error(field + ": expected 3 numbers, got " + typeName(h));
    auto s = py::reinterpret_borrow<py::sequence>(h);
    if (py::len(s) != 3) refuse(field, "3 numbers", py::repr(h).cast<std::string>());
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i) v[i] = typed<double>(s[i], field + "[" + std::to_string(i) + "]");
    return v;
}
py::tuple toTuple(const glm::dvec3& v) { return py::make_tuple(v.x, v.y, v.z); }

namespace {
// Whether UTF-8 text holds a control character (Unicode's Cc: U+0000 to
// U+001F, U+007F to U+009F).
bool hasControlCharacter(const std::string& text) {
    for (size_t i = 0; i < text.size(); ++i) {
        auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x20 || c == 0x7F) return true;
        if (c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) <= 0x9F) return true;
    }
    return false;
}
}  // namespace

// A name the saved file gives back as it is: the loader trims a <name>'s
// text, XML 1.0 has no control characters but tab and line breaks, and it
// reads a \r back as \n; so no control character at all (host/python/README.md).
std::string checkedName(const std::string& field, const py::object& name) {
    if (name.is_none()) return {};
    if (!py::isinstance<py::str>(name)) throw py::type_error(field + ": expected a string or None, got " + py::repr(name).cast<std::string>());
    std::string n = name.cast<std::string>();
    if (hasControlCharacter(n) || xml::trimmed(n) != n)
        refuse(field, "text without control characters or surrounding whitespace", py::repr(name).cast<std::string>());
    return n;
}

glm::dvec3 loaderDirection(const std::string& field, glm::dvec3 v) {
    checked(field, v, xml::kAnyValue);
    double length = glm::length(v);
    if (!(length > xml::kMinLength)) refuse(field, "a non-zero direction", py::repr(toTuple(v)).cast<std::string>());
    v /= length;
    for (int i = 0; i < 8; ++i) {
        glm::dvec3 again = v / glm::length(v);
        if (again == v) break;
        v = again;
    }
    return v;
}

std::string shapeText(const py::array& a) {
    std::string t = "shape (";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) t += (i ? ", " : "") + std::to_string(a.shape(i));
    return t + (a.ndim() == 1 ? ",)" : ")");
}

namespace {
// An array of numbers as float64, or ValueError naming the field and what it expected.
Rows numberArray(const py::object& x, const std::string& field, const std::string& expected) {
    py::array any = py::array::ensure(x);
    if (!any) refuse(field, expected, py::repr(x).cast<std::string>());
    char kind = any.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u') refuse(field, expected, "dtype " + py::str(any.dtype()).cast<std::string>());
    return Rows::ensure(any);
}
}  // namespace

Rows floatRows(const py::object& x, py::ssize_t columns, const std::string& field) {
    std::string expected = "an (N, " + std::to_string(columns) + ") array of numbers";
    Rows a = numberArray(x, field, expected);
    if (a.ndim() != 2 || a.shape(1) != columns || a.shape(0) == 0) refuse(field, expected, shapeText(a));
    return a;
}

glm::dmat4 transformMatrix(const py::object& x, const std::string& field) {
    const std::string expected = "a 4x4 matrix of numbers";
    Rows a = numberArray(x, field, expected);
    if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) refuse(field, expected, shapeText(a));
    glm::dmat4 m(1.0);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            double v = a.at(r, c);
            if (!(std::abs(v) <= xml::kMaxMagnitude)) refuse(field, "numbers within ±1e6", "M[" + std::to_string(r) + ", " + std::to_string(c) + "] = " + shown(v));
            m[c][r] = v;
        }
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
        refuse(field, "an affine matrix (last row 0 0 0 1)", "last row (" + shown(m[0][3]) + ", " + shown(m[1][3]) + ", " + shown(m[2][3]) + ", " + shown(m[3][3]) + ")");
    double det = glm::determinant(glm::dmat3(m));
    if (!(std::abs(det) > 0) || !std::isfinite(det)) refuse(field, "invertible (its 3x3 part)", "determinant " + shown(det));
    return m;
}

}  // namespace whitted::python

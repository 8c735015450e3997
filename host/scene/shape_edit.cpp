#include "scene/shape_edit.h"

#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

namespace whitted {

glm::dvec3 checkerAnchor(const Shape& s) {
    if (const Mesh* mesh = std::get_if<Mesh>(&s); mesh && mesh->source) return mesh->source->position;
    return shapeReferencePoint(s);
}

const char* shapeName(const Shape& s) {
    static constexpr const char* kNames[] = {"sphere", "cylinder", "plane", "triangle", "box", "mesh", "csg"};
    static_assert(std::variant_size_v<Shape> == std::size(kNames));
    return kNames[s.index()];
}

void translateShape(Shape& shape, const glm::dvec3& d) {
    std::visit(
        [&](auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>)
                s.center += d;
            else if constexpr (std::is_same_v<T, Cylinder>)
                s.base += d;
            else if constexpr (std::is_same_v<T, Plane>)
                s.point += d;
            else if constexpr (std::is_same_v<T, Triangle>) {
                s.v0 += d;
                s.v1 += d;
                s.v2 += d;
            } else if constexpr (std::is_same_v<T, Box>) {
                s.min += d;
                s.max += d;
            } else if constexpr (std::is_same_v<T, Csg>) {
                s.position += d;
                for (CsgChild& child : s.children) {
                    child.material.checkerOrigin += d;
                    translateShape(child.shape, d);
                }
            } else {
                for (Triangle& t : s.triangles) {
                    t.v0 += d;
                    t.v1 += d;
                    t.v2 += d;
                }
                if (s.source) s.source->position += d;
            }
        },
        shape);
}

namespace {

// s when `linear` is s times a rotation (columns orthogonal, of one length
// to 1e-9, determinant > 0), else 0.
double uniformScale(const glm::dmat3& linear) {
    double s = glm::length(linear[0]);
    for (int i = 0; i < 3; ++i) {
        if (std::abs(glm::length(linear[i]) - s) > 1e-9 * s) return 0;
        for (int j = i + 1; j < 3; ++j)
            if (std::abs(glm::dot(linear[i], linear[j])) > 1e-9 * s * s) return 0;
    }
    return glm::determinant(linear) > 0 ? s : 0;
}

}  // namespace

void transformShape(Shape& shape, const glm::dmat4& m) {
    const glm::dmat3 linear(m);
    const glm::dmat3 normalLinear = glm::transpose(glm::inverse(linear));
    auto point = [&](const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); };
    auto refuse = [&](const std::string& why) { throw std::invalid_argument(std::string("a ") + shapeName(shape) + " " + why); };
    std::visit(
        [&](auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>) {
                double k = uniformScale(linear);
                if (k == 0) refuse("takes only a rotation, a uniform scale and a translation (it stays a sphere)");
                s.center = point(s.center);
                s.radius *= k;
            } else if constexpr (std::is_same_v<T, Cylinder>) {
                double k = uniformScale(linear);
                if (k == 0) refuse("takes only a rotation, a uniform scale and a translation (it stays round)");
                s.base = point(s.base);
                s.axis = glm::normalize(linear * s.axis);
                s.radius *= k;
                s.height *= k;
            } else if constexpr (std::is_same_v<T, Plane>) {
                s.point = point(s.point);
                s.normal = glm::normalize(normalLinear * s.normal);
            } else if constexpr (std::is_same_v<T, Triangle>) {
                s = glm::determinant(linear) < 0 ? Triangle{point(s.v0), point(s.v2), point(s.v1)}
                                                 : Triangle{point(s.v0), point(s.v1), point(s.v2)};
            } else if constexpr (std::is_same_v<T, Box>) {
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        if ((i == j && !(linear[i][j] > 0)) || (i != j && linear[i][j] != 0))
                            refuse("stays axis-aligned: its transform may only scale each axis (> 0) and translate");
                s.min = point(s.min);
                s.max = point(s.max);
            } else if constexpr (std::is_same_v<T, Csg>) {
                refuse("is moved by its position, not a transform");
            } else {
                if (s.source) refuse("read from a model file is placed by add_file's transform (its <matrix>)");
                const bool flip = glm::determinant(linear) < 0;
                for (Triangle& t : s.triangles) t = {point(t.v0), flip ? point(t.v2) : point(t.v1), flip ? point(t.v1) : point(t.v2)};
                for (auto& n : s.normals) {
                    for (glm::dvec3& v : n) v = glm::normalize(normalLinear * v);
                    if (flip) std::swap(n[1], n[2]);
                }
                for (auto& t : s.tangents) {
                    for (glm::dvec3& v : t)
                        if (glm::length(v) > 0.5) v = glm::normalize(linear * v);  // 0: none (scene.h)
                    if (flip) std::swap(t[1], t[2]);
                }
                if (flip)
                    for (auto& uv : s.uvs) std::swap(uv[1], uv[2]);
            }
        },
        shape);
}

glm::dvec3 shapeReferencePoint(const Shape& shape) {
    return std::visit(
        [](const auto& s) -> glm::dvec3 {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>)
                return s.center;
            else if constexpr (std::is_same_v<T, Cylinder>)
                return s.base;
            else if constexpr (std::is_same_v<T, Plane>)
                return s.point;
            else if constexpr (std::is_same_v<T, Triangle>)
                return s.v0;
            else if constexpr (std::is_same_v<T, Box>)
                return s.min;
            else if constexpr (std::is_same_v<T, Csg>)
                return s.position;
            else
                return s.triangles.empty() ? glm::dvec3(0) : s.triangles.front().v0;
        },
        shape);
}

}  // namespace whitted

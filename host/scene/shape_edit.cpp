#include "scene/shape_edit.h"

#include <iterator>
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

#include "shapes/shapes.h"

#include <stdexcept>
#include <type_traits>

namespace whitted {

size_t primitiveCount(const Shape& shape) {
    if (const Mesh* mesh = std::get_if<Mesh>(&shape)) return mesh->triangles.size();
    return 1;
}

void appendPrimitives(const Shape& shape, uint32_t material, std::vector<gpu::Primitive>& out,
                      std::vector<Aabb>& bounds) {
    auto add = [&](const gpu::Primitive& p, const Aabb& b) {
        out.push_back(p);
        bounds.push_back(b);
    };
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>) add(packSphere(s, material), boundsSphere(s));
            else if constexpr (std::is_same_v<T, Cylinder>) add(packCylinder(s, material), boundsCylinder(s));
            else if constexpr (std::is_same_v<T, Plane>) add(packPlane(s, material), boundsPlane(s));
            else if constexpr (std::is_same_v<T, Triangle>) add(packTriangle(s, material), boundsTriangle(s));
            else if constexpr (std::is_same_v<T, Box>) add(packBox(s, material), boundsBox(s));
            else if constexpr (std::is_same_v<T, Mesh>)
                for (size_t i = 0; i < s.triangles.size(); ++i) {
                    const Triangle& t = s.triangles[i];
                    add(s.normals.empty() ? packTriangle(t, material) : packSmoothTriangle(t, s.normals[i], material),
                        boundsTriangle(t));
                }
            else if constexpr (std::is_same_v<T, Csg>)
                throw std::logic_error("a csg object is packed by packCsg");
            else static_assert(sizeof(T) == 0, "unhandled shape");
        },
        shape);
}

}  // namespace whitted

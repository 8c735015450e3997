#include "shapes/shapes.h"

#include <type_traits>

namespace whitted {

void appendPrimitives(const Shape& shape, uint32_t material, std::vector<gpu::Primitive>& out) {
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>) out.push_back(packSphere(s, material));
            else if constexpr (std::is_same_v<T, Cylinder>) out.push_back(packCylinder(s, material));
            else if constexpr (std::is_same_v<T, Plane>) out.push_back(packPlane(s, material));
            else if constexpr (std::is_same_v<T, Triangle>) out.push_back(packTriangle(s, material));
            else if constexpr (std::is_same_v<T, Box>) out.push_back(packBox(s, material));
            else if constexpr (std::is_same_v<T, Mesh>)
                for (const Triangle& t : s.triangles) out.push_back(packTriangle(t, material));
            else static_assert(sizeof(T) == 0, "unhandled shape");
        },
        shape);
}

}  // namespace whitted

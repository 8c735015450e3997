// Infinite plane: intersected by intersectPlane() in shaders/shapes/plane.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packPlane(const Plane& p, uint32_t material) {
    return {.a = glm::vec4(glm::vec3(p.point), 0.0f),
            .b = glm::vec4(glm::vec3(glm::normalize(p.normal)), 0.0f),
            .c = glm::vec4(0),
            .shape = gpu::kShapePlane,
            .material = material,
            .extra0 = 0,
            .extra1 = 0};
}

Aabb boundsPlane(const Plane&) { return Aabb::unbounded(); }

}  // namespace whitted

// Infinite plane: intersected by intersectPlane() in shaders/shapes/plane.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packPlane(const Plane& p, uint32_t material) {
    return gpu::planePrimitive(glm::vec3(p.point), glm::vec3(glm::normalize(p.normal)), material);
}

Aabb boundsPlane(const Plane&) { return Aabb::unbounded(); }

}  // namespace whitted

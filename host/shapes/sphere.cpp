// Sphere: intersected by intersectSphere() in shaders/shapes/sphere.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packSphere(const Sphere& s, uint32_t material) {
    return gpu::spherePrimitive(glm::vec3(s.center), float(s.radius), material);
}

Aabb boundsSphere(const Sphere& s) {
    Aabb b;
    b.extend(glm::vec3(s.center - s.radius));
    b.extend(glm::vec3(s.center + s.radius));
    return b;
}

}  // namespace whitted

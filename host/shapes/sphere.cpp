// Sphere: intersected by intersectSphere() in shaders/shapes/sphere.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packSphere(const Sphere& s, uint32_t material) {
    return {.a = glm::vec4(glm::vec3(s.center), float(s.radius)),
            .b = glm::vec4(0),
            .c = glm::vec4(0),
            .shape = gpu::kShapeSphere,
            .material = material,
            .extra0 = 0,
            .extra1 = 0};
}

Aabb boundsSphere(const Sphere& s) {
    Aabb b;
    b.extend(glm::vec3(s.center - s.radius));
    b.extend(glm::vec3(s.center + s.radius));
    return b;
}

}  // namespace whitted

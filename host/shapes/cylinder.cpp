// Capped cylinder: intersected by intersectCylinder() in
// shaders/shapes/cylinder.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packCylinder(const Cylinder& c, uint32_t material) {
    return {.a = glm::vec4(glm::vec3(c.base), float(c.radius)),
            .b = glm::vec4(glm::vec3(glm::normalize(c.axis)), float(c.height)),
            .c = glm::vec4(0),
            .info = glm::uvec4(gpu::kShapeCylinder, material, 0, 0)};
}

}  // namespace whitted

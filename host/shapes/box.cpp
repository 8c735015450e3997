// Axis-aligned box: intersected by intersectBox() in shaders/shapes/box.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packBox(const Box& b, uint32_t material) {
    return {.a = glm::vec4(glm::vec3(b.min), 0.0f),
            .b = glm::vec4(glm::vec3(b.max), 0.0f),
            .c = glm::vec4(0),
            .shape = gpu::kShapeBox,
            .material = material,
            .extra0 = 0,
            .extra1 = 0};
}

Aabb boundsBox(const Box& box) {
    Aabb b;
    b.extend(glm::vec3(box.min));
    b.extend(glm::vec3(box.max));
    return b;
}

}  // namespace whitted

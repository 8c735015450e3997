// Axis-aligned box: intersected by intersectBox() in shaders/shapes/box.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packBox(const Box& b, uint32_t material) {
    return gpu::boxPrimitive(glm::vec3(b.min), glm::vec3(b.max), material);
}

Aabb boundsBox(const Box& box) {
    Aabb b;
    b.extend(glm::vec3(box.min));
    b.extend(glm::vec3(box.max));
    return b;
}

}  // namespace whitted

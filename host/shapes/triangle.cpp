// Triangle (and every triangle of a mesh): intersected by
// intersectTriangle() in shaders/shapes/triangle.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packTriangle(const Triangle& t, uint32_t material) {
    return {.a = glm::vec4(glm::vec3(t.v0), 0.0f),
            .b = glm::vec4(glm::vec3(t.v1), 0.0f),
            .c = glm::vec4(glm::vec3(t.v2), 0.0f),
            .info = glm::uvec4(gpu::kShapeTriangle, material, 0, 0)};
}

Aabb boundsTriangle(const Triangle& t) {
    Aabb b;
    b.extend(glm::vec3(t.v0));
    b.extend(glm::vec3(t.v1));
    b.extend(glm::vec3(t.v2));
    return b;
}

}  // namespace whitted

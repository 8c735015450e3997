// Capped cylinder: intersected by intersectCylinder() in
// shaders/shapes/cylinder.glsl.
#include "shapes/shapes.h"

namespace whitted {

gpu::Primitive packCylinder(const Cylinder& c, uint32_t material) {
    return gpu::cylinderPrimitive(glm::vec3(c.base), glm::vec3(glm::normalize(c.axis)), float(c.radius),
                                  float(c.height), material);
}

// The two cap discs bound the cylinder; a disc of radius r perpendicular to
// unit axis a extends r * sqrt(1 - a_i^2) along world axis i.
Aabb boundsCylinder(const Cylinder& c) {
    glm::dvec3 a = glm::normalize(c.axis);
    glm::dvec3 extent = c.radius * glm::sqrt(glm::max(glm::dvec3(0.0), 1.0 - a * a));
    glm::dvec3 top = c.base + a * c.height;
    Aabb b;
    b.extend(glm::vec3(c.base - extent));
    b.extend(glm::vec3(c.base + extent));
    b.extend(glm::vec3(top - extent));
    b.extend(glm::vec3(top + extent));
    return b;
}

}  // namespace whitted

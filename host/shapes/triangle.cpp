// Triangle (and every triangle of a mesh): intersected by
// intersectTriangle() in shaders/shapes/triangle.glsl; a smooth mesh
// triangle's vertex normals are decoded by shadingNormalTriangle() there.
#include "shapes/shapes.h"

#include <cmath>

namespace whitted {

gpu::Primitive packTriangle(const Triangle& t, uint32_t material) {
    return gpu::trianglePrimitive(glm::vec3(t.v0), glm::vec3(t.v1), glm::vec3(t.v2), material);
}

// Octahedral encoding of a unit vector ("A Survey of Efficient
// Representations for Independent Unit Vectors", Cigolle et al., JCGT 3(2),
// 2014): the vector is projected onto the octahedron |x|+|y|+|z| = 1, the
// lower half folded over the upper, and (x, y) in [-1, 1] stored as two
// kOctahedralBits-bit unsigned integers, x in the low bits. 15 bits each
// keep bits 30 and 31 of the word clear, so the float the word travels in
// (the w of a vertex) is never a NaN or an infinity; the angular error is
// below 0.01 degrees.
uint32_t encodeOctahedral(const glm::dvec3& n) {
    glm::dvec3 p = n / (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
    glm::dvec2 e(p.x, p.y);
    if (p.z < 0) {
        e = (1.0 - glm::abs(glm::dvec2(p.y, p.x))) * glm::dvec2(p.x >= 0 ? 1.0 : -1.0, p.y >= 0 ? 1.0 : -1.0);
    }
    constexpr double kMax = double((1u << gpu::kOctahedralBits) - 1u);
    auto quantize = [&](double v) { return uint32_t(std::lround((glm::clamp(v, -1.0, 1.0) * 0.5 + 0.5) * kMax)); };
    return quantize(e.x) | (quantize(e.y) << gpu::kOctahedralBits);
}

// The vertex normals ride in the primitive beside the vertices
// (gpu::setTriangleNormals); the primitive stays 64 bytes and the normals
// move with it when the BVH reorders primitives.
gpu::Primitive packSmoothTriangle(const Triangle& t, const std::array<glm::dvec3, 3>& normals, uint32_t material) {
    gpu::Primitive p = packTriangle(t, material);
    gpu::setTriangleNormals(p, glm::uvec3(encodeOctahedral(normals[0]), encodeOctahedral(normals[1]),
                                          encodeOctahedral(normals[2])));
    return p;
}

Aabb boundsTriangle(const Triangle& t) {
    Aabb b;
    b.extend(glm::vec3(t.v0));
    b.extend(glm::vec3(t.v1));
    b.extend(glm::vec3(t.v2));
    return b;
}

}  // namespace whitted

// Host side of every shape: how a CPU shape becomes GPU primitives.
// One file per shape (sphere.cpp, cylinder.cpp, ...), matching one
// intersection function per shape in shaders/shapes/.
#pragma once

#include "accel/aabb.h"
#include "device_types.h"
#include "scene/scene.h"

#include <vector>

namespace whitted {

gpu::Primitive packSphere(const Sphere& sphere, uint32_t material);
gpu::Primitive packCylinder(const Cylinder& cylinder, uint32_t material);
gpu::Primitive packPlane(const Plane& plane, uint32_t material);
gpu::Primitive packTriangle(const Triangle& triangle, uint32_t material);
// A mesh triangle with unit vertex normals (smooth shading).
gpu::Primitive packSmoothTriangle(const Triangle& triangle, const std::array<glm::dvec3, 3>& normals,
                                  uint32_t material);
// A unit vector as 2 x gpu::kOctahedralBits bits (decodeOctahedral() in
// shaders/shapes/triangle.glsl is its inverse).
uint32_t encodeOctahedral(const glm::dvec3& unit);
gpu::Primitive packBox(const Box& box, uint32_t material);

// World-space bounds of each shape, for the BVH. A plane is unbounded.
Aabb boundsSphere(const Sphere& sphere);
Aabb boundsCylinder(const Cylinder& cylinder);
Aabb boundsPlane(const Plane& plane);
Aabb boundsTriangle(const Triangle& triangle);
Aabb boundsBox(const Box& box);

// How many primitives a shape becomes.
size_t primitiveCount(const Shape& shape);

// Appends the primitives of any shape (a mesh becomes one triangle each)
// and the bounds of each.
void appendPrimitives(const Shape& shape, uint32_t material, std::vector<gpu::Primitive>& out,
                      std::vector<Aabb>& bounds);

}  // namespace whitted

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

// A top-level csg object's arrays while the scene is packed: its leaves
// (ordinary primitives, stored after all others), its postfix program, and
// the materials of children that have their own, whose indices start at
// firstMaterial.
struct CsgArrays {
    std::vector<gpu::Primitive> leaves;
    std::vector<gpu::CsgNode> nodes;
    std::vector<Material> materials;
    uint32_t firstMaterial = 0;
};
// The csg object's primitive: its bounds, its leaves (gpu::csgLeaves: the
// first one's index in arrays.leaves, to which the caller adds where the
// leaves start in the primitive array, and their count) and its program's
// range in arrays.nodes (gpu::csgProgram).
gpu::Primitive packCsg(const Csg& csg, uint32_t material, CsgArrays& arrays);
Aabb boundsCsg(const Csg& csg);
size_t csgOwnMaterialCount(const Csg& csg);  // children with a material of their own

// How many primitives a shape becomes (a csg object: one in the BVH; its
// leaves are counted by csgLeafCount, scene/scene.h).
size_t primitiveCount(const Shape& shape);

// Appends the primitives of any shape but csg (a mesh becomes one triangle
// each) and the bounds of each.
void appendPrimitives(const Shape& shape, uint32_t material, std::vector<gpu::Primitive>& out,
                      std::vector<Aabb>& bounds);

}  // namespace whitted

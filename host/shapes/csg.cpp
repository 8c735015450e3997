// Constructive solid geometry: intersected by intersectCsg() in
// shaders/shapes/csg.glsl. A top-level csg object becomes one bounded
// primitive (tag kShapeCsg) in the BVH, its leaf shapes ordinary primitives
// stored after every other (gpu_scene.cpp), and its tree a postfix program
// of CsgNodes (device_types.h).
#include <stdexcept>
#include <type_traits>

#include "shapes/shapes.h"

namespace whitted {

static_assert(kCsgMaxLeaves == gpu::kCsgMaxLeaves && kCsgMaxDepth == int(gpu::kCsgMaxDepth),
              "the loader's csg limits are the shader's");
static_assert(gpu::kCsgMaxLeaves <= 32, "leaf sets are 32-bit masks in shaders/shapes/csg.glsl");

namespace {

uint32_t operationCode(Csg::Operation op) {
    switch (op) {
        case Csg::Operation::Union:
            return gpu::kCsgUnion;
        case Csg::Operation::Intersection:
            return gpu::kCsgIntersection;
        case Csg::Operation::Difference:
            return gpu::kCsgDifference;
    }
    throw std::logic_error("unknown csg operation");
}

Aabb boundsLeaf(const Shape& shape) {
    if (const Sphere* s = std::get_if<Sphere>(&shape)) return boundsSphere(*s);
    if (const Cylinder* c = std::get_if<Cylinder>(&shape)) return boundsCylinder(*c);
    if (const Box* b = std::get_if<Box>(&shape)) return boundsBox(*b);
    if (const Csg* csg = std::get_if<Csg>(&shape)) return boundsCsg(*csg);
    throw std::logic_error("csg child is not a sphere, cylinder, box or csg");
}

// Emits the postfix program of `csg` (a left fold over its children) and
// its leaves, in program order.
// `material` is the index of the material the children without their own
// take (the nearest csg object above them that has one).
void emitCsg(const Csg& csg, uint32_t material, uint32_t leafBase, CsgArrays& arrays) {
    for (size_t k = 0; k < csg.children.size(); ++k) {
        const CsgChild& child = csg.children[k];
        uint32_t childMaterial = material;
        if (child.ownMaterial) {
            childMaterial = arrays.firstMaterial + uint32_t(arrays.materials.size());
            arrays.materials.push_back(child.material);
        }
        if (const Csg* nested = std::get_if<Csg>(&child.shape)) {
            emitCsg(*nested, childMaterial, leafBase, arrays);
        } else {
            uint32_t slot = uint32_t(arrays.leaves.size()) - leafBase;
            std::vector<Aabb> unused;
            appendPrimitives(child.shape, childMaterial, arrays.leaves, unused);
            arrays.nodes.push_back({.op = gpu::kCsgLeaf, .leaf = slot});
        }
        if (k > 0) arrays.nodes.push_back({.op = operationCode(csg.operation), .leaf = 0});
    }
}

}  // namespace

size_t csgOwnMaterialCount(const Csg& csg) {
    size_t count = 0;
    for (const CsgChild& child : csg.children) {
        const Csg* nested = std::get_if<Csg>(&child.shape);
        count += (child.ownMaterial ? 1 : 0) + (nested ? csgOwnMaterialCount(*nested) : 0);
    }
    return count;
}

// Bounds: a union's is the union of its children's, an intersection's the
// intersection of theirs, a difference's its first child's. An empty
// intersection leaves the point at the centre of the first child's bounds.
Aabb boundsCsg(const Csg& csg) {
    Aabb b = boundsLeaf(csg.children.front().shape);
    for (size_t k = 1; k < csg.children.size(); ++k) {
        Aabb c = boundsLeaf(csg.children[k].shape);
        if (csg.operation == Csg::Operation::Union) {
            b.extend(c);
        } else if (csg.operation == Csg::Operation::Intersection) {
            glm::vec3 centre = b.center();
            b.min = glm::max(b.min, c.min);
            b.max = glm::min(b.max, c.max);
            if (b.empty()) b.min = b.max = centre;
        }
    }
    return b;
}

gpu::Primitive packCsg(const Csg& csg, uint32_t material, CsgArrays& arrays) {
    uint32_t firstLeaf = uint32_t(arrays.leaves.size());
    uint32_t firstNode = uint32_t(arrays.nodes.size());
    emitCsg(csg, material, firstLeaf, arrays);
    uint32_t leafCount = uint32_t(arrays.leaves.size()) - firstLeaf;
    if (leafCount > gpu::kCsgMaxLeaves) throw std::logic_error("csg object beyond kCsgMaxLeaves");
    // Padded by a few float ulps as the BVH's bounds are (gpu_scene.cpp):
    // intersectCsg tests them against float-rounded leaves.
    Aabb b = boundsCsg(csg);
    glm::vec3 pad = 1e-6f * (glm::abs(b.min) + glm::abs(b.max)) + 1e-30f;
    b.min -= pad;
    b.max += pad;
    return gpu::csgPrimitive(b.min, b.max, glm::uvec2(firstLeaf, leafCount),
                             glm::uvec2(firstNode, uint32_t(arrays.nodes.size()) - firstNode), material);
}

}  // namespace whitted

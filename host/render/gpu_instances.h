// Packing instances (scene/scene.h Prototype, Instance) for the BVH path:
// each prototype's primitives once, in its own tree's leaf order, and each
// instance as a record (gpu::InstanceRecord) and a stand-in primitive
// (gpu::kShapeInstance) that the scene's BVH holds in a leaf of its own
// (shaders/instance.glsl). render/gpu_scene.cpp puts them in place.
#pragma once

#include "accel/bvh.h"
#include "device_types.h"
#include "io/texture.h"
#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace whitted {

// Shared with render/gpu_scene.cpp: whether a mesh object needs surface
// attributes (a textured mesh with texture coordinates), its triangle i's
// attributes, and a primitive's bounds padded by a few float ulps.
bool needsAttributes(const Object& object);
gpu::SurfaceAttributes surfaceAttributes(const Mesh& mesh, size_t i);
Aabb padded(Aabb b);

// Every prototype's primitives, each prototype's in its tree's leaf order
// (its tree's order is the identity), the material of its k-th object
// (over all prototypes, in order) firstMaterial + k.
struct PrototypePack {
    // One tree a prototype, collapsed for walks that arrive with up to kJoinedRootStack entries.
    std::vector<WideBvh> trees;
    std::vector<uint32_t> firstPrimitive;    // of each prototype, among `primitives`
    std::vector<uint32_t> firstNode;         // of each prototype's tree, among the prototypes' nodes in order
    std::vector<gpu::Primitive> primitives;
    std::vector<uint32_t> primitiveInObject;  // each one's index in its prototype object
    std::vector<gpu::SurfaceAttributes> attributes;  // when packed with attributes
    uint32_t shapes = 0;                      // 1 << kShape* of the shapes they hold
};
PrototypePack packPrototypes(const Scene& scene, uint32_t firstMaterial, bool attributes);

// The prototypes' trees one after another, as they follow the scene's own
// `nodeBase` nodes, their primitives from `primitiveBase` on.
std::vector<gpu::BvhNode> prototypeNodes(const PrototypePack& prototypes, uint32_t nodeBase, uint32_t primitiveBase);

// Each instance's record (its rootNode relative to the prototypes' first
// node), its stand-in primitive and the one-leaf tree over it that
// joinWide takes as a part. An instance with a material of its own takes
// firstMaterial + k, k its place among those.
struct InstancePack {
    std::vector<gpu::InstanceRecord> records;
    std::vector<gpu::Primitive> proxies;
    std::vector<WideBvh> leafTrees;
};
InstancePack packInstances(const Scene& scene, const PrototypePack& prototypes, uint32_t firstMaterial);

// The materials instancing adds after the scene's objects' and csg
// children's: each prototype object's, then each instance's own.
std::vector<Material> instanceMaterials(const Scene& scene);

}  // namespace whitted

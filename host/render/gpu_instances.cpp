#include "render/gpu_instances.h"

#include "shapes/shapes.h"

#include <algorithm>

namespace whitted {

PrototypePack packPrototypes(const Scene& scene, uint32_t firstMaterial, bool attributes) {
    PrototypePack pack;
    uint32_t material = firstMaterial;
    uint32_t nodes = 0;
    for (const Prototype& prototype : scene.prototypes) {
        // Its objects' triangles and their bounds, then its own tree over them.
        std::vector<gpu::Primitive> primitives;
        std::vector<Aabb> bounds;
        std::vector<uint32_t> inObject;
        std::vector<gpu::SurfaceAttributes> surface;
        for (const Object& object : prototype.objects) {
            size_t first = primitives.size();
            appendPrimitives(object.shape, material++, primitives, bounds);
            for (size_t k = first; k < primitives.size(); ++k) {
                pack.shapes |= 1u << primitives[k].shape;
                inObject.push_back(uint32_t(k - first));
                if (!attributes) continue;
                const Mesh* mesh = std::get_if<Mesh>(&object.shape);
                surface.push_back(needsAttributes(object) ? surfaceAttributes(*mesh, k - first)
                                                          : gpu::SurfaceAttributes{});
            }
        }
        for (Aabb& b : bounds) b = padded(b);
        WideBvh tree = buildWideBvh(bounds);
        pack.firstPrimitive.push_back(uint32_t(pack.primitives.size()));
        pack.firstNode.push_back(nodes);
        for (uint32_t k : tree.order) {
            pack.primitives.push_back(primitives[k]);
            pack.primitiveInObject.push_back(inObject[k]);
            if (attributes) pack.attributes.push_back(surface[k]);
        }
        for (uint32_t i = 0; i < tree.order.size(); ++i) tree.order[i] = i;
        nodes += uint32_t(tree.nodes.size());
        pack.trees.push_back(std::move(tree));
    }
    return pack;
}

std::vector<gpu::BvhNode> prototypeNodes(const PrototypePack& prototypes, uint32_t nodeBase, uint32_t primitiveBase) {
    std::vector<gpu::BvhNode> nodes;
    for (size_t p = 0; p < prototypes.trees.size(); ++p)
        for (gpu::BvhNode node : prototypes.trees[p].nodes) {
            node.childBase += nodeBase + prototypes.firstNode[p];
            node.primitiveBase += primitiveBase + prototypes.firstPrimitive[p];
            nodes.push_back(node);
        }
    return nodes;
}

namespace {

// The rows of an affine matrix's top three lines (xyz linear, w translation).
void rows(const glm::dmat4& m, gpu::vec4& r0, gpu::vec4& r1, gpu::vec4& r2) {
    glm::dmat4 t = glm::transpose(m);
    r0 = gpu::vec4(t[0]);
    r1 = gpu::vec4(t[1]);
    r2 = gpu::vec4(t[2]);
}

// The world box of an object-space box under an affine transform: the box
// of its eight corners, padded as a primitive's.
Aabb worldBox(const Aabb& box, const glm::dmat4& worldFromObject) {
    Aabb world;
    for (int corner = 0; corner < 8; ++corner) {
        glm::dvec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                     (corner & 4) ? box.max.z : box.min.z);
        world.extend(glm::vec3(glm::dvec3(worldFromObject * glm::dvec4(p, 1.0))));
    }
    return padded(world);
}

// A tree of one leaf holding the one primitive: joinWide's part for an instance.
WideBvh leafTree(const Aabb& box) {
    BinaryBvhNode leaf{box.min, 0u, box.max, 1u};
    WideBvh tree;
    tree.order = {0u};
    tree.nodes = collapseToWide(std::span<const BinaryBvhNode>(&leaf, 1), tree.order, kJoinedRootStack);
    tree.bounds = box;
    tree.stats.nodeCount = 1;
    tree.stats.leafCount = 1;
    tree.stats.sahCost = 1.0;
    tree.stats.wideNodeCount = uint32_t(tree.nodes.size());
    return tree;
}

}  // namespace

InstancePack packInstances(const Scene& scene, const PrototypePack& prototypes, uint32_t firstMaterial) {
    InstancePack pack;
    uint32_t ownMaterial = firstMaterial;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        gpu::InstanceRecord r;
        rows(instance.worldFromObject, r.worldFromObject0, r.worldFromObject1, r.worldFromObject2);
        rows(glm::inverse(instance.worldFromObject), r.objectFromWorld0, r.objectFromWorld1, r.objectFromWorld2);
        r.rootNode = prototypes.firstNode[instance.prototype];
        r.object = uint32_t(scene.objects.size()) + i;
        r.material = instance.material ? ownMaterial++ : gpu::kNoMaterialOverride;
        pack.records.push_back(r);
        Aabb box = worldBox(prototypes.trees[instance.prototype].bounds, instance.worldFromObject);
        pack.proxies.push_back(gpu::instancePrimitive(box.min, box.max, i, r.object));
        pack.leafTrees.push_back(leafTree(box));
    }
    return pack;
}

std::vector<Material> instanceMaterials(const Scene& scene) {
    std::vector<Material> materials;
    for (const Prototype& prototype : scene.prototypes)
        for (const Object& object : prototype.objects) materials.push_back(object.material);
    for (const Instance& instance : scene.instances)
        if (instance.material) materials.push_back(*instance.material);
    return materials;
}

}  // namespace whitted

// Bounding volume hierarchy over the scene's bounded primitives, built on
// the host as a binary tree and collapsed into the compressed 8-wide tree
// the shader walks (shaders/bvh.glsl).
#pragma once

#include "accel/aabb.h"
#include "device_types.h"

#include <span>
#include <vector>

namespace whitted {

struct BvhStats {
    double buildSeconds = 0;
    uint32_t nodeCount = 0;      // of the binary tree
    uint32_t wideNodeCount = 0;  // of the 8-wide tree the shader walks (set by whoever collapses it)
    uint32_t leafCount = 0;
    uint32_t maxDepth = 0;
    double sahCost = 0;  // expected cost, in node-visit units
};

// A node of the binary tree: an inner node has primitiveCount = 0 and its
// two children at first and first + 1; a leaf has 1 to
// gpu::kBvhMaxLeafSize primitives at first .. first + primitiveCount - 1.
struct BinaryBvhNode {
    glm::vec3 lo{0.0f};
    uint32_t first = 0;
    glm::vec3 hi{0.0f};
    uint32_t primitiveCount = 0;
};

struct Bvh {
    std::vector<BinaryBvhNode> nodes;      // nodes[0] is the root; children of an inner node are adjacent
    std::vector<uint32_t> primitiveOrder;  // leaf ranges index this permutation of the input
    BvhStats stats;
};

// Binned SAH build ("On fast Construction of SAH-based Bounding Volume
// Hierarchies", Wald 2007): centroids are binned into kBins slabs per axis,
// the split with the lowest surface-area cost wins, a node becomes a leaf
// when splitting costs more than intersecting its primitives. A range that
// SAH cannot split (equal centroids) or that could not otherwise end in
// leaves of at most gpu::kBvhMaxLeafSize within the depth bound
// (gpu::kBvhStackSize - 1) is split at its middle. Subtrees are built in
// parallel on `threads` threads (0 = all cores).
Bvh buildBvh(std::span<const Aabb> bounds, unsigned threads = 0);

// The binary tree collapsed into the compressed 8-wide tree of Ylitie,
// Karras and Laine ("Efficient Incoherent Ray Traversal on GPUs Through
// Compressed Wide BVHs", HPG 2017; gpu::BvhNode): each wide node takes the
// two children of a binary node and, while it has fewer than eight, replaces
// its inner child of largest surface area by that child's two children (the
// greedy collapse of Wald, Benthin and Boulos 2008 and Dammertz et al. 2008,
// where Ylitie et al. collapse optimally by dynamic programming on the SAH).
// It also stops where one more child could let a walk stack more than
// gpu::kBvhWideStackSize entries (a bound kept from every node's height).
// Leaves are the binary tree's leaves (the same primitive sets); `order`
// (Bvh::primitiveOrder) is permuted so that each wide node's leaf children
// hold consecutive primitives. Node 0 is the root (a single leaf becomes a
// root with one child); each node's inner children are adjacent and their
// subtrees follow depth first. W wide nodes over L leaves: W <= max(L - 1, 1).
std::vector<gpu::BvhNode> collapseToWide(std::span<const BinaryBvhNode> binary, std::vector<uint32_t>& order);

// Quantises up to gpu::kBvhWidth child boxes onto one node's grid
// (origin, exponents and the quantX/Y/Z bytes; the rest left as it is):
// lo rounded down and hi up, checked in float arithmetic as the shader
// decodes them, so that decodeChildBox contains each child's box.
void quantiseChildren(std::span<const Aabb> children, gpu::BvhNode& node);
// Child k's box as the node stores it: origin + q * 2^(e - 127) per bound.
Aabb decodeChildBox(const gpu::BvhNode& node, uint32_t k);

}  // namespace whitted

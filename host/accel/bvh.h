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
    // A joined tree (joinWide, render/gpu_scene.h BvhPartCache): its parts,
    // those taken from an earlier build, and the primitives whose trees this
    // build made (all of them without parts).
    uint32_t parts = 0;
    uint32_t partsReused = 0;
    uint64_t primitivesBuilt = 0;
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

// What a build may make: leaves of at most maxLeafSize primitives, at most
// maxDepth levels below the root (at most maxLeafSize << maxDepth primitives).
struct BvhBuildLimits {
    uint32_t maxLeafSize = gpu::kBvhMaxLeafSize;
    uint32_t maxDepth = gpu::kBvhStackSize - 1;
};

// Binned SAH build ("On fast Construction of SAH-based Bounding Volume
// Hierarchies", Wald 2007): centroids are binned into kBins slabs per axis,
// the split with the lowest surface-area cost wins, a node becomes a leaf
// when splitting costs more than intersecting its primitives. A range that
// SAH cannot split (equal centroids) or that could not otherwise end in
// leaves of at most gpu::kBvhMaxLeafSize within the depth bound
// (gpu::kBvhStackSize - 1) is split at its middle. Subtrees are built in
// parallel on `threads` threads (0 = all cores).
Bvh buildBvh(std::span<const Aabb> bounds, unsigned threads = 0, BvhBuildLimits limits = {});

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
// rootStacked: the most entries a walk holds when it reaches the root, the
// root's own included (1 for a whole tree; kJoinedRootStack for a part of joinWide).
std::vector<gpu::BvhNode> collapseToWide(std::span<const BinaryBvhNode> binary, std::vector<uint32_t>& order,
                                         uint32_t rootStacked = 1);

// Two levels in the one tree the shader walks, so that a scene edit rebuilds
// only the parts it changed (a moved object's own tree and the top level
// over the parts; render/gpu_scene.h's BvhPartCache keeps the others). Each
// part is a wide tree collapsed on its own, for walks that arrive at its
// root with up to kJoinedRootStack entries; joinWide builds a binary SAH
// tree over the parts' boxes (one part a leaf, at most kJoinedRootStack - 1
// levels, so that walks arrive within that), collapses it as collapseToWide
// does, and puts each part's root where its leaf was, as an inner child, the
// part's other nodes after it (child and primitive bases shifted). Parts
// overlap where their objects do, as the instances of a two-level BVH do
// (Wald, Boulos and Shirley 2007; the bottom and top levels of DXR and
// Vulkan ray tracing), without their transforms: parts are in world space.
inline constexpr uint32_t kJoinedRootStack = 16;
inline constexpr uint32_t kMaxJoinedParts = 1u << (kJoinedRootStack - 1);
static_assert(kJoinedRootStack + gpu::kBvhStackSize <= gpu::kBvhWideStackSize,
              "a part's binary spine of kBvhStackSize - 1 levels must fit under a joined root");

struct WideBvh {
    std::vector<gpu::BvhNode> nodes;  // nodes[0] is the root
    std::vector<uint32_t> order;      // its leaves' primitives, indices into its build's input
    Aabb bounds;                      // of every input box
    BvhStats stats;
};
// buildBvh, then collapseToWide for a part (rootStacked kJoinedRootStack).
WideBvh buildWideBvh(std::span<const Aabb> bounds, unsigned threads = 0);
// One tree over parts (at most kMaxJoinedParts, none empty): part p's
// primitive i is primitive partFirst[p] + i of `order`'s numbering. `order`
// becomes the leaves' primitives in the joined tree's order; `stats` the
// joined tree's, as buildBvh counts them (but buildSeconds, left 0).
std::vector<gpu::BvhNode> joinWide(std::span<const WideBvh* const> parts, std::span<const uint32_t> partFirst,
                                   std::vector<uint32_t>& order, BvhStats& stats);

// Quantises up to gpu::kBvhWidth child boxes onto one node's grid
// (origin, exponents and the quantX/Y/Z bytes; the rest left as it is):
// lo rounded down and hi up, checked in float arithmetic as the shader
// decodes them, so that decodeChildBox contains each child's box.
void quantiseChildren(std::span<const Aabb> children, gpu::BvhNode& node);
// Child k's box as the node stores it: origin + q * 2^(e - 127) per bound.
Aabb decodeChildBox(const gpu::BvhNode& node, uint32_t k);

}  // namespace whitted

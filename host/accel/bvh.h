// Bounding volume hierarchy over the scene's bounded primitives, built on
// the host and flattened for the shader (shaders/bvh.glsl traverses it).
#pragma once

#include "accel/aabb.h"
#include "device_types.h"

#include <span>
#include <vector>

namespace whitted {

struct BvhStats {
    double buildSeconds = 0;
    uint32_t nodeCount = 0;
    uint32_t leafCount = 0;
    uint32_t maxDepth = 0;
    double sahCost = 0;  // expected cost, in node-visit units
};

struct Bvh {
    std::vector<gpu::BvhNode> nodes;     // nodes[0] is the root; children of an inner node are adjacent
    std::vector<uint32_t> primitiveOrder;  // leaf ranges index this permutation of the input
    BvhStats stats;
};

// Binned SAH build ("On fast Construction of SAH-based Bounding Volume
// Hierarchies", Wald 2007): centroids are binned into kBins slabs per axis,
// the split with the lowest surface-area cost wins, a node becomes a leaf
// when splitting costs more than intersecting its primitives. Subtrees are
// built in parallel on `threads` threads (0 = all cores).
Bvh buildBvh(std::span<const Aabb> bounds, unsigned threads = 0);

// The binary tree collapsed into a 4-wide one, in the same 32-byte nodes:
// an inner node's two to four children are adjacent slots, BvhNode::first holding
// the first and their count (gpu::kBvhChildCountShift); leaves are the
// binary tree's leaves unchanged (same primitive ranges). Each wide node
// takes the two children of a binary node and, while it has fewer than
// four, replaces its inner child of largest surface area by that child's
// two children (the greedy collapse of Wald, Benthin and Boulos 2008 and
// Dammertz et al. 2008; Ylitie, Karras and Laine 2017 collapse optimally by
// dynamic programming on the SAH). Slot 0 is the root. A node with fewer
// than four children has leaves only, so W wide nodes over L leaves have
// W <= (2 L - 1) / 3 and the tree W + L <= 2 L - 1 slots, no more than the
// binary tree. A walk needs at most 3/2 the binary depth in stack entries
// (gpu::kBvhWideStackSize).
std::vector<gpu::BvhNode> collapseToWide(std::span<const gpu::BvhNode> binary);

}  // namespace whitted

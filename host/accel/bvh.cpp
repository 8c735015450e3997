#include "accel/bvh.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <future>
#include <memory>
#include <thread>

namespace whitted {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kMaxLeafSize = 8;
constexpr uint32_t kMaxDepth = gpu::kBvhStackSize - 1;
constexpr float kTraversalCost = 1.0f;     // relative to one primitive test
constexpr uint32_t kParallelThreshold = 16384;  // primitives; smaller subtrees stay on one thread

struct BuildNode {
    Aabb bounds;
    uint32_t first = 0, count = 0;  // leaf range in the order array
    std::unique_ptr<BuildNode> left, right;
};

// A primitive's bounds, centroid and input index, kept together and
// partitioned in place so every pass reads memory in order (an index array
// into the input bounds made each pass a random gather, a large share of a
// big mesh's build time; measured: see tools/benchmark_results/README.md).
struct PrimitiveRef {
    Aabb bounds;
    glm::vec3 centroid;
    uint32_t index;
};

struct Builder {
    std::vector<PrimitiveRef> refs;
    std::atomic<int> freeThreads{0};

    std::unique_ptr<BuildNode> build(uint32_t first, uint32_t count, uint32_t depth) {
        auto node = std::make_unique<BuildNode>();
        Aabb centroidBounds;
        for (uint32_t i = first; i < first + count; ++i) {
            node->bounds.extend(refs[i].bounds);
            centroidBounds.extend(refs[i].centroid);
        }
        node->first = first;
        node->count = count;
        if (count <= 1 || depth >= kMaxDepth) return node;

        // Binned SAH over the three axes.
        float bestCost = std::numeric_limits<float>::infinity();
        int bestAxis = -1, bestSplit = 0;
        glm::vec3 extent = centroidBounds.max - centroidBounds.min;
        // One pass bins the primitives along all three axes at once.
        Aabb bins[3][kBins];
        uint32_t binCounts[3][kBins] = {};
        glm::vec3 scales = glm::vec3(float(kBins)) / extent;
        for (uint32_t i = first; i < first + count; ++i) {
            glm::vec3 rel = (refs[i].centroid - centroidBounds.min) * scales;
            for (int axis = 0; axis < 3; ++axis) {
                if (!(extent[axis] > 0)) continue;
                int b = std::min(kBins - 1, int(rel[axis]));
                bins[axis][b].extend(refs[i].bounds);
                ++binCounts[axis][b];
            }
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0)) continue;
            const Aabb* binBounds = bins[axis];
            const uint32_t* binCount = binCounts[axis];
            // Sweep from the right to get suffix areas, then from the left.
            float rightArea[kBins];
            uint32_t rightCount[kBins];
            Aabb acc;
            uint32_t n = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc.extend(binBounds[b]);
                n += binCount[b];
                rightArea[b] = acc.surfaceArea();
                rightCount[b] = n;
            }
            acc = Aabb();
            n = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.extend(binBounds[b]);
                n += binCount[b];
                if (n == 0 || rightCount[b + 1] == 0) continue;
                float cost = acc.surfaceArea() * float(n) + rightArea[b + 1] * float(rightCount[b + 1]);
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestSplit = b;
                }
            }
        }
        float parentArea = node->bounds.surfaceArea();
        float leafCost = float(count);
        float splitCost = kTraversalCost + (parentArea > 0 ? bestCost / parentArea : float(count));
        if (bestAxis < 0 || (count <= kMaxLeafSize && leafCost <= splitCost)) return node;

        // Partition by bin.
        float scale = kBins / extent[bestAxis];
        auto mid = std::partition(refs.begin() + first, refs.begin() + first + count, [&](const PrimitiveRef& p) {
            int b = std::min(kBins - 1, int((p.centroid[bestAxis] - centroidBounds.min[bestAxis]) * scale));
            return b <= bestSplit;
        });
        uint32_t leftCount = uint32_t(mid - (refs.begin() + first));
        if (leftCount == 0 || leftCount == count) return node;

        // Large subtrees are built in parallel while threads are free.
        if (count > kParallelThreshold && freeThreads.fetch_sub(1) > 0) {
            auto future = std::async(std::launch::async, [&] { return build(first, leftCount, depth + 1); });
            node->right = build(first + leftCount, count - leftCount, depth + 1);
            node->left = future.get();
            freeThreads.fetch_add(1);
        } else {
            if (count > kParallelThreshold) freeThreads.fetch_add(1);
            node->left = build(first, leftCount, depth + 1);
            node->right = build(first + leftCount, count - leftCount, depth + 1);
        }
        node->count = 0;
        return node;
    }
};

// Flattens depth first, the two children of a node in adjacent slots.
void flatten(const BuildNode& node, uint32_t index, uint32_t depth, Bvh& bvh) {
    gpu::BvhNode& out = bvh.nodes[index];
    out.lo = node.bounds.min;
    out.hi = node.bounds.max;
    bvh.stats.maxDepth = std::max(bvh.stats.maxDepth, depth);
    if (!node.left) {
        out.first = node.first;
        out.primitiveCount = node.count;
        ++bvh.stats.leafCount;
        return;
    }
    uint32_t children = uint32_t(bvh.nodes.size());
    out.first = children;
    out.primitiveCount = 0u;
    bvh.nodes.resize(bvh.nodes.size() + 2);
    flatten(*node.left, children, depth + 1, bvh);
    flatten(*node.right, children + 1, depth + 1, bvh);
}

// Expected traversal cost of the tree (for reports): sum over nodes of
// area(node) / area(root) times the node's work.
double sahCost(const Bvh& bvh) {
    if (bvh.nodes.empty()) return 0;
    auto area = [](const gpu::BvhNode& n) {
        Aabb b;
        b.min = n.lo;
        b.max = n.hi;
        return double(b.surfaceArea());
    };
    double rootArea = std::max(area(bvh.nodes[0]), 1e-30);
    double cost = 0;
    for (const gpu::BvhNode& n : bvh.nodes) {
        uint32_t count = n.primitiveCount;
        cost += area(n) / rootArea * (count ? double(count) : kTraversalCost);
    }
    return cost;
}

// Area of a node's box (for the collapse's choice).
float nodeArea(const gpu::BvhNode& n) {
    Aabb b;
    b.min = n.lo;
    b.max = n.hi;
    return b.surfaceArea();
}

bool isInner(const gpu::BvhNode& n) { return n.primitiveCount == 0u; }

// Fills the four child slots of wide node `slot` from binary inner node b.
void collapseNode(std::span<const gpu::BvhNode> binary, uint32_t b, uint32_t slot, std::vector<gpu::BvhNode>& out) {
    uint32_t first = binary[b].first;
    std::vector<uint32_t> children = {first, first + 1};
    while (children.size() < 4) {
        int open = -1;
        for (int k = 0; k < int(children.size()); ++k)
            if (isInner(binary[children[k]]) &&
                (open < 0 || nodeArea(binary[children[k]]) > nodeArea(binary[children[open]])))
                open = k;
        if (open < 0) break;
        uint32_t c = binary[children[open]].first;
        // In place, so that the children keep the binary tree's order.
        children[open] = c;
        children.insert(children.begin() + open + 1, c + 1);
    }
    uint32_t wide = uint32_t(out.size());
    uint32_t count = uint32_t(children.size());
    out[slot].first = ((count - 2u) << gpu::kBvhChildCountShift) | wide;
    out.resize(out.size() + count);
    for (uint32_t k = 0; k < children.size(); ++k) out[wide + k] = binary[children[k]];
    for (uint32_t k = 0; k < children.size(); ++k)
        if (isInner(binary[children[k]])) collapseNode(binary, children[k], wide + k, out);
}

}  // namespace

std::vector<gpu::BvhNode> collapseToWide(std::span<const gpu::BvhNode> binary) {
    std::vector<gpu::BvhNode> out;
    if (binary.empty()) return out;
    out.reserve(2 * binary.size() + 4);
    out.push_back(binary[0]);
    if (isInner(binary[0])) collapseNode(binary, 0, 0, out);
    return out;
}

Bvh buildBvh(std::span<const Aabb> bounds, unsigned threads) {
    auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    if (bounds.empty()) return bvh;
    Builder builder;
    builder.refs.resize(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i) builder.refs[i] = {bounds[i], bounds[i].center(), i};
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    builder.freeThreads = int(threads) - 1;
    std::unique_ptr<BuildNode> root = builder.build(0, uint32_t(bounds.size()), 0);

    bvh.nodes.reserve(2 * bounds.size());
    bvh.nodes.resize(1);
    flatten(*root, 0, 0, bvh);
    bvh.primitiveOrder.resize(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i) bvh.primitiveOrder[i] = builder.refs[i].index;
    bvh.stats.nodeCount = uint32_t(bvh.nodes.size());
    bvh.stats.sahCost = sahCost(bvh);
    bvh.stats.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace whitted

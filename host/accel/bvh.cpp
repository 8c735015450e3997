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

struct Builder {
    std::span<const Aabb> bounds;
    std::vector<glm::vec3> centroids;
    std::vector<uint32_t> order;
    std::atomic<int> freeThreads{0};

    std::unique_ptr<BuildNode> build(uint32_t first, uint32_t count, uint32_t depth) {
        auto node = std::make_unique<BuildNode>();
        Aabb centroidBounds;
        for (uint32_t i = first; i < first + count; ++i) {
            node->bounds.extend(bounds[order[i]]);
            centroidBounds.extend(centroids[order[i]]);
        }
        node->first = first;
        node->count = count;
        if (count <= 1 || depth >= kMaxDepth) return node;

        // Binned SAH over the three axes.
        float bestCost = std::numeric_limits<float>::infinity();
        int bestAxis = -1, bestSplit = 0;
        glm::vec3 extent = centroidBounds.max - centroidBounds.min;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0)) continue;
            Aabb binBounds[kBins];
            uint32_t binCount[kBins] = {};
            float scale = kBins / extent[axis];
            for (uint32_t i = first; i < first + count; ++i) {
                int b = std::min(kBins - 1, int((centroids[order[i]][axis] - centroidBounds.min[axis]) * scale));
                binBounds[b].extend(bounds[order[i]]);
                ++binCount[b];
            }
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
        auto mid = std::partition(order.begin() + first, order.begin() + first + count, [&](uint32_t p) {
            int b = std::min(kBins - 1, int((centroids[p][bestAxis] - centroidBounds.min[bestAxis]) * scale));
            return b <= bestSplit;
        });
        uint32_t leftCount = uint32_t(mid - (order.begin() + first));
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
    out.lo = glm::vec4(node.bounds.min, 0.0f);
    out.hi = glm::vec4(node.bounds.max, 0.0f);
    bvh.stats.maxDepth = std::max(bvh.stats.maxDepth, depth);
    if (!node.left) {
        out.lo.w = std::bit_cast<float>(node.first);
        out.hi.w = std::bit_cast<float>(node.count);
        ++bvh.stats.leafCount;
        return;
    }
    uint32_t children = uint32_t(bvh.nodes.size());
    out.lo.w = std::bit_cast<float>(children);
    out.hi.w = std::bit_cast<float>(0u);
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
        b.min = glm::vec3(n.lo);
        b.max = glm::vec3(n.hi);
        return double(b.surfaceArea());
    };
    double rootArea = std::max(area(bvh.nodes[0]), 1e-30);
    double cost = 0;
    for (const gpu::BvhNode& n : bvh.nodes) {
        uint32_t count = std::bit_cast<uint32_t>(n.hi.w);
        cost += area(n) / rootArea * (count ? double(count) : kTraversalCost);
    }
    return cost;
}

}  // namespace

Bvh buildBvh(std::span<const Aabb> bounds, unsigned threads) {
    auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    if (bounds.empty()) return bvh;
    Builder builder;
    builder.bounds = bounds;
    builder.centroids.resize(bounds.size());
    builder.order.resize(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i) {
        builder.centroids[i] = bounds[i].center();
        builder.order[i] = i;
    }
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    builder.freeThreads = int(threads) - 1;
    std::unique_ptr<BuildNode> root = builder.build(0, uint32_t(bounds.size()), 0);

    bvh.nodes.reserve(2 * bounds.size());
    bvh.nodes.resize(1);
    flatten(*root, 0, 0, bvh);
    bvh.primitiveOrder = std::move(builder.order);
    bvh.stats.nodeCount = uint32_t(bvh.nodes.size());
    bvh.stats.sahCost = sahCost(bvh);
    bvh.stats.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace whitted

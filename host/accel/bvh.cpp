#include "accel/bvh.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

namespace whitted {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kMaxLeafSize = gpu::kBvhMaxLeafSize;
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
    uint32_t maxLeafSize = kMaxLeafSize;
    uint32_t maxDepth = kMaxDepth;

    std::unique_ptr<BuildNode> build(uint32_t first, uint32_t count, uint32_t depth) {
        auto node = std::make_unique<BuildNode>();
        Aabb centroidBounds;
        for (uint32_t i = first; i < first + count; ++i) {
            node->bounds.extend(refs[i].bounds);
            centroidBounds.extend(refs[i].centroid);
        }
        node->first = first;
        node->count = count;
        if (count <= 1 || depth >= maxDepth) return node;

        // Binned SAH over the three axes.
        float bestCost = std::numeric_limits<float>::infinity();
        int bestAxis = -1, bestSplit = 0;
        glm::vec3 extent = centroidBounds.max - centroidBounds.min;
        // One pass bins the primitives along all three axes at once.
        Aabb bins[3][kBins];
        uint32_t binCounts[3][kBins] = {};
        glm::vec3 scales = glm::vec3(float(kBins)) / extent;
        // An axis is binned where its centroids spread and kBins / extent is
        // finite (a subnormal extent is not).
        bool binned[3];
        for (int axis = 0; axis < 3; ++axis) binned[axis] = extent[axis] > 0 && std::isfinite(scales[axis]);
        for (uint32_t i = first; i < first + count; ++i) {
            glm::vec3 rel = (refs[i].centroid - centroidBounds.min) * scales;
            for (int axis = 0; axis < 3; ++axis) {
                if (!binned[axis]) continue;
                int b = std::min(kBins - 1, int(rel[axis]));
                bins[axis][b].extend(refs[i].bounds);
                ++binCounts[axis][b];
            }
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (!binned[axis]) continue;
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
        if (count <= maxLeafSize && (bestAxis < 0 || leafCost <= splitCost)) return node;

        // Partition by bin; a range SAH cannot split, or whose larger side
        // could not end in leaves of at most maxLeafSize within the depth
        // bound (count <= maxLeafSize << (maxDepth - depth) holds for every
        // node), is split at its middle.
        uint32_t leftCount = 0;
        if (bestAxis >= 0) {
            float scale = kBins / extent[bestAxis];
            auto mid = std::partition(refs.begin() + first, refs.begin() + first + count, [&](const PrimitiveRef& p) {
                int b = std::min(kBins - 1, int((p.centroid[bestAxis] - centroidBounds.min[bestAxis]) * scale));
                return b <= bestSplit;
            });
            leftCount = uint32_t(mid - (refs.begin() + first));
        }
        uint32_t remaining = maxDepth - depth - 1;  // levels below the children
        uint64_t childLimit = remaining >= 32 ? UINT64_MAX : uint64_t(maxLeafSize) << remaining;
        bool unsplit = leftCount == 0 || leftCount == count;
        if (unsplit && count <= maxLeafSize) return node;
        if (unsplit || std::max(leftCount, count - leftCount) > childLimit) leftCount = count / 2;

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
    BinaryBvhNode& out = bvh.nodes[index];
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

Aabb boxOf(const BinaryBvhNode& n) {
    Aabb b;
    b.min = n.lo;
    b.max = n.hi;
    return b;
}

// Expected traversal cost of the tree (for reports): sum over nodes of
// area(node) / area(root) times the node's work.
double sahCost(const Bvh& bvh) {
    if (bvh.nodes.empty()) return 0;
    auto area = [](const BinaryBvhNode& n) { return double(boxOf(n).surfaceArea()); };
    double rootArea = std::max(area(bvh.nodes[0]), 1e-30);
    double cost = 0;
    for (const BinaryBvhNode& n : bvh.nodes) {
        uint32_t count = n.primitiveCount;
        cost += area(n) / rootArea * (count ? double(count) : kTraversalCost);
    }
    return cost;
}

bool isInner(const BinaryBvhNode& n) { return n.primitiveCount == 0u; }

// The shader's decode of one bound: origin + q * scale, one rounding (the
// product is exact).
float decode(float origin, uint32_t q, float scale) { return origin + float(q) * scale; }

float scaleOf(uint32_t biased) { return std::bit_cast<float>(biased << 23); }

uint32_t byteOf(uint32_t word, uint32_t k) { return (word >> (8u * (k & 3u))) & 0xffu; }

// Writes byte k (0-7) of a pair of words (k < 4: word a, else word b).
void setByte(uint32_t& a, uint32_t& b, uint32_t k, uint32_t value) {
    uint32_t& word = k < 4 ? a : b;
    word |= value << (8u * (k & 3u));
}

struct Collapser {
    std::span<const BinaryBvhNode> binary;
    const std::vector<uint32_t>& order;
    std::vector<uint32_t> height;  // of each binary node's subtree (a leaf: 0)
    std::vector<gpu::BvhNode> out;
    std::vector<uint32_t> newOrder;
    // joinWide's top level: each binary leaf holds one part (order[first]),
    // which goes in as an inner child, its own nodes after; empty otherwise.
    std::span<const WideBvh* const> parts{};
    std::span<const uint32_t> partFirst{};

    bool isPart(const BinaryBvhNode& n) const { return !parts.empty() && !isInner(n); }
    // Walks inside a part may stack up to kBvhWideStackSize - kJoinedRootStack
    // entries more than it arrives with: its height, for the bound below.
    uint32_t computeHeight(uint32_t b) {
        const BinaryBvhNode& n = binary[b];
        if (isPart(n)) return height[b] = gpu::kBvhWideStackSize - kJoinedRootStack;
        if (!isInner(n)) return height[b] = 0;
        return height[b] = 1 + std::max(computeHeight(n.first), computeHeight(n.first + 1));
    }

    // Part `p`'s root into slot `slot`, its other nodes appended, its
    // primitives (numbered from partFirst[p]) appended to newOrder.
    void placePart(uint32_t p, uint32_t slot) {
        const WideBvh& part = *parts[p];
        uint32_t nodeShift = uint32_t(out.size()) - 1;  // node j > 0 goes to j + nodeShift
        uint32_t primitiveShift = uint32_t(newOrder.size());
        auto relocate = [&](gpu::BvhNode node) {
            node.childBase += nodeShift;
            node.primitiveBase += primitiveShift;
            return node;
        };
        out[slot] = relocate(part.nodes[0]);
        for (size_t j = 1; j < part.nodes.size(); ++j) out.push_back(relocate(part.nodes[j]));
        for (uint32_t local : part.order) newOrder.push_back(partFirst[p] + local);
    }

    // Fills wide node `slot` from binary node b (inner, or a leaf for a
    // root that is one). `stacked`: the most entries a walk may hold when it
    // reaches this node, itself included (the root: 1). A child reached
    // from here may find stacked - 1 + (children) entries, and below it one
    // more per level at least, so a node keeps children + the tallest one's
    // height + stacked - 1 within gpu::kBvhWideStackSize; two children
    // always fit since the builder keeps the binary height below kBvhStackSize.
    void fill(uint32_t b, uint32_t slot, uint32_t stacked) {
        // Fixed arrays: one heap allocation a node made a large share of
        // the collapse's time.
        uint32_t children[gpu::kBvhWidth];
        uint32_t count = 0;
        if (isInner(binary[b])) {
            children[count++] = binary[b].first;
            children[count++] = binary[b].first + 1;
        } else {
            children[count++] = b;
        }
        while (count < gpu::kBvhWidth) {
            int open = -1;
            float openArea = 0;
            uint32_t tallestOther = 0;
            for (int k = 0; k < int(count); ++k) {
                if (!isInner(binary[children[k]])) continue;
                float area = boxOf(binary[children[k]]).surfaceArea();
                if (open < 0 || area > openArea) {
                    open = k;
                    openArea = area;
                }
            }
            if (open < 0) break;
            for (int k = 0; k < int(count); ++k)
                if (k != open) tallestOther = std::max(tallestOther, height[children[k]]);
            uint32_t c = binary[children[open]].first;
            uint32_t tallest = std::max({tallestOther, height[c], height[c + 1]});
            if (stacked - 1 + (count + 1) + tallest > gpu::kBvhWideStackSize) break;
            // In place, so that the children keep the binary tree's order.
            for (int k = int(count); k > open + 1; --k) children[k] = children[k - 1];
            children[open] = c;
            children[open + 1] = c + 1;
            ++count;
        }

        gpu::BvhNode node;
        Aabb boxes[gpu::kBvhWidth];
        for (uint32_t k = 0; k < count; ++k) boxes[k] = boxOf(binary[children[k]]);
        quantiseChildren(std::span<const Aabb>(boxes, count), node);
        node.primitiveBase = uint32_t(newOrder.size());
        node.childBase = uint32_t(out.size());
        uint32_t inner = 0;
        uint32_t innerChildren[gpu::kBvhWidth];
        for (uint32_t k = 0; k < count; ++k) {
            const BinaryBvhNode& child = binary[children[k]];
            if (isInner(child) || isPart(child)) {
                setByte(node.childInfo0, node.childInfo1, k, gpu::kBvhChildInner | inner);
                innerChildren[inner++] = children[k];
            } else {
                setByte(node.childInfo0, node.childInfo1, k, child.primitiveCount);
                newOrder.insert(newOrder.end(), order.begin() + child.first,
                                order.begin() + child.first + child.primitiveCount);
            }
        }
        out.resize(out.size() + inner);
        out[slot] = node;
        uint32_t childStacked = stacked - 1 + count;
        for (uint32_t k = 0; k < inner; ++k) {
            const BinaryBvhNode& child = binary[innerChildren[k]];
            if (isPart(child)) placePart(order[child.first], node.childBase + k);
            else fill(innerChildren[k], node.childBase + k, childStacked);
        }
    }
};

}  // namespace

void quantiseChildren(std::span<const Aabb> children, gpu::BvhNode& node) {
    Aabb all;
    for (const Aabb& c : children) all.extend(c);
    node.origin = all.min;
    node.exponents &= 0xff000000u;
    uint32_t* words[3] = {&node.quantX[0], &node.quantY[0], &node.quantZ[0]};
    for (int axis = 0; axis < 3; ++axis) {
        float lo = all.min[axis], hi = all.max[axis];
        // The smallest power-of-two step whose 255 steps reach hi from lo.
        double extent = double(hi) - double(lo);
        int e = extent > 0 ? int(std::ceil(std::log2(extent / 255.0))) : -126;
        e = std::clamp(e, -126, 127);
        while (e < 127 && decode(lo, 255u, std::ldexp(1.0f, e)) < hi) ++e;
        uint32_t biased = uint32_t(e + 127);
        float scale = scaleOf(biased);
        node.exponents |= biased << (8 * axis);
        uint32_t* q = words[axis];
        q[0] = q[1] = q[2] = q[3] = 0;
        for (uint32_t k = 0; k < children.size(); ++k) {
            const Aabb& c = children[k];
            double steps = (double(c.min[axis]) - double(lo)) / double(scale);
            uint32_t qlo = uint32_t(std::clamp(std::floor(steps), 0.0, 255.0));
            while (qlo > 0 && decode(lo, qlo, scale) > c.min[axis]) --qlo;
            steps = (double(c.max[axis]) - double(lo)) / double(scale);
            uint32_t qhi = uint32_t(std::clamp(std::ceil(steps), 0.0, 255.0));
            while (qhi < 255 && decode(lo, qhi, scale) < c.max[axis]) ++qhi;
            setByte(q[0], q[1], k, qlo);
            setByte(q[2], q[3], k, qhi);
        }
    }
}

Aabb decodeChildBox(const gpu::BvhNode& node, uint32_t k) {
    Aabb b;
    const glm::uvec4* quant[3] = {&node.quantX, &node.quantY, &node.quantZ};
    for (int axis = 0; axis < 3; ++axis) {
        float scale = scaleOf((node.exponents >> (8 * axis)) & 0xffu);
        const glm::uvec4& q = *quant[axis];
        b.min[axis] = decode(node.origin[axis], byteOf(k < 4 ? q.x : q.y, k), scale);
        b.max[axis] = decode(node.origin[axis], byteOf(k < 4 ? q.z : q.w, k), scale);
    }
    return b;
}

std::vector<gpu::BvhNode> collapseToWide(std::span<const BinaryBvhNode> binary, std::vector<uint32_t>& order,
                                         uint32_t rootStacked) {
    if (binary.empty()) return {};
    Collapser c{binary, order, std::vector<uint32_t>(binary.size(), 0u), {}, {}};
    c.computeHeight(0);
    c.out.reserve(binary.size() / 2 + 1);
    c.newOrder.reserve(order.size());
    c.out.resize(1);
    c.fill(0, 0, rootStacked);
    order = std::move(c.newOrder);
    return std::move(c.out);
}

WideBvh buildWideBvh(std::span<const Aabb> bounds, unsigned threads) {
    WideBvh part;
    for (const Aabb& b : bounds) part.bounds.extend(b);
    Bvh bvh = buildBvh(bounds, threads);
    part.stats = bvh.stats;
    part.order = std::move(bvh.primitiveOrder);
    part.nodes = collapseToWide(bvh.nodes, part.order, kJoinedRootStack);
    part.stats.wideNodeCount = uint32_t(part.nodes.size());
    return part;
}

std::vector<gpu::BvhNode> joinWide(std::span<const WideBvh* const> parts, std::span<const uint32_t> partFirst,
                                   std::vector<uint32_t>& order, BvhStats& stats) {
    order.clear();
    if (parts.size() != partFirst.size()) throw std::logic_error("joinWide: one first primitive a part");
    if (parts.size() > kMaxJoinedParts)
        throw std::logic_error("joinWide: " + std::to_string(parts.size()) + " parts, more than " +
                               std::to_string(kMaxJoinedParts));
    std::vector<Aabb> partBounds;
    size_t primitives = 0;
    for (const WideBvh* part : parts) {
        if (part->nodes.empty()) throw std::logic_error("joinWide: an empty part");
        partBounds.push_back(part->bounds);
        primitives += part->order.size();
    }
    if (parts.empty()) return {};
    // One part a leaf, a part at most kJoinedRootStack - 1 levels down:
    // walks arrive at its root with at most kJoinedRootStack entries.
    Bvh top = buildBvh(partBounds, 1, {.maxLeafSize = 1, .maxDepth = kJoinedRootStack - 1});
    // The joined tree's statistics as buildBvh's would count them: each
    // part's nodes at the depth of its leaf in the top level; the expected
    // cost sums every part's (scaled by its box's area) and the top level's
    // inner nodes.
    stats = {};
    double rootArea = std::max(double(boxOf(top.nodes[0]).surfaceArea()), 1e-30);
    std::function<void(uint32_t, uint32_t)> count = [&](uint32_t b, uint32_t depth) {
        const BinaryBvhNode& n = top.nodes[b];
        if (isInner(n)) {
            stats.nodeCount += 1;
            stats.sahCost += double(boxOf(n).surfaceArea()) / rootArea * kTraversalCost;
            count(n.first, depth + 1);
            count(n.first + 1, depth + 1);
            return;
        }
        const BvhStats& part = parts[top.primitiveOrder[n.first]]->stats;
        stats.nodeCount += part.nodeCount;
        stats.leafCount += part.leafCount;
        stats.maxDepth = std::max(stats.maxDepth, depth + part.maxDepth);
        stats.sahCost += part.sahCost * double(boxOf(n).surfaceArea()) / rootArea;
    };
    count(0, 0);
    Collapser c{top.nodes, top.primitiveOrder, std::vector<uint32_t>(top.nodes.size(), 0u), {}, {}, parts, partFirst};
    c.newOrder.reserve(primitives);
    c.computeHeight(0);
    c.out.resize(1);
    if (top.nodes.size() == 1) {  // a single part is the tree
        c.placePart(top.primitiveOrder[0], 0);
    } else {
        c.fill(0, 0, 1);
    }
    order = std::move(c.newOrder);
    stats.wideNodeCount = uint32_t(c.out.size());
    return std::move(c.out);
}

Bvh buildBvh(std::span<const Aabb> bounds, unsigned threads, BvhBuildLimits limits) {
    auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    if (bounds.empty()) return bvh;
    Builder builder;
    builder.refs.resize(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i) builder.refs[i] = {bounds[i], bounds[i].center(), i};
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    builder.freeThreads = int(threads) - 1;
    builder.maxLeafSize = limits.maxLeafSize;
    builder.maxDepth = limits.maxDepth;
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

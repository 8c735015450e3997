// The BVH: structure invariants of the builder, and the same images as the
// brute-force loop over every primitive.
#include "accel/bvh.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <functional>
#include <numbers>
#include <random>
#include <set>

namespace whitted::test {
namespace {

// Every primitive in exactly one leaf, every node's box containing its
// children's boxes or its primitives' boxes, children adjacent.
TEST(Bvh, BuilderInvariantsOnRandomBoxes) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-100.0f, 100.0f), size(0.01f, 3.0f);
    std::vector<Aabb> boxes(50000);
    for (Aabb& b : boxes) {
        glm::vec3 p(u(rng), u(rng), u(rng));
        b.min = p;
        b.max = p + glm::vec3(size(rng), size(rng), size(rng));
    }
    Bvh bvh = buildBvh(boxes, 2);
    ASSERT_EQ(bvh.primitiveOrder.size(), boxes.size());
    std::vector<int> seen(boxes.size(), 0);
    for (uint32_t p : bvh.primitiveOrder) ++seen[p];
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));

    auto contains = [](const BinaryBvhNode& n, const Aabb& b) {
        return glm::all(glm::lessThanEqual(glm::vec3(n.lo), b.min)) && glm::all(glm::greaterThanEqual(glm::vec3(n.hi), b.max));
    };
    size_t leafPrimitives = 0;
    for (const BinaryBvhNode& n : bvh.nodes) {
        uint32_t first = n.first, count = n.primitiveCount;
        EXPECT_LE(count, gpu::kBvhMaxLeafSize);
        if (count > 0) {
            leafPrimitives += count;
            for (uint32_t i = first; i < first + count; ++i) ASSERT_TRUE(contains(n, boxes[bvh.primitiveOrder[i]]));
        } else {
            ASSERT_LT(first + 1, bvh.nodes.size());
            for (uint32_t c : {first, first + 1}) {
                Aabb child;
                child.min = glm::vec3(bvh.nodes[c].lo);
                child.max = glm::vec3(bvh.nodes[c].hi);
                ASSERT_TRUE(contains(n, child));
            }
        }
    }
    EXPECT_EQ(leafPrimitives, boxes.size());
    EXPECT_LT(bvh.stats.maxDepth, gpu::kBvhStackSize);
    // A SAH tree over uniformly scattered boxes costs a few dozen tests per
    // ray, far below the 50000 of brute force.
    EXPECT_LT(bvh.stats.sahCost, 200.0);
}

bool contains(const Aabb& outer, const Aabb& inner) {
    return glm::all(glm::lessThanEqual(outer.min, inner.min)) && glm::all(glm::greaterThanEqual(outer.max, inner.max));
}

// The primitive sets of a tree's leaves, each sorted, in sorted order.
using LeafSets = std::vector<std::vector<uint32_t>>;

// Checks the compressed 8-wide tree the shader walks against its binary
// tree and the input boxes: every primitive in exactly one leaf, the binary
// tree's leaves unchanged (the same primitive sets), each node's leaf
// children holding consecutive primitives from its primitiveBase, every
// quantised child box containing the exact box of the primitives below it,
// one to eight children a node (two or more but at a root that is a single
// leaf), every node the child of exactly one other (or the root), no more
// nodes than max(leaves - 1, 1) (countSceneArrays' bound; extraNodes more
// for joined parts of a single leaf) and the walk's
// stack within gpu::kBvhWideStackSize. Returns how many nodes have fewer than
// eight children while one of them is an inner node.
// The leaves of a binary tree, as primitive sets (each numbered from `first`).
LeafSets binaryLeafSets(const Bvh& bvh, uint32_t first = 0) {
    LeafSets leaves;
    for (const BinaryBvhNode& node : bvh.nodes)
        if (node.primitiveCount > 0) {
            std::vector<uint32_t> set;
            for (uint32_t i = node.first; i < node.first + node.primitiveCount; ++i)
                set.push_back(first + bvh.primitiveOrder[i]);
            std::sort(set.begin(), set.end());
            leaves.push_back(std::move(set));
        }
    return leaves;
}

uint32_t checkWideTree(const std::vector<Aabb>& boxes, LeafSets binaryLeaves, const std::vector<gpu::BvhNode>& wide,
                       const std::vector<uint32_t>& order, size_t extraNodes = 0) {
    size_t n = boxes.size();
    EXPECT_EQ(order.size(), n);
    LeafSets wideLeaves;
    EXPECT_FALSE(wide.empty());
    EXPECT_LE(wide.size(), std::max<size_t>(binaryLeaves.size(), 2) - 1 + extraNodes);

    // The exact box of a subtree: its primitives' boxes, collected bottom up.
    std::vector<int> seen(n, 0);
    std::vector<int> parents(wide.size(), 0);
    uint32_t fewer = 0, maxStack = 0;
    std::function<Aabb(uint32_t, uint32_t)> visit = [&](uint32_t index, uint32_t stacked) -> Aabb {
        maxStack = std::max(maxStack, stacked);
        const gpu::BvhNode& node = wide[index];
        Aabb all;
        uint32_t children = 0, inner = 0, leafEnd = 0;
        for (uint32_t k = 0; k < gpu::kBvhWidth; ++k) {
            uint32_t info = ((k < 4 ? node.childInfo0 : node.childInfo1) >> (8 * (k & 3))) & 0xffu;
            if (info == 0) continue;
            EXPECT_EQ(children, k) << "children fill the first slots";
            ++children;
        }
        for (uint32_t k = 0; k < children; ++k) {
            uint32_t info = ((k < 4 ? node.childInfo0 : node.childInfo1) >> (8 * (k & 3))) & 0xffu;
            Aabb exact;
            // A child reached from here: this entry popped, the others pushed.
            uint32_t childStacked = stacked - 1 + children;
            maxStack = std::max(maxStack, childStacked);
            if (info & gpu::kBvhChildInner) {
                uint32_t child = node.childBase + (info & 7u);
                EXPECT_EQ(info & 7u, inner++) << "inner children in slot order";
                EXPECT_LT(child, wide.size());
                if (child >= wide.size()) continue;
                ++parents[child];
                exact = visit(child, childStacked);
            } else {
                EXPECT_LE(info, gpu::kBvhMaxLeafSize);
                std::vector<uint32_t> set;
                for (uint32_t i = node.primitiveBase + leafEnd; i < node.primitiveBase + leafEnd + info; ++i) {
                    EXPECT_LT(i, n);
                    if (i >= n) break;
                    ++seen[order[i]];
                    set.push_back(order[i]);
                    exact.extend(boxes[order[i]]);
                }
                leafEnd += info;
                std::sort(set.begin(), set.end());
                wideLeaves.push_back(std::move(set));
            }
            Aabb decoded = decodeChildBox(node, k);
            EXPECT_TRUE(contains(decoded, exact)) << "node " << index << " child " << k;
            all.extend(exact);
        }
        EXPECT_TRUE(children >= 2 || ((index == 0 || extraNodes > 0) && children == 1 && inner == 0))
            << "node " << index;
        if (children < gpu::kBvhWidth && inner > 0) ++fewer;
        return all;
    };
    visit(0, 1);
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }));
    EXPECT_EQ(std::count(parents.begin() + 1, parents.end(), 1), std::ptrdiff_t(wide.size()) - 1);
    EXPECT_LE(maxStack, gpu::kBvhWideStackSize);
    std::sort(binaryLeaves.begin(), binaryLeaves.end());
    std::sort(wideLeaves.begin(), wideLeaves.end());
    EXPECT_EQ(wideLeaves, binaryLeaves);
    return fewer;
}

uint32_t checkWideTree(const std::vector<Aabb>& boxes, const Bvh& bvh, const std::vector<gpu::BvhNode>& wide,
                       const std::vector<uint32_t>& order) {
    return checkWideTree(boxes, binaryLeafSets(bvh), wide, order);
}

std::vector<Aabb> randomBoxes(size_t n, float range, float minSize, float maxSize, glm::vec3 offset = glm::vec3(0)) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-range, range), size(minSize, maxSize);
    std::vector<Aabb> boxes(n);
    for (Aabb& b : boxes) {
        glm::vec3 p = offset + glm::vec3(u(rng), u(rng), u(rng));
        b.min = p;
        b.max = p + glm::vec3(size(rng), size(rng), size(rng));
    }
    return boxes;
}

// Random boxes: eight children a node wherever an inner child could still
// be opened (the stack bound is far off on a tree this shallow).
TEST(Bvh, WideCollapseKeepsLeavesAndBounds) {
    for (size_t n : {1u, 2u, 3u, 7u, 9u, 50000u}) {
        std::vector<Aabb> boxes = randomBoxes(n, 100.0f, 0.01f, 3.0f);
        Bvh bvh = buildBvh(boxes, 2);
        std::vector<uint32_t> order = bvh.primitiveOrder;
        std::vector<gpu::BvhNode> wide = collapseToWide(bvh.nodes, order);
        EXPECT_EQ(checkWideTree(boxes, bvh, wide, order), 0u) << n << " boxes";
    }
}

// Degenerate inputs: equal boxes (SAH cannot split them: split at the
// middle into leaves of at most kBvhMaxLeafSize), flat boxes, points, boxes
// far from the origin, huge and tiny coordinates, and a chain of boxes
// growing geometrically, whose SAH tree is as deep as the builder allows.
TEST(Bvh, WideCollapseOfDegenerateInputs) {
    std::vector<std::vector<Aabb>> cases;
    cases.push_back(std::vector<Aabb>(1000, randomBoxes(1, 1.0f, 0.5f, 1.0f)[0]));
    std::vector<Aabb> flat = randomBoxes(3000, 10.0f, 0.0f, 1.0f);
    for (Aabb& b : flat) b.max.y = b.min.y = 2.5f;
    cases.push_back(flat);
    std::vector<Aabb> points = randomBoxes(3000, 10.0f, 0.0f, 0.0f);
    for (Aabb& b : points) b.max = b.min;
    cases.push_back(points);
    cases.push_back(randomBoxes(3000, 1.0f, 1e-6f, 1e-3f, glm::vec3(1e7f, -3e6f, 5e5f)));
    cases.push_back(randomBoxes(3000, 1e29f, 1e26f, 1e28f));
    cases.push_back(randomBoxes(3000, 1e-30f, 0.0f, 1e-33f));
    cases.push_back(randomBoxes(3000, 1e-36f, 0.0f, 1e-38f));  // subnormal extents
    std::vector<Aabb> chain(3000);
    for (size_t i = 0; i < chain.size(); ++i) {
        chain[i].min = glm::vec3(std::ldexp(1.0f, int(i % 90) - 30), 0.0f, float(i / 90));
        chain[i].max = chain[i].min + glm::vec3(std::ldexp(1.0f, int(i % 90) - 31));
    }
    cases.push_back(chain);
    for (size_t c = 0; c < cases.size(); ++c) {
        Bvh bvh = buildBvh(cases[c], 2);
        EXPECT_LT(bvh.stats.maxDepth, gpu::kBvhStackSize);
        std::vector<uint32_t> order = bvh.primitiveOrder;
        std::vector<gpu::BvhNode> wide = collapseToWide(bvh.nodes, order);
        checkWideTree(cases[c], bvh, wide, order);
        EXPECT_FALSE(testing::Test::HasFailure()) << "case " << c;
        if (testing::Test::HasFailure()) break;
    }
}

// A walk may stack at most gpu::kBvhWideStackSize entries even where the
// greedy collapse would stack more: a binary tree as deep as the builder
// allows (a spine of kBvhStackSize - 1 levels), each spine node's other
// child a block of eight leaves larger than the rest of the spine, so that
// the collapse opens the block first and a wide node descends one spine
// level while pushing seven entries. The collapse gives up children there.
Bvh spineTree(std::vector<Aabb>& boxes) {
    Bvh bvh;
    auto leaf = [&](uint32_t index, const Aabb& b) {
        bvh.nodes[index] = {b.min, uint32_t(boxes.size()), b.max, 1u};
        boxes.push_back(b);
        return b;
    };
    auto inner = [&](uint32_t index, uint32_t first, const Aabb& b) {
        bvh.nodes[index] = {b.min, first, b.max, 0u};
        return b;
    };
    std::function<Aabb(uint32_t, glm::vec3, glm::vec3, int)> block = [&](uint32_t index, glm::vec3 lo, glm::vec3 size,
                                                                          int height) -> Aabb {
        if (height == 0) return leaf(index, Aabb{lo, lo + size});
        uint32_t first = uint32_t(bvh.nodes.size());
        bvh.nodes.resize(first + 2);
        int axis = 3 - height;
        glm::vec3 half = size;
        half[axis] *= 0.5f;
        glm::vec3 second = lo;
        second[axis] += half[axis];
        Aabb b = block(first, lo, half, height - 1);
        b.extend(block(first + 1, second, half, height - 1));
        return inner(index, first, b);
    };
    const int kSpine = int(gpu::kBvhStackSize) - 1;
    std::function<Aabb(uint32_t, int)> spine = [&](uint32_t index, int d) -> Aabb {
        float side = std::ldexp(1.0f, -2 * d);
        glm::vec3 corner(10.0f * side, 0.0f, 0.0f);
        if (d == kSpine) return leaf(index, Aabb{corner, corner + glm::vec3(side)});
        uint32_t first = uint32_t(bvh.nodes.size());
        bvh.nodes.resize(first + 2);
        Aabb b = spine(first, d + 1);
        b.extend(block(first + 1, corner, glm::vec3(2.0f * side), 3));
        return inner(index, first, b);
    };
    bvh.nodes.resize(1);
    spine(0, 0);
    bvh.primitiveOrder.resize(boxes.size());
    for (uint32_t i = 0; i < boxes.size(); ++i) bvh.primitiveOrder[i] = i;
    bvh.stats.nodeCount = uint32_t(bvh.nodes.size());
    bvh.stats.maxDepth = uint32_t(kSpine);
    bvh.stats.leafCount = uint32_t(boxes.size());  // one box a leaf
    return bvh;
}

TEST(Bvh, WideCollapseKeepsTheStackBound) {
    std::vector<Aabb> boxes;
    Bvh bvh = spineTree(boxes);
    std::vector<uint32_t> order = bvh.primitiveOrder;
    std::vector<gpu::BvhNode> wide = collapseToWide(bvh.nodes, order);
    EXPECT_GT(checkWideTree(boxes, bvh, wide, order), 0u);  // the bound took children away
}

// Parts joined under a top level (joinWide, the BVH parts of a renderer's
// scene edits) make one tree with every invariant of a whole one: each
// part's leaves kept, boxes containing, the walk's stack within
// gpu::kBvhWideStackSize. Cases: a few overlapping parts of random boxes,
// a part of one box, a part of equal boxes; 3,000 small parts (a deep top
// level); the spine tree as deep as the builder allows, as a part among
// 200 others, where walks arrive at its root with the most entries.
TEST(Bvh, JoinedPartsKeepEveryInvariant) {
    auto join = [](std::vector<std::vector<Aabb>> partBoxes, std::vector<WideBvh> parts, const char* what) {
        std::vector<Aabb> all;
        LeafSets leaves;
        std::vector<const WideBvh*> pointers;
        std::vector<uint32_t> first;
        for (size_t p = 0; p < parts.size(); ++p) {
            first.push_back(uint32_t(all.size()));
            pointers.push_back(&parts[p]);
            // A part's leaves: the primitive sets of its wide tree's leaf children.
            for (const gpu::BvhNode& node : parts[p].nodes) {
                uint32_t leafEnd = 0;
                for (uint32_t k = 0; k < gpu::kBvhWidth; ++k) {
                    uint32_t info = ((k < 4 ? node.childInfo0 : node.childInfo1) >> (8 * (k & 3))) & 0xffu;
                    if (info == 0 || (info & gpu::kBvhChildInner)) continue;
                    std::vector<uint32_t> set;
                    for (uint32_t i = 0; i < info; ++i)
                        set.push_back(first.back() + parts[p].order[node.primitiveBase + leafEnd + i]);
                    leafEnd += info;
                    std::sort(set.begin(), set.end());
                    leaves.push_back(std::move(set));
                }
            }
            all.insert(all.end(), partBoxes[p].begin(), partBoxes[p].end());
        }
        std::vector<uint32_t> order;
        BvhStats stats;
        std::vector<gpu::BvhNode> wide = joinWide(pointers, first, order, stats);
        // A part of one leaf is a node for it (a whole tree's root would be).
        size_t singleLeafParts = std::count_if(parts.begin(), parts.end(), [](const WideBvh& w) {
            return w.nodes.size() == 1 && w.nodes[0].childInfo1 == 0 && (w.nodes[0].childInfo0 & 0xffffff00u) == 0;
        });
        checkWideTree(all, leaves, wide, order, singleLeafParts);
        EXPECT_EQ(stats.wideNodeCount, wide.size()) << what;
        EXPECT_EQ(stats.leafCount, leaves.size()) << what;
        EXPECT_FALSE(testing::Test::HasFailure()) << what;
    };
    auto build = [](const std::vector<std::vector<Aabb>>& partBoxes) {
        std::vector<WideBvh> parts;
        for (const auto& boxes : partBoxes) parts.push_back(buildWideBvh(boxes, 2));
        return parts;
    };

    std::vector<std::vector<Aabb>> few = {randomBoxes(20000, 100.0f, 0.01f, 3.0f),
                                          randomBoxes(5000, 10.0f, 0.01f, 1.0f, glm::vec3(150.0f, 0.0f, 0.0f)),
                                          randomBoxes(3000, 200.0f, 0.01f, 5.0f), randomBoxes(1, 1.0f, 0.5f, 1.0f),
                                          std::vector<Aabb>(100, randomBoxes(1, 1.0f, 0.5f, 1.0f)[0])};
    join(few, build(few), "a few parts");
    join({few[0]}, build({few[0]}), "one part");

    std::vector<std::vector<Aabb>> many;
    for (int p = 0; p < 3000; ++p)
        many.push_back(randomBoxes(1 + p % 17, 1.0f, 0.01f, 0.3f, glm::vec3(float(p % 40), float(p / 40), 0.0f)));
    join(many, build(many), "3,000 parts");

    std::vector<Aabb> spineBoxes;
    Bvh spine = spineTree(spineBoxes);
    WideBvh spinePart;
    spinePart.order = spine.primitiveOrder;
    spinePart.nodes = collapseToWide(spine.nodes, spinePart.order, kJoinedRootStack);
    for (const Aabb& b : spineBoxes) spinePart.bounds.extend(b);
    spinePart.stats = spine.stats;
    std::vector<std::vector<Aabb>> around(many.begin(), many.begin() + 200);
    std::vector<WideBvh> parts = build(around);
    around.push_back(spineBoxes);
    parts.push_back(std::move(spinePart));
    join(around, std::move(parts), "the deepest part among 200");
}

// The quantised child boxes contain the children's boxes: random sets of
// one to eight boxes at many scales and offsets, flat and point boxes.
TEST(Bvh, QuantisedBoxesContainTheirChildren) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-120, 95), count(1, 8), kind(0, 3);
    for (int trial = 0; trial < 20000; ++trial) {
        float scale = std::ldexp(1.0f, exponent(rng));
        glm::vec3 offset = glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f) *
                           std::ldexp(1.0f, exponent(rng));
        std::vector<Aabb> children(size_t(count(rng)));
        for (Aabb& c : children) {
            c.min = offset + scale * glm::vec3(unit(rng), unit(rng), unit(rng));
            c.max = c.min + scale * glm::vec3(unit(rng), unit(rng), unit(rng));
            int k = kind(rng);
            if (k == 1) c.max.x = c.min.x;  // flat
            if (k == 2) c.max = c.min;      // a point
        }
        gpu::BvhNode node;
        quantiseChildren(children, node);
        for (uint32_t k = 0; k < children.size(); ++k) {
            Aabb decoded = decodeChildBox(node, k);
            ASSERT_TRUE(contains(decoded, children[k]))
                << "trial " << trial << " child " << k << ": (" << children[k].min.x << " " << children[k].max.x
                << ") in (" << decoded.min.x << " " << decoded.max.x << ")";
        }
    }
}

// Every scene renders the same with the BVH as with brute force, pixel for
// pixel. (Only coincident surfaces, hit at exactly the same distance, could
// legitimately differ, since the order of tests decides the tie; the scenes
// keep objects 1 mm apart for that reason: a cylinder standing exactly on
// the floor made its bottom cap and the floor tie.)
class BvhMatchesBruteForce : public ::testing::TestWithParam<std::string> {};

TEST_P(BvhMatchesBruteForce, SameImage) {
    Scene scene = loadScene(sourceDir() / "scenes" / (GetParam() + ".xml"));
    RenderSettings s{.width = 96, .height = 72, .samplesPerPixel = 1, .maxDepth = 6, .auxiliary = false};
    RenderResult bvh = renderScene(scene, s);
    s.useBvh = false;
    RenderResult brute = renderScene(scene, s);
    EXPECT_GT(bvh.bvh.nodeCount, 0u);
    // The record's wide nodes are the tree the shader walks: W <= max(L - 1, 1).
    EXPECT_GT(bvh.bvh.wideNodeCount, 0u);
    EXPECT_LE(bvh.bvh.wideNodeCount, std::max(bvh.bvh.leafCount, 2u) - 1u);
    EXPECT_LT(bvh.bvh.wideNodeCount, bvh.bvh.nodeCount);
    int differing = 0;
    for (int y = 0; y < bvh.height; ++y)
        for (int x = 0; x < bvh.width; ++x) {
            glm::vec4 a = pixel(bvh, gpu::kAovColor, x, y), b = pixel(brute, gpu::kAovColor, x, y);
            if (glm::any(glm::greaterThan(glm::abs(a - b), glm::vec4(1e-5f)))) ++differing;
        }
    EXPECT_EQ(differing, 0) << "pixels that differ between BVH and brute force";
    EXPECT_EQ(bvh.rays.primary, brute.rays.primary);
}

INSTANTIATE_TEST_SUITE_P(Scenes, BvhMatchesBruteForce,
                         ::testing::Values("room", "nested_spheres", "one_mirror", "several_mirrors", "n_objects",
                                           "n_diffuse_objects", "three_diffuse_spheres"),
                         [](const auto& info) { return info.param; });

// The shader reads BVH nodes and primitives through their device addresses
// or, on drivers that load a storage buffer faster (lavapipe before Mesa 25),
// through storage buffers of the same arrays (RenderSettings::sceneReads forces
// either): both give the same image, value for value, and the same ray counts.
class SceneReads : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneReads, DescriptorMatchesAddress) {
    Scene scene = loadScene(sourceDir() / "scenes" / (GetParam() + ".xml"));
    RenderSettings s{.width = 96, .height = 72, .samplesPerPixel = 1, .maxDepth = 6, .auxiliary = false};
    s.sceneReads = whitted::SceneReads::Address;
    RenderResult address = renderScene(scene, s);
    s.sceneReads = whitted::SceneReads::Descriptor;
    RenderResult descriptor = renderScene(scene, s);
    ASSERT_GT(address.bvh.nodeCount, 0u);
    int differing = 0;
    for (int y = 0; y < address.height; ++y)
        for (int x = 0; x < address.width; ++x)
            if (pixel(address, gpu::kAovColor, x, y) != pixel(descriptor, gpu::kAovColor, x, y)) ++differing;
    EXPECT_EQ(differing, 0) << "pixels that differ between reads through the addresses and the descriptors";
    EXPECT_EQ(address.rays.primary, descriptor.rays.primary);
    EXPECT_EQ(address.rays.shadow, descriptor.rays.shadow);
    EXPECT_EQ(address.rays.secondary, descriptor.rays.secondary);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneReads, ::testing::Values("room", "several_mirrors", "n_objects"),
                         [](const auto& info) { return info.param; });

// The tracer built for the scene (without the code of csg objects and
// textures where the scene has none, RenderSettings::fittedShader) renders
// every shipped scene as the full build does: every output layer, value for
// value, and the same ray counts, at 1 sample and with adaptive sampling.
class FittedShader : public ::testing::TestWithParam<std::string> {};

TEST_P(FittedShader, MatchesFullShader) {
    Scene scene = loadScene(sourceDir() / "scenes" / (GetParam() + ".xml"));
    for (AntiAliasing aa : {AntiAliasing::Uniform, AntiAliasing::Adaptive}) {
        RenderSettings s{.width = 96, .height = 72, .samplesPerPixel = aa == AntiAliasing::Uniform ? 1 : 16,
                         .maxDepth = 6, .auxiliary = true};
        s.antiAliasing = aa;
        s.fittedShader = true;
        RenderResult fitted = renderScene(scene, s);
        s.fittedShader = false;
        RenderResult full = renderScene(scene, s);
        ASSERT_EQ(fitted.layers.size(), full.layers.size());
        ASSERT_FALSE(full.layers.empty());
        for (size_t layer = 0; layer < full.layers.size(); ++layer)
            EXPECT_TRUE(fitted.layers[layer].size() == full.layers[layer].size() &&
                        std::memcmp(fitted.layers[layer].data(), full.layers[layer].data(),
                                    full.layers[layer].size() * sizeof(float)) == 0)
                << "layer " << layer << " differs (bit for bit)";
        EXPECT_EQ(fitted.rays.primary, full.rays.primary);
        EXPECT_EQ(fitted.rays.shadow, full.rays.shadow);
        EXPECT_EQ(fitted.rays.secondary, full.rays.secondary);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, FittedShader,
                         ::testing::Values("room", "nested_spheres", "one_mirror", "several_mirrors", "n_objects",
                                           "n_diffuse_objects", "three_diffuse_spheres", "showcase"),
                         [](const auto& info) { return info.param; });

// A UV sphere of rings x segments x 2 triangles, smooth-shaded.
Mesh tessellatedSphere(glm::dvec3 center, double radius, int rings, int segments) {
    Mesh mesh;
    auto at = [&](int r, int s) {
        double theta = std::numbers::pi * r / rings, phi = 2.0 * std::numbers::pi * s / segments;
        return glm::dvec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            glm::dvec3 n[4] = {at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)};
            for (auto [a, b, c] : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
                mesh.triangles.push_back({center + radius * n[a], center + radius * n[b], center + radius * n[c]});
                mesh.normals.push_back({n[a], n[b], n[c]});
            }
        }
    return mesh;
}

// A renderer's scene edits (Renderer::setScene) give meshes of
// kBvhPartMinTriangles or more BVH parts of their own and keep them: moving
// a sphere rebuilds the sphere's tree and the top level only, moving a mesh
// its own part too, and every image (colour, normals, object ids) is the one
// a fresh renderer makes of the edited scene with its one tree over everything.
TEST(BvhParts, EditsRebuildOnlyWhatChangedAndRenderAsAFreshRenderer) {
    Scene scene;
    scene.camera.eye = {0, 1.5, 6};
    scene.camera.windowCenter = {0, 1.2, 5};
    scene.ambientLight = {0.2, 0.2, 0.2};
    scene.lights.push_back({.position = {3, 6, 4}});
    Material matte;
    matte.ambient = 0.2;
    scene.objects.push_back({.shape = Plane{{0, -1, 0}, {0, 1, 0}}, .material = matte});
    scene.objects.push_back({.shape = tessellatedSphere({-1.2, 0, 0}, 1.0, 48, 64), .material = matte});  // 6,144
    scene.objects.push_back({.shape = tessellatedSphere({1.2, 0, -1}, 0.9, 40, 56), .material = matte});   // 4,480
    scene.objects.push_back({.shape = Sphere{{0, 1.8, 0.5}, 0.4}, .material = matte});
    RenderSettings settings{.width = 96, .height = 72, .samplesPerPixel = 1, .maxDepth = 2, .auxiliary = true};
    settings.ids = true;
    Renderer renderer(testContext(), scene, settings);
    renderer.render();

    auto expectFreshImage = [&](const RenderResult& got, const char* edit) {
        RenderResult fresh = renderScene(scene, settings);
        ASSERT_EQ(got.layers.size(), fresh.layers.size());
        for (size_t layer = 0; layer < fresh.layers.size(); ++layer)
            // Bit for bit (the id layer holds integers' bits, NaNs among them).
            EXPECT_TRUE(got.layers[layer].size() == fresh.layers[layer].size() &&
                        std::memcmp(got.layers[layer].data(), fresh.layers[layer].data(),
                                    fresh.layers[layer].size() * sizeof(float)) == 0)
                << edit << ": layer " << layer << " differs";
        EXPECT_EQ(got.rays.primary, fresh.rays.primary) << edit;
        // Every object in view: the floor, both meshes and the ball have pixels.
        std::set<uint32_t> seen;
        const std::vector<float>& idLayer = got.layers[got.layout.idLayer()];
        for (size_t i = 0; i < idLayer.size(); i += 4) seen.insert(std::bit_cast<uint32_t>(idLayer[i]));
        for (uint32_t object : {0u, 1u, 2u, 3u}) EXPECT_TRUE(seen.count(object)) << edit << ": object " << object;
    };
    struct Expected {
        const char* edit;
        uint32_t reused;
        uint64_t built;
    };
    auto& ball = std::get<Sphere>(scene.objects[3].shape);
    for (Expected e : {Expected{"the ball moved (the parts built)", 0, 6144 + 4480 + 1},
                       Expected{"the ball moved again", 2, 1}}) {
        ball.center.x += 0.3;
        renderer.setScene(scene);
        RenderResult got = renderer.render();
        EXPECT_EQ(got.bvh.parts, 2u) << e.edit;
        EXPECT_EQ(got.bvh.partsReused, e.reused) << e.edit;
        EXPECT_EQ(got.bvh.primitivesBuilt, e.built) << e.edit;
        expectFreshImage(got, e.edit);
    }
    for (Triangle& t : std::get<Mesh>(scene.objects[2].shape).triangles)
        for (glm::dvec3* v : {&t.v0, &t.v1, &t.v2}) v->y += 0.25;
    renderer.setScene(scene);
    RenderResult got = renderer.render();
    EXPECT_EQ(got.bvh.partsReused, 1u);
    EXPECT_EQ(got.bvh.primitivesBuilt, 4480u + 1u);
    expectFreshImage(got, "a mesh moved");
    // Its material changed, not its shape: every part reused.
    scene.objects[1].material.diffuseColor = {0.9, 0.2, 0.1};
    renderer.setScene(scene);
    got = renderer.render();
    EXPECT_EQ(got.bvh.partsReused, 2u);
    expectFreshImage(got, "a material changed");
    EXPECT_EQ(testContext().validationMessageCount(), 0u);
}

}  // namespace
}  // namespace whitted::test

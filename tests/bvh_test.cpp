// The BVH: structure invariants of the builder, and the same images as the
// brute-force loop over every primitive.
#include "accel/bvh.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <functional>
#include <random>

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
// nodes than max(leaves - 1, 1) (countSceneArrays' bound) and the walk's
// stack within gpu::kBvhWideStackSize. Returns how many nodes have fewer than
// eight children while one of them is an inner node.
uint32_t checkWideTree(const std::vector<Aabb>& boxes, const Bvh& bvh, const std::vector<gpu::BvhNode>& wide,
                       const std::vector<uint32_t>& order) {
    size_t n = boxes.size();
    EXPECT_EQ(order.size(), n);
    LeafSets binaryLeaves, wideLeaves;
    for (const BinaryBvhNode& node : bvh.nodes)
        if (node.primitiveCount > 0) {
            std::vector<uint32_t> set(bvh.primitiveOrder.begin() + node.first,
                                      bvh.primitiveOrder.begin() + node.first + node.primitiveCount);
            std::sort(set.begin(), set.end());
            binaryLeaves.push_back(std::move(set));
        }
    EXPECT_FALSE(wide.empty());
    EXPECT_LE(wide.size(), std::max<size_t>(binaryLeaves.size(), 2) - 1);

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
        EXPECT_TRUE(children >= 2 || (index == 0 && children == 1 && inner == 0)) << "node " << index;
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
TEST(Bvh, WideCollapseKeepsTheStackBound) {
    Bvh bvh;
    std::vector<Aabb> boxes;
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
    std::vector<uint32_t> order = bvh.primitiveOrder;
    std::vector<gpu::BvhNode> wide = collapseToWide(bvh.nodes, order);
    EXPECT_GT(checkWideTree(boxes, bvh, wide, order), 0u);  // the bound took children away
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

}  // namespace
}  // namespace whitted::test

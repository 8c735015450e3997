// The BVH: structure invariants of the builder, and the same images as the
// brute-force loop over every primitive.
#include "accel/bvh.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <algorithm>
#include <bit>
#include <cstring>
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

    auto contains = [](const gpu::BvhNode& n, const Aabb& b) {
        return glm::all(glm::lessThanEqual(glm::vec3(n.lo), b.min)) && glm::all(glm::greaterThanEqual(glm::vec3(n.hi), b.max));
    };
    size_t leafPrimitives = 0;
    for (const gpu::BvhNode& n : bvh.nodes) {
        uint32_t first = n.first, count = n.primitiveCount;
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

// The 4-wide tree the shader walks: the binary tree's leaves unchanged
// (same primitive ranges, every primitive once), every child's box inside
// its node's, two to four children a node and four wherever a child could
// still be opened, no more slots than the binary tree (countSceneArrays'
// bound) and the walk's stack within gpu::kBvhWideStackSize.
TEST(Bvh, WideCollapseKeepsLeavesAndBounds) {
    for (size_t n : {1u, 2u, 3u, 7u, 50000u}) {
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-100.0f, 100.0f), size(0.01f, 3.0f);
        std::vector<Aabb> boxes(n);
        for (Aabb& b : boxes) {
            glm::vec3 p(u(rng), u(rng), u(rng));
            b.min = p;
            b.max = p + glm::vec3(size(rng), size(rng), size(rng));
        }
        Bvh bvh = buildBvh(boxes, 2);
        std::vector<gpu::BvhNode> wide = collapseToWide(bvh.nodes);
        ASSERT_FALSE(wide.empty());
        EXPECT_LE(wide.size(), bvh.nodes.size());
        EXPECT_LE(wide.size(), 2 * n - 1);

        auto leafRanges = [](const std::vector<gpu::BvhNode>& nodes) {
            std::vector<std::pair<uint32_t, uint32_t>> ranges;
            for (const gpu::BvhNode& node : nodes)
                if (uint32_t count = node.primitiveCount; count > 0)
                    ranges.emplace_back(node.first, count);
            std::sort(ranges.begin(), ranges.end());
            return ranges;
        };
        EXPECT_EQ(leafRanges(wide), leafRanges(bvh.nodes));

        auto contains = [](const gpu::BvhNode& outer, const gpu::BvhNode& inner) {
            return glm::all(glm::lessThanEqual(glm::vec3(outer.lo), glm::vec3(inner.lo))) &&
                   glm::all(glm::greaterThanEqual(glm::vec3(outer.hi), glm::vec3(inner.hi)));
        };
        size_t reached = 1;
        uint32_t maxStack = 0;
        // Depth first, with the entries a walk could have stacked on the way:
        // every hit child but the one it goes on with.
        std::vector<std::pair<uint32_t, uint32_t>> todo = {{0u, 1u}};
        while (!todo.empty()) {
            auto [slot, stacked] = todo.back();
            todo.pop_back();
            maxStack = std::max(maxStack, stacked);
            const gpu::BvhNode& node = wide[slot];
            if (node.primitiveCount != 0u) continue;  // a leaf
            uint32_t word = node.first;
            uint32_t first = word & gpu::kBvhChildIndexMask, children = (word >> gpu::kBvhChildCountShift) + 2;
            ASSERT_LE(children, 4u);
            ASSERT_LE(first + children, wide.size());
            reached += children;
            bool leavesOnly = true;
            for (uint32_t k = 0; k < children; ++k) {
                const gpu::BvhNode& child = wide[first + k];
                ASSERT_TRUE(contains(node, child));
                leavesOnly = leavesOnly && child.primitiveCount != 0u;
            }
            EXPECT_TRUE(children == 4 || leavesOnly);
            // This entry popped, all children but the one walked pushed.
            for (uint32_t k = 0; k < children; ++k) todo.emplace_back(first + k, stacked - 1 + children);
        }
        EXPECT_EQ(reached, wide.size());  // every slot is a child of exactly one node (or the root)
        EXPECT_LE(maxStack, gpu::kBvhWideStackSize);
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

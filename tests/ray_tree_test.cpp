// The ray-tree inspector (render/ray_tree.h, `whitted trace`): the tree is
// the renderer's (its contributions add up to the rendered pixel), its
// reflections, refractions and shadow rays are the ones a hand computation
// gives, and it is a tree.
#include "exact_triangle.h"
#include "io/image_io.h"
#include "render/gpu_scene.h"
#include "render/ray_tree.h"
#include "scene/scene_loader.h"
#include "test_support.h"
#include "view/ray_tree_overlay.h"

#include <glm/gtc/epsilon.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <set>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

RenderSettings traceSettings(int width, int height, int maxDepth = 6) {
    return {.width = width, .height = height, .samplesPerPixel = 1, .maxDepth = maxDepth, .auxiliary = false,
            .antiAliasing = AntiAliasing::Uniform, .bandBytes = 0};
}

RayTree traceXml(const std::string& xml, int width, int height, int x, int y, int maxDepth = 6) {
    Scene scene = loadSceneFromString(xml, "test.xml");
    Renderer renderer(testContext(), scene, traceSettings(width, height, maxDepth));
    RayTreeRecorder recorder(testContext());
    return recorder.trace(renderer, x, y);
}

// Rays form a tree: the camera ray first, each other ray after its parent,
// one deeper, never past maxDepth; at most one reflection-like and one
// refraction child a ray; each ray's shadow rays point back at it.
void expectTree(const RayTree& tree, int maxDepth) {
    ASSERT_FALSE(tree.rays.empty());
    EXPECT_EQ(tree.dropped, 0u);
    EXPECT_EQ(tree.rays[0].kind, gpu::kRayCamera);
    EXPECT_EQ(tree.rays[0].parent, gpu::kNoObject);
    EXPECT_EQ(tree.rays[0].depth, 0u);
    for (uint32_t i = 1; i < tree.rays.size(); ++i) {
        const gpu::RayTreeRay& r = tree.rays[i];
        ASSERT_LT(r.parent, i) << "ray " << i;
        EXPECT_NE(r.kind, gpu::kRayCamera) << "ray " << i;
        EXPECT_EQ(r.depth, tree.rays[r.parent].depth + 1) << "ray " << i;
        EXPECT_NE(tree.rays[r.parent].primitive, gpu::kNoObject) << "a ray that missed has no children";
    }
    for (uint32_t i = 0; i < tree.rays.size(); ++i) {
        EXPECT_LE(tree.rays[i].depth, uint32_t(maxDepth));
        int reflections = 0, refractions = 0;
        for (uint32_t c : tree.children(i)) (tree.rays[c].kind == gpu::kRayRefraction ? refractions : reflections)++;
        EXPECT_LE(reflections, 1);
        EXPECT_LE(refractions, 1);
        const gpu::RayTreeRay& r = tree.rays[i];
        for (uint32_t s = r.firstShadowRay; s < r.firstShadowRay + r.shadowRayCount; ++s) {
            ASSERT_LT(s, tree.shadowRays.size());
            EXPECT_EQ(tree.shadowRays[s].ray, i);
        }
    }
}

// The recorder's crossing-by-crossing transmittance is the renderer's
// shadow query (traceQuery), and each ray's contribution is its weight times its
// local terms, the per-light shares adding up to them.
void expectShadowsAgree(const RayTree& tree) {
    for (const gpu::RayTreeShadowRay& s : tree.shadowRays)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.transmittance[c], s.visibility[c], 1e-5f * std::max(1.0f, s.visibility[c]));
    for (const gpu::RayTreeRay& r : tree.rays) {
        glm::vec3 diffuse(0.0f), specular(0.0f);
        for (uint32_t s = r.firstShadowRay; s < r.firstShadowRay + r.shadowRayCount; ++s) {
            diffuse += tree.shadowRays[s].diffuse;
            specular += tree.shadowRays[s].specular;
        }
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(diffuse[c], r.diffuse[c], 1e-5f * std::max(1e-3f, r.diffuse[c]));
            EXPECT_NEAR(specular[c], r.specular[c], 1e-5f * std::max(1e-3f, r.specular[c]));
            EXPECT_NEAR(r.contribution[c], r.weight[c] * (r.ambient[c] + r.diffuse[c] + r.specular[c] + r.emission[c]),
                        1e-6f * std::max(1.0f, r.contribution[c]));
        }
    }
}

// Each shipped scene at 80x60, 20 pixels from a fixed seed: the sum of the
// contributions is the pixel of `whitted render --aa uniform --spp 1` (a
// float EXR) within 1e-5 relative. This is what makes the tree the
// renderer's.
class ShippedScene : public testing::TestWithParam<std::string> {};

TEST_P(ShippedScene, RayTreeContributionsAddUpToTheRenderedPixel) {
    constexpr int kWidth = 80, kHeight = 60;
    fs::path path = sourceDir() / "scenes" / GetParam();
    std::mt19937 random(18);
    fs::path dir = freshOutputDir("ray_tree", "sums_" + path.stem().string());
    fs::path exr = dir / "render.exr";
    CommandRun run = runCommand("'" WHITTED_EXECUTABLE "' render '" + path.string() +
                                    "' --aa uniform --spp 1 --width 80 --height 60 --aov none -q -o '" + exr.string() +
                                    "'",
                                dir);
    ASSERT_EQ(run.status, 0) << run.output;
    int w = 0, h = 0, channels = 0;
    std::vector<float> storage;
    std::span<const float> image = readImageInto(exr, w, h, channels, storage);
    ASSERT_EQ(w, kWidth);
    ASSERT_EQ(h, kHeight);
    Scene scene = loadScene(path);
    Renderer renderer(testContext(), scene, traceSettings(kWidth, kHeight));
    RayTreeRecorder recorder(testContext());
    std::uniform_int_distribution<int> px(0, kWidth - 1), py(0, kHeight - 1);
    int lit = 0;
    for (int k = 0; k < 20; ++k) {
        int x = px(random), y = py(random);
        RayTree tree = recorder.trace(renderer, x, y);
        SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y));
        expectTree(tree, 6);
        expectShadowsAgree(tree);
        glm::vec3 sum = tree.color();
        for (int c = 0; c < 3; ++c) {
            float want = image[(size_t(y) * w + x) * channels + c];
            EXPECT_NEAR(sum[c], want, 1e-5f * std::abs(want) + 1e-9f);
        }
        lit += sum.r + sum.g + sum.b > 0.0f ? 1 : 0;
    }
    EXPECT_GT(lit, 0) << "every pixel drawn was black: the comparison proves little";
}

// Every scene file shipped in scenes/ (a test below checks the list is whole).
const std::vector<std::string> kShippedScenes = {"environment.xml", "n_diffuse_objects.xml", "n_objects.xml",
                                                 "nested_spheres.xml", "one_mirror.xml", "room.xml",
                                                 "several_mirrors.xml", "showcase.xml", "soft.xml",
                                                 "three_diffuse_spheres.xml"};
INSTANTIATE_TEST_SUITE_P(RayTree, ShippedScene, testing::ValuesIn(kShippedScenes),
                         [](const testing::TestParamInfo<std::string>& info) {
                             return fs::path(info.param).stem().string();
                         });

// RayTree::walk, the one walk of every view of the tree (text, window):
// depth first, children in the order traced, leave after a ray's children,
// none of them for a ray whose enter said no; shadowRaysOf and crossingsOf
// stop at what the record holds.
TEST(RayTree, WalkIsDepthFirstInTracedOrder) {
    RayTree tree;
    // 0 camera; 1, 2 its children; 3 a child of 1; 4 a child of 2 (not
    // entered); 5 a child of 3.
    const uint32_t parents[] = {gpu::kNoObject, 0, 0, 1, 2, 3};
    for (uint32_t p : parents) {
        gpu::RayTreeRay r{};
        r.parent = p;
        tree.rays.push_back(r);
    }
    std::string order;
    tree.walk(
        [&](uint32_t i, int level) {
            order.append("+").append(std::to_string(i)).append("@").append(std::to_string(level));
            return i != 2;
        },
        [&](uint32_t i) { order.append("-").append(std::to_string(i)); });
    EXPECT_EQ(order, "+0@0+1@1+3@2+5@3-5-3-1+2@1-0");

    tree.rays[1].firstShadowRay = 1;
    tree.rays[1].shadowRayCount = 5;  // the record holds 3 shadow rays
    tree.shadowRays.resize(3);
    tree.shadowRays[2].firstCrossing = 1;
    tree.shadowRays[2].crossingCount = 4;  // and 2 crossings
    tree.crossings.resize(2);
    EXPECT_EQ(tree.shadowRaysOf(1).size(), 2u);
    EXPECT_EQ(tree.shadowRaysOf(0).size(), 0u);
    EXPECT_EQ(tree.crossingsOf(tree.shadowRays[2]).size(), 1u);
    EXPECT_EQ(&tree.crossingsOf(tree.shadowRays[2])[0], &tree.crossings[1]);
}

TEST(RayTree, EveryShippedSceneIsTraced) {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(sourceDir() / "scenes"))
        if (entry.path().extension() == ".xml") found.push_back(entry.path().filename().string());
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, kShippedScenes);
}

// A mirror turned 45 degrees about y at the origin, the camera on +z looking
// down -z: the centre pixel's ray (0, 0, -1) reflects about n = (1, 0, 1)/√2
// into d - 2 (d.n) n = (1, 0, 0), and so hits the red sphere at (6, 0, 0),
// radius 1, at (5, 0, 0), t = 5 from the mirror; the blue one at (-6, 0, 0)
// is where a reflection going the wrong way would land.
TEST(RayTree, MirrorPixelReflectsToTheObjectAHandComputationGives) {
    std::string xml = R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
      <width>41</width><height>31</height></camera>
      <lights><light><position x="0" y="5" z="5"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="1" y="0" z="1"/>
        <diffuse_coef>0</diffuse_coef><reflective>true</reflective><reflection_coef>1</reflection_coef></properties></object>
      <object><position x="6" y="0" z="0"/><diffuse_color r="1" g="0" b="0"/>
        <properties><type>sphere</type><radius>1</radius><ambiente_coef>0.2</ambiente_coef></properties></object>
      <object><position x="-6" y="0" z="0"/><diffuse_color r="0" g="0" b="1"/>
        <properties><type>sphere</type><radius>1</radius><ambiente_coef>0.2</ambiente_coef></properties></object>
      </objects></scene>)";
    RayTree tree = traceXml(xml, 41, 31, 20, 15);
    expectTree(tree, 6);
    ASSERT_GE(tree.rays.size(), 2u);
    EXPECT_EQ(tree.rays[0].material, 0u);
    EXPECT_NEAR(tree.rays[0].t, 5.0f, 1e-4f);
    std::vector<uint32_t> children = tree.children(0);
    ASSERT_EQ(children.size(), 1u);
    const gpu::RayTreeRay& reflected = tree.rays[children[0]];
    EXPECT_EQ(reflected.kind, gpu::kRayReflection);
    EXPECT_TRUE(glm::all(glm::epsilonEqual(reflected.direction, glm::vec3(1, 0, 0), 1e-5f)));
    EXPECT_EQ(reflected.material, 1u) << "the red sphere";
    EXPECT_NEAR(reflected.t, 5.0f, 1e-3f);
    EXPECT_TRUE(glm::all(glm::epsilonEqual(reflected.point, glm::vec3(5, 0, 0), 1e-3f)));
    EXPECT_GT(reflected.contribution.r, 0.0f);
    EXPECT_EQ(reflected.contribution.b, 0.0f);
}

// A glass sphere (IOR 1.5) seen through its centre: the camera ray enters
// at z = 1 (t = 4), its refraction child crosses the sphere from inside
// (t = 2) and that one's refraction child leaves at z = -1.
TEST(RayTree, GlassSphereHasRefractionsEnteringAndLeaving) {
    std::string xml = R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
      <width>41</width><height>31</height></camera>
      <lights><light><position x="3" y="5" z="5"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="0" y="0" z="0"/><properties><type>sphere</type><radius>1</radius>
        <transmission_coef>0.9</transmission_coef><refraction_coef>1.5</refraction_coef>
        <diffuse_coef>0.1</diffuse_coef><specular_coef>0.1</specular_coef></properties></object>
      <object><position x="0" y="0" z="-4"/><properties><type>plane</type><normal x="0" y="0" z="1"/></properties></object>
      </objects></scene>)";
    RayTree tree = traceXml(xml, 41, 31, 20, 15);
    expectTree(tree, 6);
    EXPECT_EQ(tree.rays[0].frontFace, 1u);
    EXPECT_NEAR(tree.rays[0].t, 4.0f, 1e-4f);
    const gpu::RayTreeRay* inside = nullptr;
    for (uint32_t c : tree.children(0))
        if (tree.rays[c].kind == gpu::kRayRefraction) inside = &tree.rays[c];
    ASSERT_NE(inside, nullptr);
    EXPECT_EQ(inside->frontFace, 0u) << "entering: it hits the sphere from inside";
    EXPECT_NEAR(inside->t, 2.0f, 1e-3f);
    uint32_t insideIndex = uint32_t(inside - tree.rays.data());
    const gpu::RayTreeRay* leaving = nullptr;
    for (uint32_t c : tree.children(insideIndex))
        if (tree.rays[c].kind == gpu::kRayRefraction) leaving = &tree.rays[c];
    ASSERT_NE(leaving, nullptr);
    EXPECT_NEAR(leaving->origin.z, -1.0f, 1e-3f);
    EXPECT_EQ(leaving->material, 1u) << "it leaves for the wall";
    EXPECT_NEAR(leaving->t, 3.0f, 1e-3f);
}

// A glass cube seen from above at 45 degrees: rays entering its top face and
// meeting a side face from inside are past the critical angle there (a
// refraction angle r <= 41.8 degrees leaves 90 - r >= 48.2 on a
// perpendicular face). At every inside hit the tree has a total internal
// reflection exactly where sin(incidence) > 1 / IOR, a refraction where less
// (and no reflection: the glass has kr = 0).
TEST(RayTree, RayPastTheCriticalAngleIsTotalInternalReflection) {
    std::string xml = R"(<scene><camera><position x="0" y="3" z="3"/><window_position x="0" y="2.4" z="2.4"/>
      <width>40</width><height>30</height></camera>
      <lights><light><position x="3" y="5" z="5"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="-1" y="-1" z="-1"/><properties><type>box</type><size x="2" y="2" z="2"/>
        <transmission_coef>0.9</transmission_coef><refraction_coef>1.5</refraction_coef>
        <diffuse_coef>0.1</diffuse_coef></properties></object>
      </objects></scene>)";
    Scene scene = loadSceneFromString(xml, "test.xml");
    Renderer renderer(testContext(), scene, traceSettings(40, 30, 4));
    RayTreeRecorder recorder(testContext());
    const float critical = 1.0f / 1.5f;
    int totalInternal = 0, refracted = 0;
    for (int y = 1; y < 30; y += 3)
        for (int x = 1; x < 40; x += 3) {
            RayTree tree = recorder.trace(renderer, x, y);
            expectTree(tree, 4);
            for (uint32_t i = 0; i < tree.rays.size(); ++i) {
                const gpu::RayTreeRay& r = tree.rays[i];
                if (r.primitive == gpu::kNoObject || r.frontFace || r.depth >= 4) continue;
                float cosine = -glm::dot(r.direction, r.normal);
                float sine = std::sqrt(std::max(0.0f, 1.0f - cosine * cosine));
                std::set<uint32_t> kinds;
                for (uint32_t c : tree.children(i)) kinds.insert(tree.rays[c].kind);
                if (sine > critical + 1e-4f) {
                    EXPECT_EQ(kinds, std::set<uint32_t>{gpu::kRayTotalInternal}) << "pixel " << x << "," << y;
                    ++totalInternal;
                } else if (sine < critical - 1e-4f) {
                    // (no reflection ray: the glass has kr = 0)
                    EXPECT_EQ(kinds, std::set<uint32_t>{gpu::kRayRefraction}) << "pixel " << x << "," << y;
                    ++refracted;
                }
            }
        }
    EXPECT_GT(totalInternal, 0);
    EXPECT_GT(refracted, 0);
}

// The floor right under a glass sphere (Cd (0.2, 0.6, 1), kd 0.5, kt 0.8)
// lit from straight above: the shadow ray crosses the sphere twice, each
// time filtered by kt * mix(white, Cd, kd) = (0.48, 0.64, 0.8), as
// shaders/intersect.glsl filters it, and the light that reaches the floor is
// the product.
TEST(RayTree, ShadowRayThroughGlassReportsTheGlassAndItsFilter) {
    std::string xml = R"(<scene><camera><position x="0" y="2" z="6"/><window_position x="0" y="1.6666666" z="5"/>
      <width>41</width><height>31</height></camera>
      <lights><light><position x="0" y="4" z="0"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="0" y="1" z="0"/>
        <diffuse_coef>0.8</diffuse_coef></properties></object>
      <object><position x="0" y="1" z="0"/><diffuse_color r="0.2" g="0.6" b="1"/>
        <properties><type>sphere</type><radius>0.5</radius><transmission_coef>0.8</transmission_coef>
        <refraction_coef>1.5</refraction_coef><diffuse_coef>0.5</diffuse_coef></properties></object>
      </objects></scene>)";
    RayTree tree = traceXml(xml, 41, 31, 20, 15);
    expectTree(tree, 6);
    expectShadowsAgree(tree);
    const gpu::RayTreeRay& floor = tree.rays[0];
    ASSERT_EQ(floor.material, 0u) << "the centre pixel sees the floor at the origin";
    EXPECT_LT(glm::length(floor.point), 1e-3f);
    ASSERT_EQ(floor.shadowRayCount, 1u);
    const gpu::RayTreeShadowRay& shadow = tree.shadowRays[floor.firstShadowRay];
    EXPECT_EQ(shadow.outcome, gpu::kShadowFiltered);
    ASSERT_EQ(shadow.crossingCount, 2u);
    const glm::vec3 filter(0.48f, 0.64f, 0.8f);
    for (uint32_t c = shadow.firstCrossing; c < shadow.firstCrossing + 2; ++c) {
        EXPECT_EQ(tree.crossings[c].material, 1u) << "the glass";
        EXPECT_TRUE(glm::all(glm::epsilonEqual(tree.crossings[c].filterColour, filter, 1e-5f)));
    }
    EXPECT_TRUE(glm::all(glm::epsilonEqual(shadow.visibility, filter * filter, 1e-5f)));
    // diffuse = visibility * light * kd * Cd * N.L with N.L = 1.
    EXPECT_TRUE(glm::all(glm::epsilonEqual(floor.diffuse, filter * filter * 0.8f, 1e-5f)));
}

// A record that overflows says so instead of reading lit: a shadow ray
// through 1,100 glass spheres crosses 2,200 surfaces, more than the 2,048 the
// record holds; it is still "filtered", its crossings past the record are
// counted on it and in `dropped`, and its transmittance is the renderer's.
// A second light's shadow ray, every crossing of which finds the record full,
// is "filtered" too (it read "lit" before).
// A tree deeper than the record's 256 rays counts every ray it leaves out,
// the descendants of a left-out ray included, and its text says it is not
// fully recorded.
TEST(RayTree, AFullRecordSaysSoAndCountsWhatItLeftOut) {
    std::string xml = R"(<scene><camera><position x="0" y="2" z="6"/><window_position x="0" y="1.6666666" z="5"/>
      <width>41</width><height>31</height></camera>
      <lights><light><position x="0" y="6" z="0"/><color r="1" g="1" b="1"/></light>
        <light><position x="0" y="7" z="0"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="0" y="1" z="0"/>
        <diffuse_coef>0.8</diffuse_coef></properties></object>)";
    constexpr int kSpheres = 1100;
    for (int i = 0; i < kSpheres; ++i)
        xml += "<object><position x=\"0\" y=\"" + std::to_string(0.1 + 0.004 * i) +
               "\" z=\"0\"/><properties><type>sphere</type><radius>0.0015</radius>"
               "<transmission_coef>0.999</transmission_coef><refraction_coef>1</refraction_coef>"
               "<diffuse_coef>0</diffuse_coef></properties></object>";
    xml += "</objects></scene>";
    RayTree tree = traceXml(xml, 41, 31, 20, 15);
    const gpu::RayTreeRay& floor = tree.rays[0];
    ASSERT_EQ(floor.material, 0u) << "the centre pixel sees the floor at the origin";
    ASSERT_EQ(floor.shadowRayCount, 2u);
    const gpu::RayTreeShadowRay& shadow = tree.shadowRays[floor.firstShadowRay];
    const gpu::RayTreeShadowRay& second = tree.shadowRays[floor.firstShadowRay + 1];
    EXPECT_EQ(shadow.outcome, gpu::kShadowFiltered) << "not lit: it crossed 2,200 surfaces";
    EXPECT_EQ(shadow.crossingCount, gpu::kRayTreeMaxCrossings);
    EXPECT_EQ(shadow.crossingCount + shadow.droppedCrossings, 2u * kSpheres);
    EXPECT_EQ(second.outcome, gpu::kShadowFiltered) << "not lit: none of its crossings fit, all were found";
    EXPECT_EQ(second.crossingCount, 0u);
    EXPECT_EQ(second.droppedCrossings, 2u * kSpheres);
    EXPECT_EQ(tree.dropped, 4u * kSpheres - gpu::kRayTreeMaxCrossings);
    const float expected = std::pow(0.999f, 2.0f * kSpheres);
    for (const gpu::RayTreeShadowRay* s : {&shadow, &second})
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(s->transmittance[c], expected, 1e-3f * expected);
            EXPECT_NEAR(s->visibility[c], s->transmittance[c], 1e-4f * expected) << "the renderer's own";
        }
    std::string text = rayTreeText(tree, loadSceneFromString(xml, "test.xml"));
    EXPECT_NE(text.find("(not fully recorded: 2352 rays, shadow rays or crossings"), std::string::npos) << text;
    EXPECT_NE(text.find("(and 152 crossings not recorded)"), std::string::npos);
    EXPECT_NE(text.find("filtered (and 2200 crossings not recorded)"), std::string::npos);

    // Stacked glass slabs that reflect and refract: the tree branches at
    // every surface, past the record's 256 rays at depth 12.
    std::string slabs = R"(<scene><camera><position x="0.1" y="0.13" z="6"/><window_position x="0.1" y="0.13" z="5"/>
      <width>41</width><height>31</height></camera>
      <lights><light><position x="3" y="4" z="8"/><color r="1" g="1" b="1"/></light></lights><objects>)";
    for (int i = 0; i < 6; ++i)
        slabs += "<object><position x=\"-2\" y=\"-2\" z=\"" + std::to_string(-1.0 * i) +
                 "\"/><properties><type>box</type><size x=\"4\" y=\"4\" z=\"0.5\"/>"
                 "<reflection_coef>0.3</reflection_coef><transmission_coef>0.6</transmission_coef>"
                 "<refraction_coef>1.5</refraction_coef></properties></object>";
    slabs += "</objects></scene>";
    RayTree deep = traceXml(slabs, 41, 31, 20, 15, 12);
    EXPECT_EQ(deep.rays.size(), size_t(gpu::kRayTreeMaxRays));
    EXPECT_GT(deep.dropped, 0u);
    const std::string deepText = rayTreeText(deep, loadSceneFromString(slabs, "slabs.xml"));
    EXPECT_NE(deepText.find("(not fully recorded: "), std::string::npos) << deepText.substr(0, 300);
}

// A shadow ray through a 307,200-triangle glass mesh (600 tilted layers of
// 512 triangles above a floor, the light above them): the recorder gets its
// crossings from the renderer's own shadow walk, along the BVH or the ray
// queries (shadowCrossing's hook, shaders/intersect.glsl), not from a loop
// over every primitive, and they are exactly those a double-precision test
// of every triangle finds along the recorded ray: the same count, the same
// triangles in the same order, t within 1e-5 relative. The floor point lies
// 0.004 or more from every layer's triangle edges in x and z, so no
// crossing is a near miss either way.
TEST(RayTree, ShadowRayThroughALargeMeshRecordsExactlyTheCrossingsBruteForceFinds) {
    constexpr int kLayers = 600, kGrid = 16;
    Scene scene;
    const glm::dvec3 target(0.0131, 0.0, 0.0173);
    scene.camera.eye = target + glm::dvec3(0, 0.5, 6);
    scene.camera.windowCenter = target + glm::dvec3(0, 0.5 - 0.5 / 6, 5);
    scene.camera.width = 41;
    scene.camera.height = 31;
    Light light;
    light.position = target + glm::dvec3(0, 5, 0);
    scene.lights.push_back(light);
    Object floor;
    floor.shape = Plane{{0, 0, 0}, {0, 1, 0}};
    floor.material.diffuse = 0.8;
    scene.objects.push_back(floor);
    Mesh mesh;
    for (int layer = 0; layer < kLayers; ++layer) {
        auto vertex = [&](int i, int j) {
            double x = -1 + 2.0 * i / kGrid, z = -1 + 2.0 * j / kGrid;
            // Float values, as the renderer packs them: the reference tests the same triangles.
            return glm::dvec3(glm::vec3(glm::dvec3(x, 1 + 0.003 * layer + 0.0004 * x - 0.0003 * z, z)));
        };
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
                mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
            }
    }
    Object glass;
    glass.shape = mesh;
    glass.material.transmission = 0.99;
    glass.material.diffuse = 0.0;
    scene.objects.push_back(glass);
    const std::vector<Triangle>& tris = mesh.triangles;
    ASSERT_EQ(tris.size(), size_t(kLayers) * kGrid * kGrid * 2);

    std::vector<TracePath> paths = {TracePath::Bvh};
    if (testContext().deviceInfo().rayQuery) paths.push_back(TracePath::RayQuery);
    for (TracePath path : paths) {
        SCOPED_TRACE(path == TracePath::Bvh ? "BVH walk" : "ray queries");
        RenderSettings settings = traceSettings(41, 31);
        settings.trace = path;
        Renderer renderer(testContext(), scene, settings);
        RayTreeRecorder recorder(testContext());
        RayTree tree = recorder.trace(renderer, 20, 15);
        expectShadowsAgree(tree);
        ASSERT_EQ(tree.rays[0].material, 0u) << "the centre pixel sees the floor";
        ASSERT_EQ(tree.rays[0].shadowRayCount, 1u);
        const gpu::RayTreeShadowRay& s = tree.shadowRays[tree.rays[0].firstShadowRay];

        // Every triangle against the recorded ray (its float origin and direction), in (0, distance).
        std::vector<std::pair<double, size_t>> expected;
        for (size_t k = 0; k < tris.size(); ++k)
            if (auto h = watertightTriangle(glm::dvec3(s.origin), glm::dvec3(s.direction), tris[k]);
                h && h->t < double(s.distance))
                expected.emplace_back(h->t, k);
        std::sort(expected.begin(), expected.end());
        ASSERT_EQ(expected.size(), size_t(kLayers)) << "the ray crosses every layer once";
        EXPECT_EQ(tree.dropped, 0u);
        EXPECT_EQ(s.droppedCrossings, 0u);
        EXPECT_EQ(s.outcome, gpu::kShadowFiltered);
        ASSERT_EQ(s.crossingCount, expected.size());
        // The packed primitives name the triangles the record points at.
        GpuScene packed = packScene(scene, settings);
        for (size_t i = 0; i < expected.size(); ++i) {
            const gpu::RayTreeCrossing& c = tree.crossings[s.firstCrossing + i];
            const Triangle& want = tris[expected[i].second];
            ASSERT_LT(c.primitive, packed.primitives.size());
            const gpu::Primitive& got = packed.primitives[c.primitive];
            EXPECT_TRUE(gpu::triangleV0(got) == glm::vec3(want.v0) && gpu::triangleV1(got) == glm::vec3(want.v1) &&
                        gpu::triangleV2(got) == glm::vec3(want.v2))
                << "crossing " << i << ": primitive " << c.primitive << " is not triangle " << expected[i].second;
            EXPECT_NEAR(c.t, expected[i].first, 1e-5 * expected[i].first) << "crossing " << i;
            EXPECT_EQ(c.material, 1u);
        }
        const float want = std::pow(0.99f, float(kLayers));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.visibility[c], want, 1e-3f * want);
    }
}

// --max-depth bounds the tree.
TEST(RayTree, NoRayDeeperThanMaxDepth) {
    Scene scene = loadScene(sourceDir() / "scenes" / "several_mirrors.xml");
    for (int depth : {0, 1, 3}) {
        Renderer renderer(testContext(), scene, traceSettings(40, 30, depth));
        RayTreeRecorder recorder(testContext());
        uint32_t deepest = 0;
        for (int y = 1; y < 30; y += 2)
            for (int x = 1; x < 40; x += 2) {
                RayTree tree = recorder.trace(renderer, x, y);
                expectTree(tree, depth);
                for (const gpu::RayTreeRay& r : tree.rays) deepest = std::max(deepest, r.depth);
            }
        EXPECT_EQ(deepest, uint32_t(depth)) << "mirrors: some ray goes as deep as allowed";
    }
}

TEST(RayTree, TraceCommandPrintsTheTreeAndItsErrorsExitTwo) {
    fs::path dir = freshOutputDir("ray_tree", "cli");
    std::string exe = "'" WHITTED_EXECUTABLE "' trace ";
    std::string room = "'" + (sourceDir() / "scenes" / "room.xml").string().append("'");
    CommandRun ok = runCommand(exe + room + " --pixel 40,30 --width 80 --height 60", dir);
    ASSERT_EQ(ok.status, 0) << ok.output;
    EXPECT_EQ(ok.output.rfind("pixel 40,30 of 80x60, max depth 6: colour (", 0), 0u) << ok.output;
    EXPECT_NE(ok.output.find("\ncamera [depth 0] "), std::string::npos) << ok.output;
    EXPECT_NE(ok.output.find("\n  shadow ray to light "), std::string::npos) << ok.output;
    CommandRun json = runCommand(exe + room + " --pixel 40,30 --width 80 --height 60 --json --max-depth 2", dir);
    ASSERT_EQ(json.status, 0) << json.output;
    EXPECT_NE(json.output.find("\"max_depth\": 2"), std::string::npos);
    EXPECT_NE(json.output.find("\"kind\": \"camera\""), std::string::npos);

    CommandRun outside = runCommand(exe + room + " --pixel 80,10 --width 80 --height 60", dir);
    EXPECT_EQ(outside.status, 2);
    EXPECT_EQ(outside.output, "whitted: --pixel 80,10 is outside the 80x60 image\n");
    CommandRun malformed = runCommand(exe + room + " --pixel 3", dir);
    EXPECT_EQ(malformed.status, 2);
    EXPECT_EQ(malformed.output, "whitted: --pixel: expected X,Y (two integers), got '3'\n");
    fs::path bad = dir / "bad.xml";
    std::ofstream(bad) << "<scene>\n<camera><bogus/></camera></scene>\n";
    CommandRun badScene = runCommand(exe + "bad.xml --pixel 1,1", dir);
    EXPECT_EQ(badScene.status, 2);
    EXPECT_EQ(badScene.output.rfind("bad.xml:2: ", 0), 0u) << badScene.output;
    std::set<std::string> files;
    for (const auto& entry : fs::directory_iterator(dir)) files.insert(entry.path().filename().string());
    EXPECT_EQ(files, std::set<std::string>{"bad.xml"}) << "trace writes nothing";
}

// The window under Xvfb: after `pick`, the window screenshot shows the tree
// over the image. The scene is the mirror of the hand-computed test above
// (camera on +z, 41x31 shown 19 times enlarged, 779x589): the camera ray's
// ring sits on the centre pixel; the reflection runs from the mirror at the
// origin along +x, so along the image's middle row to the right edge; the
// mirror's shadow ray to the light at (0, 3, 3) runs straight up from the
// centre, its midpoint (0, 1.5, 1.5) at depth 3.5: ndc y = (1.5 / 3.5) /
// tan 30 = 0.742, window row (1 - 0.742) / 2 * 589 = 76.
TEST(RayTree, WindowDrawsThePickedPixelsTreeOverTheImage) {
    fs::path dir = freshOutputDir("ray_tree", "window");
    std::ofstream(dir / "mirror.xml") << R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
      <width>41</width><height>31</height></camera>
      <lights><light><position x="0" y="3" z="3"/><color r="1" g="1" b="1"/></light></lights><objects>
      <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="1" y="0" z="1"/>
        <diffuse_coef>0.3</diffuse_coef><reflective>true</reflective><reflection_coef>0.7</reflection_coef></properties></object>
      <object><position x="6" y="0" z="0"/><diffuse_color r="1" g="0" b="0"/>
        <properties><type>sphere</type><radius>1</radius><ambiente_coef>0.2</ambiente_coef></properties></object>
      </objects></scene>)";
    std::ofstream(dir / "script.txt") << "spp 1\nkey F1\npick 20 15\nframes 2\nwindow_screenshot window.png\n"
                                         "screenshot image.png\nquit\n";
    CommandRun view = runCommand("xvfb-run -a -s '-screen 0 1024x768x24' '" WHITTED_EXECUTABLE
                                 "' view mirror.xml --spp 1 --script script.txt",
                                 dir);
    ASSERT_EQ(view.status, 0) << view.output;
    EXPECT_NE(view.output.find("view: ray tree of pixel 20,15: 2 rays"), std::string::npos) << view.output;
    int w = 0, h = 0, channels = 0;
    std::vector<float> storage;
    std::span<const float> window = readImageInto(dir / "window.png", w, h, channels, storage);
    ASSERT_EQ(w, 779);
    ASSERT_EQ(h, 589);
    // Some pixel within 3 of (x, y) has the overlay's colour (RGBA8 0xAABBGGRR).
    auto near = [&](std::span<const float> image, int x, int y, uint32_t colour) {
        glm::vec3 want(float(colour & 0xff), float((colour >> 8) & 0xff), float((colour >> 16) & 0xff));
        for (int dy = -3; dy <= 3; ++dy)
            for (int dx = -3; dx <= 3; ++dx) {
                const float* p = &image[(size_t(y + dy) * w + x + dx) * channels];
                glm::vec3 got(p[0] * 255.0f, p[1] * 255.0f, p[2] * 255.0f);
                if (glm::all(glm::lessThanEqual(glm::abs(got - want), glm::vec3(40.0f)))) return true;
            }
        return false;
    };
    for (int x : {480, 560, 640, 720}) EXPECT_TRUE(near(window, x, 294, kOverlayReflectionColour)) << "x " << x;
    EXPECT_TRUE(near(window, 389, 76, kOverlayShadowColour));
    EXPECT_TRUE(near(window, 389, 294 - 6, kOverlayCameraColour));
    std::vector<float> plainStorage;
    std::span<const float> plain = readImageInto(dir / "image.png", w, h, channels, plainStorage);
    ASSERT_EQ(w, 41) << "the image alone, without the overlay";
}


}  // namespace
}  // namespace whitted::test

// Constructive solid geometry (scenes/README.md "CSG"; host/shapes/csg.cpp,
// shaders/shapes/csg.glsl): what the loader builds, a difference's shadow
// against the camera's view of it, and a glass lens made as the
// intersection of two spheres against the thick-lens formula. The POV-Ray
// cross-check of nested opaque CSG is tests/povray_scenes/csg.xml
// (tests/povray_test.cpp), the ray-query path tests/ray_query_test.cpp, the
// refused input tests/bad_scenes/csg_*.xml.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"
#include "view/editor_panel.h"

namespace whitted::test {
namespace {

std::string sceneXml(const std::string& camera, const std::string& lights, const std::string& objects) {
    return "<scene><camera>" + camera + "</camera><lights>" + lights + "</lights><objects>" + objects +
           "</objects></scene>";
}

// ---- The loader --------------------------------------------------------------

// Children are placed from the csg object's position (nested ones from
// their parent's); a child without material elements takes its csg
// object's material, one with any keeps its own (defaults for the rest), a
// nested csg object's material passes to its own children.
TEST(CsgLoader, PlacesChildrenAndPassesMaterialsDown) {
    const std::string xml = sceneXml(R"(<position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>)", "",
                                     R"(<object><position x="1" y="2" z="3"/><diffuse_color r="1" g="0" b="0"/>
             <properties><type>csg</type><operation>difference</operation><diffuse_coef>0.5</diffuse_coef></properties>
             <objects>
               <object><position x="0" y="0" z="0"/><properties><type>sphere</type><radius>1</radius></properties></object>
               <object><position x="0.5" y="0" z="0"/><diffuse_color r="0" g="1" b="0"/>
                 <properties><type>box</type><size x="1" y="1" z="1"/></properties></object>
               <object><position x="0" y="-1" z="0"/><diffuse_color r="0" g="0" b="1"/>
                 <properties><type>csg</type><operation>intersection</operation></properties>
                 <objects>
                   <object><position x="0" y="0" z="0"/><properties><type>cylinder</type><radius>0.2</radius><height>1</height></properties></object>
                   <object><position x="0" y="0.5" z="0"/><properties><type>sphere</type><radius>0.4</radius></properties></object>
                 </objects>
               </object>
             </objects></object>)");
    Scene scene = loadSceneFromString(xml, "t.xml");
    ASSERT_EQ(scene.objects.size(), 1u);
    const Csg& csg = std::get<Csg>(scene.objects[0].shape);
    EXPECT_EQ(csg.operation, Csg::Operation::Difference);
    EXPECT_EQ(csg.position, glm::dvec3(1, 2, 3));
    ASSERT_EQ(csg.children.size(), 3u);

    const CsgChild& sphere = csg.children[0];
    EXPECT_EQ(std::get<Sphere>(sphere.shape).center, glm::dvec3(1, 2, 3));
    EXPECT_FALSE(sphere.ownMaterial);
    EXPECT_EQ(sphere.material.diffuseColor, glm::dvec3(1, 0, 0));
    EXPECT_EQ(sphere.material.diffuse, 0.5);

    const CsgChild& box = csg.children[1];
    EXPECT_EQ(std::get<Box>(box.shape).min, glm::dvec3(1.5, 2, 3));
    EXPECT_EQ(std::get<Box>(box.shape).max, glm::dvec3(2.5, 3, 4));
    EXPECT_TRUE(box.ownMaterial);
    EXPECT_EQ(box.material.diffuseColor, glm::dvec3(0, 1, 0));
    EXPECT_EQ(box.material.diffuse, Material{}.diffuse);  // its own: the default, not the csg object's 0.5

    const Csg& nested = std::get<Csg>(csg.children[2].shape);
    EXPECT_EQ(nested.operation, Csg::Operation::Intersection);
    EXPECT_EQ(nested.position, glm::dvec3(1, 1, 3));
    EXPECT_EQ(std::get<Cylinder>(nested.children[0].shape).base, glm::dvec3(1, 1, 3));
    EXPECT_EQ(std::get<Sphere>(nested.children[1].shape).center, glm::dvec3(1, 1.5, 3));
    for (const CsgChild& c : nested.children) {
        EXPECT_FALSE(c.ownMaterial);
        EXPECT_EQ(c.material.diffuseColor, glm::dvec3(0, 0, 1));
    }

    // The scene writer keeps all of it: positions relative to the parent,
    // materials only where a child has its own.
    Scene again = loadSceneFromString(whitted::sceneXml(scene), "again.xml");
    const Csg& csg2 = std::get<Csg>(again.objects[0].shape);
    EXPECT_EQ(csg2.operation, Csg::Operation::Difference);
    EXPECT_EQ(std::get<Box>(csg2.children[1].shape).min, glm::dvec3(1.5, 2, 3));
    EXPECT_FALSE(csg2.children[0].ownMaterial);
    EXPECT_TRUE(csg2.children[1].ownMaterial);
    EXPECT_EQ(csg2.children[1].material.diffuseColor, glm::dvec3(0, 1, 0));
    const Csg& nested2 = std::get<Csg>(csg2.children[2].shape);
    EXPECT_EQ(std::get<Sphere>(nested2.children[1].shape).center, glm::dvec3(1, 1.5, 3));
    EXPECT_EQ(nested2.children[1].material.diffuseColor, glm::dvec3(0, 0, 1));
}

// ---- Operations -------------------------------------------------------------------

// Two overlapping spheres side by side, seen from the front; the operation
// set as the editor panel sets it (setObjectField, the script's `edit`).
// Pixels: through the left sphere only, through the middle (where the left
// sphere's chord lies inside the right's), through the right sphere only.
TEST(CsgRender, EachOperationKeepsWhatItShould) {
    const std::string xml = sceneXml(
        R"(<position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>)",
        R"(<light><position x="0" y="0" z="5"/><color r="1" g="1" b="1"/></light>)",
        R"(<object><position x="0" y="0" z="0"/><properties><type>csg</type><operation>union</operation></properties>
             <objects>
               <object><position x="-0.5" y="0" z="0"/><properties><type>sphere</type><radius>0.8</radius></properties></object>
               <object><position x="0.5" y="0" z="0"/><properties><type>sphere</type><radius>0.8</radius></properties></object>
             </objects></object>)");
    Scene scene = loadSceneFromString(xml, "t.xml");
    EXPECT_EQ(setObjectField(scene, 0, "operation", 3),
              "operation must be 0 (union), 1 (intersection) or 2 (difference)");
    struct Case {
        int operation;
        bool left, middle, right;
    };
    const Case cases[] = {{0, true, true, true}, {1, false, true, false}, {2, true, false, false}};
    for (const Case& c : cases) {
        ASSERT_EQ(setObjectField(scene, 0, "operation", c.operation), std::nullopt);
        RenderSettings s{.width = 64,
                         .height = 48,
                         .samplesPerPixel = 1,
                         .maxDepth = 0,
                         .auxiliary = true,
                         .antiAliasing = AntiAliasing::Uniform};
        RenderResult r = renderScene(scene, s);
        // The hit mask (w of the normal layer) at x = -1.1, 0.06 and 1.1 in the spheres' plane.
        EXPECT_EQ(pixel(r, gpu::kAovNormal, 22, 24).w, c.left ? 1.0f : 0.0f) << "operation " << c.operation;
        EXPECT_EQ(pixel(r, gpu::kAovNormal, 32, 24).w, c.middle ? 1.0f : 0.0f) << "operation " << c.operation;
        EXPECT_EQ(pixel(r, gpu::kAovNormal, 41, 24).w, c.right ? 1.0f : 0.0f) << "operation " << c.operation;
    }
    Scene plain = loadSceneFromString(
        sceneXml(
            R"(<position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>)", "",
            R"(<object><position x="0" y="0" z="0"/><properties><type>sphere</type><radius>1</radius></properties></object>)"),
        "p.xml");
    EXPECT_EQ(setObjectField(plain, 0, "operation", 1), "operation applies to csg objects only");
}

// ---- Random trees against a double-precision reference --------------------------------

// The span of the ray o + t d inside a convex leaf, in double precision, or
// nothing: sphere by its quadratic, box by slabs, capped cylinder as the
// intersection of the infinite cylinder's span and the slab between its caps.
std::optional<std::pair<double, double>> leafSpan(const Shape& shape, const glm::dvec3& o, const glm::dvec3& d) {
    static constexpr double kInf = std::numeric_limits<double>::infinity();
    auto slab = [](double origin, double dir, double lo, double hi) -> std::pair<double, double> {
        if (dir == 0) return origin > lo && origin < hi ? std::pair{-kInf, kInf} : std::pair{kInf, -kInf};
        double a = (lo - origin) / dir, b = (hi - origin) / dir;
        return {std::min(a, b), std::max(a, b)};
    };
    std::pair<double, double> span{-kInf, kInf};
    if (const Sphere* s = std::get_if<Sphere>(&shape)) {
        glm::dvec3 f = o - s->center;
        double b = glm::dot(f, d), disc = b * b - (glm::dot(f, f) - s->radius * s->radius);
        if (disc <= 0) return std::nullopt;
        span = {-b - std::sqrt(disc), -b + std::sqrt(disc)};
    } else if (const Box* box = std::get_if<Box>(&shape)) {
        for (int i = 0; i < 3; ++i) {
            auto [a, b] = slab(o[i], d[i], box->min[i], box->max[i]);
            span = {std::max(span.first, a), std::min(span.second, b)};
        }
    } else {
        const Cylinder& c = std::get<Cylinder>(shape);
        glm::dvec3 f = o - c.base;
        double oa = glm::dot(f, c.axis), da = glm::dot(d, c.axis);
        span = slab(oa, da, 0.0, c.height);
        glm::dvec3 op = f - oa * c.axis, dp = d - da * c.axis;
        double a = glm::dot(dp, dp), b = glm::dot(op, dp), cc = glm::dot(op, op) - c.radius * c.radius;
        double disc = b * b - a * cc;
        if (disc <= 0 || a == 0) return std::nullopt;
        span = {std::max(span.first, (-b - std::sqrt(disc)) / a), std::min(span.second, (-b + std::sqrt(disc)) / a)};
    }
    if (!(span.first < span.second)) return std::nullopt;
    return span;
}

// Point membership by the tree itself (not the shader's postfix program):
// union = any child, intersection = all, difference = the first and none of
// the others. `inLeaf` says whether p is in each leaf, in leaf order.
bool contains(const Csg& csg, const std::vector<bool>& inLeaf, size_t& next) {
    std::vector<bool> in;
    for (const CsgChild& c : csg.children)
        in.push_back(std::holds_alternative<Csg>(c.shape) ? contains(std::get<Csg>(c.shape), inLeaf, next)
                                                          : bool(inLeaf[next++]));
    switch (csg.operation) {
        case Csg::Operation::Union:
            return std::find(in.begin(), in.end(), true) != in.end();
        case Csg::Operation::Intersection:
            return std::find(in.begin(), in.end(), false) == in.end();
        case Csg::Operation::Difference:
            return in[0] && std::find(in.begin() + 1, in.end(), true) == in.end();
    }
    return false;
}

void collectLeaves(const Csg& csg, std::vector<const Shape*>& out) {
    for (const CsgChild& c : csg.children)
        if (const Csg* nested = std::get_if<Csg>(&c.shape))
            collectLeaves(*nested, out);
        else
            out.push_back(&c.shape);
}

// What the reference sees along one camera ray: the first crossing of the
// solid's surface (t, leaf) or none; `clear` is false when another span end
// lies within 1e-4 of it (coincident or tangent surfaces: no single answer).
struct Reference {
    bool hit = false;
    double t = 0;
    int leaf = -1;
    bool clear = true;
};

Reference referenceHit(const Csg& csg, const std::vector<const Shape*>& leaves, const glm::dvec3& o,
                       const glm::dvec3& d) {
    std::vector<std::optional<std::pair<double, double>>> spans;
    std::vector<std::pair<double, int>> ends;
    for (size_t j = 0; j < leaves.size(); ++j) {
        spans.push_back(leafSpan(*leaves[j], o, d));
        if (spans[j] && spans[j]->first > 0) ends.push_back({spans[j]->first, int(j)});
        if (spans[j] && spans[j]->second > 0) ends.push_back({spans[j]->second, int(j)});
    }
    std::sort(ends.begin(), ends.end());
    auto solidAt = [&](double t) {
        std::vector<bool> in;
        for (const auto& s : spans) in.push_back(s && s->first < t && t < s->second);
        size_t next = 0;
        return contains(csg, in, next);
    };
    Reference r;
    bool before = solidAt(ends.empty() ? 1.0 : ends.front().first * 0.5);
    for (size_t k = 0; k < ends.size(); ++k) {
        double after = k + 1 < ends.size() ? 0.5 * (ends[k].first + ends[k + 1].first) : ends[k].first + 1.0;
        if (solidAt(after) == before) continue;
        r.hit = true;
        r.t = ends[k].first;
        r.leaf = ends[k].second;
        r.clear = (k == 0 || ends[k].first - ends[k - 1].first > 1e-4) &&
                  (k + 1 == ends.size() || ends[k + 1].first - ends[k].first > 1e-4);
        break;
    }
    return r;
}

// A random csg tree of spheres, boxes and cylinders in [-1, 1]^3, each leaf
// with a colour of its own (ambient only, so a pixel shows the leaf it
// sees), nested csg objects at random offsets.
std::string randomCsgXml(std::mt19937& rng, int depth, int& leaves, const glm::dvec3& offset) {
    std::uniform_real_distribution<double> u(-1, 1), size(0.5, 1.0);
    // Unions half the time: a random intersection or difference is often small.
    std::discrete_distribution<int> op({2, 1, 1});
    std::uniform_int_distribution<int> kids(2, 3), shape(0, 2);
    auto vec = [](const char* tag, const glm::dvec3& v) {
        std::ostringstream s;
        s.precision(17);
        s << "<" << tag << " x=\"" << v.x << "\" y=\"" << v.y << "\" z=\"" << v.z << "\"/>";
        return s.str();
    };
    static const char* kOps[] = {"union", "intersection", "difference"};
    std::ostringstream s;
    s << "<object>" << vec("position", offset) << "<properties><type>csg</type><operation>" << kOps[op(rng)]
      << "</operation></properties><objects>";
    int n = kids(rng);
    for (int k = 0; k < n; ++k) {
        if (depth < 3 && leaves + 4 <= 16 && std::uniform_real_distribution<double>(0, 1)(rng) < 0.35) {
            glm::dvec3 shift(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
            s << randomCsgXml(rng, depth + 1, leaves, shift);
            continue;
        }
        int id = leaves++;
        glm::dvec3 colour((id % 4 + 1) / 4.0, (id / 4 % 4 + 1) / 4.0, 0.5);
        glm::dvec3 p(0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng));
        std::ostringstream c;
        c << "<diffuse_color r=\"" << colour.r << "\" g=\"" << colour.g << "\" b=\"" << colour.b << "\"/>";
        std::string material = "<ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef>";
        switch (shape(rng)) {
            case 0:
                s << "<object>" << vec("position", p) << c.str() << "<properties><type>sphere</type><radius>"
                  << size(rng) << "</radius>" << material << "</properties></object>";
                break;
            case 1:
                s << "<object>" << vec("position", p - 0.5) << c.str() << "<properties><type>box</type>"
                  << vec("size", glm::dvec3(size(rng), size(rng), size(rng)) * 1.4) << material
                  << "</properties></object>";
                break;
            default:
                s << "<object>" << vec("position", p - glm::dvec3(0, 0.6, 0)) << c.str()
                  << "<properties><type>cylinder</type><radius>" << 0.5 * size(rng) << "</radius><height>"
                  << 2 * size(rng) << "</height>" << vec("axis", glm::dvec3(u(rng), 1.5, u(rng))) << material
                  << "</properties></object>";
        }
    }
    return s.str() + "</objects></object>";
}

// Random nested trees rendered with one camera sample per pixel centre: at
// every pixel whose answer is clear (the reference's crossing has no other
// span end within 1e-4, and its four neighbours see the same leaf at a
// depth within 0.05, so no silhouette or depth step passes through it), the
// hit mask, the depth (within 1e-4 relative: float against double) and the
// leaf struck (its colour) must be the reference's. Both tracing paths.
TEST(CsgRender, RandomTreesMatchADoublePrecisionReference) {
    std::mt19937 rng(20261201);
    const int w = 80, h = 60;
    const glm::dvec3 eye(0.4, 0.7, 5), target(0, 0, 0);
    int compared = 0, hits = 0;
    for (int tree = 0; tree < 16; ++tree) {
        int leaves = 0;
        std::string object = randomCsgXml(rng, 1, leaves, glm::dvec3(0));
        std::string xml = sceneXml(R"(<position x="0.4" y="0.7" z="5"/><window_position x="0.32" y="0.56" z="4.01"/>)"
                                   R"(<fov>28</fov>)",
                                   "", object);
        xml.replace(xml.find("<lights>"), 0, R"(<ambient_light r="1" g="1" b="1"/>)");
        Scene scene = loadSceneFromString(xml, "random.xml");
        const Csg& csg = std::get<Csg>(scene.objects[0].shape);
        std::vector<const Shape*> leafShapes;
        collectLeaves(csg, leafShapes);
        ASSERT_EQ(int(leafShapes.size()), leaves);

        const Camera& cam = scene.camera;
        const double tanHalf = std::tan(glm::radians(cam.verticalFovDegrees) / 2.0), aspect = double(w) / h;
        const glm::dvec3 forward = glm::normalize(cam.windowCenter - cam.eye);
        const glm::dvec3 right = glm::normalize(glm::cross(forward, cam.up));
        const glm::dvec3 up = glm::cross(right, forward);
        std::vector<Reference> refs(size_t(w) * h);
        std::vector<glm::dvec3> dirs(refs.size());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                glm::dvec3 d = glm::normalize(forward + (2.0 * (x + 0.5) / w - 1.0) * tanHalf * aspect * right +
                                              (1.0 - 2.0 * (y + 0.5) / h) * tanHalf * up);
                refs[size_t(y) * w + x] = referenceHit(csg, leafShapes, cam.eye, d);
            }
        int treeHits = 0;
        for (TracePath trace : {TracePath::Bvh, TracePath::RayQuery}) {
            if (trace == TracePath::RayQuery && !testContext().deviceInfo().rayQuery) continue;
            RenderSettings s{.width = w,
                             .height = h,
                             .samplesPerPixel = 1,
                             .maxDepth = 0,
                             .auxiliary = true,
                             .trace = trace,
                             .antiAliasing = AntiAliasing::Uniform};
            RenderResult r = renderScene(scene, s);
            for (int y = 1; y + 1 < h; ++y)
                for (int x = 1; x + 1 < w; ++x) {
                    const Reference& ref = refs[size_t(y) * w + x];
                    bool clear = ref.clear;
                    for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                        const Reference& n = refs[size_t(y + dy) * w + x + dx];
                        clear = clear && n.clear && n.hit == ref.hit && n.leaf == ref.leaf &&
                                (!ref.hit || std::abs(n.t - ref.t) < 0.05);
                    }
                    if (!clear) continue;
                    ++compared;
                    hits += ref.hit ? 1 : 0;
                    treeHits += ref.hit ? 1 : 0;
                    std::string where = std::string(trace == TracePath::Bvh ? "BVH" : "ray query") + ", tree " +
                                        std::to_string(tree) + ", pixel " + std::to_string(x) + "," + std::to_string(y);
                    ASSERT_EQ(pixel(r, gpu::kAovNormal, x, y).w, ref.hit ? 1.0f : 0.0f) << where;
                    if (!ref.hit) continue;
                    // Depth is the distance along the unit camera ray.
                    EXPECT_NEAR(pixel(r, gpu::kAovCoefs0, x, y).w, ref.t, 1e-4 * ref.t) << where;
                    glm::vec4 c = pixel(r, gpu::kAovColor, x, y);
                    int leaf = int(std::lround(c.r * 4 - 1)) + 4 * int(std::lround(c.g * 4 - 1));
                    EXPECT_EQ(leaf, ref.leaf) << where;
                }
        }
        std::printf("[ csg      ] tree %d: %d leaves, %d clear pixels on the solid\n", tree, leaves, treeHits);
    }
    std::printf("[ csg      ] random trees: %d clear pixels compared, %d of them on the solid\n", compared, hits);
    EXPECT_GT(hits, 2000);
    EXPECT_GT(compared - hits, 2000);
}

// ---- Shadows ------------------------------------------------------------------

// A slab (box) with a sphere removed from its middle, lit from straight
// above: its shadow on the floor is a square with a lit disc where the light
// comes through the hole. The camera sits below the slab, so it sees the
// floor directly (the slab itself only above the horizon). Every floor pixel whose shadow ray is clearly blocked or
// clearly free (decided in double precision by sampling the segment to the
// light against the solid's exact shape, margin 1e-3) must have the diffuse
// term 0 or kd cos(theta) exactly. A shadow ray that took the csg object for
// its box (or for its convex hull) would darken the disc; one that took the
// sphere's surface for an obstacle would darken a ring around it.
TEST(CsgRender, DifferenceCastsTheShadowOfItsShape) {
    const int w = 160, h = 120;
    const glm::dvec3 light(0, 4, 0), eye(0, 0.9, 3), window(0, 0.6, 2);
    const glm::dvec3 boxMin(-1, 1, -1), boxMax(1, 1.2, 1), centre(0, 1.1, 0);
    const double radius = 0.5;
    const std::string xml = sceneXml(
        R"(<position x="0" y="0.9" z="3"/><window_position x="0" y="0.6" z="2"/><fov>60</fov>)",
        R"(<light><position x="0" y="4" z="0"/><color r="1" g="1" b="1"/></light>)",
        R"(<object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="0" y="1" z="0"/></properties></object>
           <object><position x="0" y="1.1" z="0"/><diffuse_color r="0.8" g="0.3" b="0.2"/>
             <properties><type>csg</type><operation>difference</operation></properties>
             <objects>
               <object><position x="-1" y="-0.1" z="-1"/><properties><type>box</type><size x="2" y="0.2" z="2"/></properties></object>
               <object><position x="0" y="0" z="0"/><properties><type>sphere</type><radius>0.5</radius></properties></object>
             </objects></object>)");
    // The largest margin by which a point is inside the solid (negative:
    // outside by that much).
    auto solidMargin = [&](const glm::dvec3& q) {
        glm::dvec3 in = glm::min(q - boxMin, boxMax - q);
        return std::min({in.x, in.y, in.z, glm::length(q - centre) - radius});
    };
    for (TracePath trace : {TracePath::Bvh, TracePath::RayQuery}) {
        if (trace == TracePath::RayQuery && !testContext().deviceInfo().rayQuery) continue;
        RenderSettings s{.width = w,
                         .height = h,
                         .samplesPerPixel = 1,
                         .maxDepth = 0,
                         .auxiliary = true,
                         .trace = trace,
                         .antiAliasing = AntiAliasing::Uniform};
        RenderResult r = renderXml(xml, s);
        // The camera frame of host/render/gpu_scene.cpp.
        const double tanHalf = std::tan(glm::radians(60.0) / 2.0), aspect = double(w) / h;
        const glm::dvec3 forward = glm::normalize(window - eye);
        const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
        const glm::dvec3 up = glm::cross(right, forward);
        int lit = 0, litThroughHole = 0, shadowed = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                glm::dvec3 d = glm::normalize(forward + (2.0 * (x + 0.5) / w - 1.0) * tanHalf * aspect * right +
                                              (1.0 - 2.0 * (y + 0.5) / h) * tanHalf * up);
                if (d.y >= -1e-3) continue;  // not the floor
                glm::dvec3 p = eye + d * (-eye.y / d.y);
                // Where the segment to the light crosses the slab's height.
                double most = -1e9;
                for (int k = 0; k <= 4000; ++k) {
                    double yk = boxMin.y - 0.01 + (boxMax.y - boxMin.y + 0.02) * k / 4000.0;
                    glm::dvec3 q = p + (light - p) * ((yk - p.y) / (light.y - p.y));
                    most = std::max(most, solidMargin(q));
                }
                if (std::abs(most) < 1e-3) continue;  // too near the shadow's edge to call
                bool blocked = most > 0;
                double expected = blocked ? 0.0 : glm::normalize(light - p).y;
                glm::vec4 diffuse = pixel(r, gpu::kAovDiffuse, x, y);
                EXPECT_NEAR(diffuse.r, expected, 1e-4)
                    << (trace == TracePath::Bvh ? "BVH" : "ray query") << ", pixel " << x << "," << y
                    << (blocked ? " should be in shadow" : " should be lit");
                if (blocked)
                    ++shadowed;
                else if (std::abs(p.x) < 1.3 && std::abs(p.z) < 1.3)
                    ++litThroughHole;
                else
                    ++lit;
            }
        // The image shows all three: open floor, the slab's shadow, the disc of light through the hole.
        EXPECT_GT(lit, 500);
        EXPECT_GT(shadowed, 300);
        EXPECT_GT(litThroughHole, 200);
    }
}

// ---- Subtracted surfaces face into the removed volume ------------------------------

// An absorbing clear (IOR 1, so rays go straight) box with a spherical
// cavity (a sphere subtracted wholly inside it), in front of a white wall;
// the light sits at the eye. Light reaching the eye through the box is
// attenuated by exp(-sigma L), L the length of the ray inside the solid: the
// box's chord minus the cavity's. That holds only if the cavity's surface
// counts as leaving the solid where the ray enters the cavity, i.e. its
// normal is the sphere's turned round; with the sphere's own normal the
// cavity's first wall would read as an entry and the ray's first stretch in
// the solid would go unattenuated. Camera rays (weight exp(-sigma t) on each
// stretch between an entry and an exit, whitted.comp) and shadow rays
// (signed optical depth, intersect.glsl) are checked apart: without lights
// the transmission layer is ka exp(-sigma L); with the light and ka 0 it is
// kd cos(theta) exp(-sigma L) exp(-sigma L), the shadow ray retracing the
// camera ray. Every pixel whose ray crosses the box's front and back faces
// and clears the cavity's outline by 1e-3 is compared (1e-4, float).
TEST(CsgRender, AbsorptionSeesTheCavityOfADifference) {
    const int w = 96, h = 72;
    const glm::dvec3 eye(0, 0, 5), sigma(1.0, 2.0, 0.5);
    const double radius = 0.4;
    auto render = [&](bool lit) {
        std::string wall = lit ? "<ambiente_coef>0</ambiente_coef><diffuse_coef>0.5</diffuse_coef>"
                               : "<ambiente_coef>0.5</ambiente_coef><diffuse_coef>0</diffuse_coef>";
        std::string xml = sceneXml(
            R"(<position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/><fov>25</fov>)",
            lit ? R"(<light><position x="0" y="0" z="5"/><color r="1" g="1" b="1"/></light>)" : "",
            R"(<object><position x="0" y="0" z="-3"/><properties><type>plane</type><normal x="0" y="0" z="1"/>)" +
                wall + R"(</properties></object>
               <object><position x="0" y="0" z="0"/><properties><type>csg</type><operation>difference</operation>
                 <transmission_coef>1</transmission_coef><refraction_coef>1</refraction_coef>
                 <diffuse_coef>0</diffuse_coef><absorption r="1" g="2" b="0.5"/></properties><objects>
                 <object><position x="-1" y="-1" z="-0.5"/><properties><type>box</type><size x="2" y="2" z="1"/></properties></object>
                 <object><position x="0" y="0" z="0"/><properties><type>sphere</type><radius>0.4</radius></properties></object>
               </objects></object>)");
        xml.replace(xml.find("<lights>"), 0, R"(<ambient_light r="1" g="1" b="1"/>)");
        RenderSettings s{.width = w,
                         .height = h,
                         .samplesPerPixel = 1,
                         .maxDepth = 6,
                         .auxiliary = true,
                         .antiAliasing = AntiAliasing::Uniform};
        return renderXml(xml, s);
    };
    RenderResult ambient = render(false), lit = render(true);
    const double tanHalf = std::tan(glm::radians(25.0) / 2.0), aspect = double(w) / h;
    int compared = 0, throughCavity = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / w - 1.0) * tanHalf * aspect,
                                                     (1.0 - 2.0 * (y + 0.5) / h) * tanHalf, -1.0));
            // Through the front (z = 0.5) and back (z = -0.5) faces, away from their edges.
            glm::dvec3 front = eye + d * ((0.5 - eye.z) / d.z), back = eye + d * ((-0.5 - eye.z) / d.z);
            if (std::max({std::abs(front.x), std::abs(front.y), std::abs(back.x), std::abs(back.y)}) > 0.99) continue;
            double inBox = glm::length(back - front);
            double b = glm::dot(eye, d), disc = b * b - (glm::dot(eye, eye) - radius * radius);
            if (std::abs(disc) < 1e-3) continue;  // grazing the cavity
            double inCavity = disc > 0 ? 2.0 * std::sqrt(disc) : 0.0;
            glm::dvec3 e = glm::exp(-sigma * (inBox - inCavity));
            glm::dvec3 wall = eye + d * ((-3.0 - eye.z) / d.z);
            double cosine = glm::dot(glm::normalize(eye - wall), glm::dvec3(0, 0, 1));
            glm::vec4 a = pixel(ambient, gpu::kAovTransmission, x, y), l = pixel(lit, gpu::kAovTransmission, x, y);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(a[c], 0.5 * e[c], 1e-4) << "camera ray, pixel " << x << "," << y << " channel " << c;
                EXPECT_NEAR(l[c], 0.5 * cosine * e[c] * e[c], 1e-4)
                    << "shadow ray, pixel " << x << "," << y << " channel " << c;
            }
            ++compared;
            throughCavity += inCavity > 0 ? 1 : 0;
        }
    EXPECT_GT(compared, 2000);
    EXPECT_GT(throughCavity, 300);
}

// ---- Refraction -----------------------------------------------------------------

// A biconvex glass lens made as the intersection of two spheres (radius R,
// centres at z = ±(R - t/2): thickness t on the axis, IOR n) must focus
// where the thick-lens equations say (lensmaker's equation with the
// thickness term, principal planes; Hecht, Optics, 5th ed., 6.2):
//   1/f = (n - 1) (2/R - (n - 1) t / (n R^2)),
// each principal plane f (n - 1) t / (n R) inside its vertex, and an object
// at s1 before the front one images at s2 after the back one, 1/s1 + 1/s2
// = 1/f. The eye on the axis is the object; a small matte sphere (radius
// rho, ambient only, black background) behind the lens is seen through it.
// A camera ray at height h on the lens crosses the plane of the sphere's
// centre at distance h |delta| / s2 from the axis, delta the sphere's
// distance from the focus, so the sphere fills a disc of radius
// proportional to rho s2 / |delta| in the image. Rendered with the sphere a
// distance D before and after the predicted focus z0, the disc radii r1, r2
// (from pixel counts) place the true focus at
//   z = (r1 (z0 - D) + r2 (z0 + D)) / (r1 + r2),
// whatever rho, s2 and the pixel scale. The tolerance, 0.015 (0.1% of s2),
// allows for the pixel count (a disc of about 44 pixels' radius is counted
// to within about 0.3% of its area: 0.003 in z) and for spherical
// aberration: the rays that bound the disc pass 0.11 from the axis, where
// they focus slightly nearer the lens. Measured: 0.005 nearer than z0; with
// rho (so the heights on the lens) doubled, 0.015 nearer, as an aberration
// growing with the square of the height does. The thin-lens formula, which
// ignores the thickness, puts the focus 0.29 away.
TEST(CsgRender, GlassLensFocusesWhereTheThickLensFormulaSays) {
    const double n = 1.5, R = 10.0, t = 0.5, eyeZ = 30.0, rho = 0.015, D = 2.0;
    const double f = 1.0 / ((n - 1.0) * (2.0 / R - (n - 1.0) * t / (n * R * R)));
    const double inset = f * (n - 1.0) * t / (n * R);
    const double front = t / 2 - inset, back = -t / 2 + inset;  // principal planes (light goes towards -z)
    const double s1 = eyeZ - front;
    const double s2 = 1.0 / (1.0 / f - 1.0 / s1);
    const double z0 = back - s2;
    const double thinZ = -1.0 / ((n - 1.0) * 2.0 / R - 1.0 / eyeZ);
    ASSERT_GT(std::abs(thinZ - z0), 0.2) << "the test must tell the thick lens from the thin one";

    auto discRadius = [&](double sphereZ) {
        std::ostringstream objects;
        objects.precision(17);
        objects << R"(<object><position x="0" y="0" z="0"/><diffuse_color r="1" g="1" b="1"/>
             <properties><type>csg</type><operation>intersection</operation>
               <transmission_coef>1</transmission_coef><refraction_coef>)"
                << n << R"(</refraction_coef><diffuse_coef>0</diffuse_coef></properties><objects>
               <object><position x="0" y="0" z=")"
                << -(R - t / 2) << R"("/><properties><type>sphere</type><radius>)" << R
                << R"(</radius></properties></object>
               <object><position x="0" y="0" z=")"
                << (R - t / 2) << R"("/><properties><type>sphere</type><radius>)" << R
                << R"(</radius></properties></object></objects></object>
           <object><position x="0" y="0" z=")"
                << sphereZ << R"("/><diffuse_color r="1" g="0" b="0"/><properties><type>sphere</type><radius>)" << rho
                << R"(</radius><ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>)";
        std::string xml =
            "<scene><camera><position x=\"0\" y=\"0\" z=\"30\"/><window_position x=\"0\" y=\"0\" "
            "z=\"29\"/><fov>1.6</fov></camera><ambient_light r=\"1\" g=\"1\" b=\"1\"/><lights/>"
            "<objects>" +
            objects.str() + "</objects></scene>";
        RenderSettings s{.width = 320,
                         .height = 320,
                         .samplesPerPixel = 1,
                         .maxDepth = 4,
                         .auxiliary = false,
                         .antiAliasing = AntiAliasing::Uniform};
        RenderResult r = renderXml(xml, s);
        int count = 0, edge = 0;
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x)
                if (pixel(r, gpu::kAovColor, x, y).r > 0.5f) {
                    ++count;
                    if (x == 0 || y == 0 || x == s.width - 1 || y == s.height - 1) ++edge;
                }
        EXPECT_EQ(edge, 0) << "the disc must lie inside the image";
        return std::sqrt(count / M_PI);
    };
    double r1 = discRadius(z0 - D), r2 = discRadius(z0 + D);
    double focus = (r1 * (z0 - D) + r2 * (z0 + D)) / (r1 + r2);
    std::printf(
        "[ lens     ] f %.4f, predicted focus z %.4f (thin lens %.4f), disc radii %.2f and %.2f px, "
        "measured focus z %.4f\n",
        f, z0, thinZ, r1, r2, focus);
    EXPECT_GT(r1, 20.0);
    EXPECT_GT(r2, 20.0);
    EXPECT_NEAR(focus, z0, 0.015);
}

}  // namespace
}  // namespace whitted::test

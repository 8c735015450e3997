// Closed meshes seen from inside through the shader's BVH walk
// (shaders/bvh.glsl) and, where the device has them, ray queries: every
// primary ray from a point inside a closed triangle mesh must hit it (the
// hit mask of the auxiliary layers, kAovCoefs1.w). The cube's faces lie on
// its BVH nodes' grid planes (its boxes' own faces); eyes placed just
// inside a face send rays grazing it, and the mesh's shared edges and
// vertices are crossed by many pixels' rays.
#include "scene/scene.h"
#include "test_support.h"

#include <cmath>
#include <map>
#include <numbers>

namespace whitted::test {
namespace {

using Tris = std::vector<Triangle>;

Tris cube(glm::dvec3 lo, glm::dvec3 hi) {
    glm::dvec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    Tris t;
    for (const auto& q : quads) {
        t.push_back({c[q[0]], c[q[1]], c[q[2]]});
        t.push_back({c[q[0]], c[q[2]], c[q[3]]});
    }
    return t;
}

// Icosahedron subdivided `levels` times, vertices on the sphere (shared
// vertices computed once, so neighbouring triangles share them exactly).
Tris icosphere(glm::dvec3 centre, double radius, int levels) {
    const double g = (1 + std::sqrt(5.0)) / 2;
    std::vector<glm::dvec3> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (auto& p : v) p = glm::normalize(p);
    std::vector<glm::ivec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(glm::normalize(v[size_t(a)] + v[size_t(b)]));
            return mid[key] = int(v.size()) - 1;
        };
        std::vector<glm::ivec3> next;
        for (const auto& t : f) {
            int a = midpoint(t.x, t.y), b = midpoint(t.y, t.z), c = midpoint(t.z, t.x);
            next.insert(next.end(), {{t.x, a, c}, {t.y, b, a}, {t.z, c, b}, {a, b, c}});
        }
        f = std::move(next);
    }
    Tris out;
    for (const auto& t : f)
        out.push_back({centre + radius * v[size_t(t.x)], centre + radius * v[size_t(t.y)], centre + radius * v[size_t(t.z)]});
    return out;
}

Tris torus(double major, double minor, int n, int m) {
    auto p = [&](int i, int j) {
        double a = 2 * std::numbers::pi * (i % n) / n, b = 2 * std::numbers::pi * (j % m) / m;
        return glm::dvec3((major + minor * std::cos(b)) * std::cos(a), minor * std::sin(b),
                          (major + minor * std::cos(b)) * std::sin(a));
    };
    Tris t;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            t.push_back({p(i, j), p(i + 1, j), p(i + 1, j + 1)});
            t.push_back({p(i, j), p(i + 1, j + 1), p(i, j + 1)});
        }
    return t;
}

// Pixels whose primary ray hits nothing, from `eye` looking at `at`.
int escapes(const Tris& mesh, glm::dvec3 eye, glm::dvec3 at, TracePath trace, int size) {
    Scene scene;
    scene.camera.eye = eye;
    scene.camera.windowCenter = at;
    scene.camera.up = std::abs(glm::normalize(at - eye).y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    scene.camera.verticalFovDegrees = 120.0;
    scene.camera.width = scene.camera.height = size;
    Mesh m;
    m.triangles = mesh;
    Object o;
    o.shape = m;
    scene.objects.push_back(o);
    RenderSettings s{.width = size, .height = size, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true,
                     .trace = trace};
    RenderResult r = renderScene(scene, s);
    EXPECT_EQ(r.trace, trace);
    int missed = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) missed += pixel(r, gpu::kAovCoefs1, x, y).w < 0.5f;
    return missed;
}

struct View {
    glm::dvec3 eye, at;
};

void expectClosed(const Tris& mesh, const std::vector<View>& views, TracePath trace) {
    for (const View& v : views)
        EXPECT_EQ(escapes(mesh, v.eye, v.at, trace, 160), 0)
            << "eye (" << v.eye.x << ", " << v.eye.y << ", " << v.eye.z << ") towards (" << v.at.x << ", " << v.at.y
            << ", " << v.at.z << ")";
}

// Eyes inside, some a hair inside a face or an edge, looking along it, at
// an edge, at a corner.
std::vector<View> cubeViews() {
    return {{{0.5, 0.5, 0.5}, {0.5, 0.5, 0}},          {{0.5, 0.5, 0.5}, {1, 1, 1}},
            {{0.5, 1e-4, 0.5}, {0.9, 1e-4, 0.1}},      {{1e-5, 0.3, 0.7}, {1e-5, 0.9, 0.1}},
            {{0.999, 0.999, 0.5}, {0.999, 0.999, 0}},  {{0.25, 0.75, 0.999999}, {0.75, 0.25, 0.999999}},
            {{0.1, 0.2, 0.3}, {1, 0, 1}},              {{0.9, 0.1, 0.5}, {0, 1, 0.5}}};
}

std::vector<View> sphereViews() {
    return {{{0, 0, 0}, {0, 0, -1}},   {{0.3, -0.2, 0.1}, {1, 1, 1}},     {{0.99, 0, 0}, {0.99, 1, 0}},
            {{0, 0.999, 0}, {1, 0.999, 1}}, {{-0.5, 0.5, 0.5}, {0.5, 0.5, -0.5}}};
}

std::vector<View> torusViews() {
    // Inside the tube: on its core circle, looking along it and across it.
    return {{{2, 0, 0}, {2, 0, 1}}, {{0, 0, 2}, {1, 0, 2}}, {{-2, 0.49, 0}, {-2, 0.49, 1}}, {{0, 0.2, -2.3}, {0, 1, -2.3}}};
}

// The unit cube, and one moved off the origin so that its faces are not at
// round numbers.
const Tris kCube = cube({0, 0, 0}, {1, 1, 1});
Tris oddCube() { return cube({0.1234567, -3.7654321, 12.5}, {1.1234567, -2.7654321, 13.5}); }

TEST(Watertight, ClosedMeshesSeenFromInsideThroughTheBvh) {
    expectClosed(kCube, cubeViews(), TracePath::Bvh);
    Tris odd = oddCube();
    std::vector<View> oddViews;
    for (View v : cubeViews())
        oddViews.push_back({v.eye + glm::dvec3(0.1234567, -3.7654321, 12.5), v.at + glm::dvec3(0.1234567, -3.7654321, 12.5)});
    expectClosed(odd, oddViews, TracePath::Bvh);
    expectClosed(icosphere({0, 0, 0}, 1.0, 4), sphereViews(), TracePath::Bvh);
    expectClosed(torus(2.0, 0.5, 64, 32), torusViews(), TracePath::Bvh);
}

TEST(Watertight, ClosedMeshesSeenFromInsideThroughRayQueries) {
    if (!testContext().deviceInfo().rayQuery)
        GTEST_SKIP() << "device '" << testContext().deviceInfo().name << "' lacks VK_KHR_ray_query";
    expectClosed(kCube, cubeViews(), TracePath::RayQuery);
    expectClosed(icosphere({0, 0, 0}, 1.0, 4), sphereViews(), TracePath::RayQuery);
    expectClosed(torus(2.0, 0.5, 64, 32), torusViews(), TracePath::RayQuery);
}

}  // namespace
}  // namespace whitted::test

// Closed triangle meshes must have no holes for the tracer, on both trace
// paths (the shader's BVH walk, shaders/bvh.glsl, and ray queries where the
// device has them).
//
// Seen from inside: every primary ray from a point inside a closed mesh must
// hit it (the hit mask of the auxiliary layers, kAovCoefs1.w). The cube's
// faces lie on its BVH nodes' grid planes (its boxes' own faces); eyes placed
// just inside a face send rays grazing it, and the mesh's shared edges and
// vertices are crossed by many pixels' rays.
//
// Seen from outside, against brute force: batches of rays cast through the
// renderer's own traceClosest (RayCaster, render/ray_cast.h) are
// compared with a double-precision watertight test of every triangle (Woop,
// Benthin and Wald 2013; watertightTriangle in test_support.h). Rays come at
// random, aimed at the meshes' vertices and at points of their edges, along
// the axes over a lattice (a cube's edges, diagonals and corners exactly),
// and lying in the planes of the BVH nodes' quantisation grids (a child box's
// bound origin + q * 2^e, host/accel/bvh.cpp: a ray with that coordinate and
// a direction of 0 along the axis grazes the box face all along).
//
// Is the shader's triangle test watertight? shaders/shapes/triangle.glsl is
// Woop et al.'s test without its double-precision re-evaluation of edge
// functions that come out exactly 0. Each vertex is sheared by the same
// float arithmetic whichever triangle it belongs to, and an edge function
// is computed from its two vertices alone, unfused, so the two triangles on
// an edge compute it as exact negatives: a ray can not be outside both by
// that edge, and 0 counts as inside for both. At a vertex, the signs of the
// edge functions of the edges that meet there are each consistent between
// their two triangles, but a ray within rounding of the vertex sees them
// with rounding noise; and a ray that slipped through the near side of a
// closed mesh would still hit its far side, so a hole shows up as a wrong
// t, not a miss. The outside test therefore checks t as well as hit or
// miss, and on the rays aimed within rounding of vertices finds no such
// slip on either path.
#include "exact_triangle.h"
#include "accel/bvh.h"
#include "render/gpu_scene.h"
#include "render/ray_cast.h"
#include "scene/scene.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <span>
#include <string>

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

// Pixels whose primary ray hits nothing, from `eye` looking at `at`. With
// `instance`, the mesh is a prototype drawn by one instance of that
// transform (scene/scene.h Instance), and eye and at go through it too.
int escapes(const Tris& mesh, glm::dvec3 eye, glm::dvec3 at, TracePath trace, int size,
            const glm::dmat4* instance = nullptr) {
    if (instance) {
        eye = glm::dvec3(*instance * glm::dvec4(eye, 1.0));
        at = glm::dvec3(*instance * glm::dvec4(at, 1.0));
    }
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
    if (instance) {
        scene.prototypes.push_back({.name = "mesh", .objects = {o}});
        scene.instances.push_back({.prototype = 0, .worldFromObject = *instance});
    } else {
        scene.objects.push_back(o);
    }
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

void expectClosed(const Tris& mesh, const std::vector<View>& views, TracePath trace,
                  const glm::dmat4* instance = nullptr) {
    for (const View& v : views)
        EXPECT_EQ(escapes(mesh, v.eye, v.at, trace, 160, instance), 0)
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
// The sphere seen from outside: 20 * 4^8 = 1,310,720 triangles.
constexpr int kOutsideSphereLevels = 8;
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

// The cube as a prototype, drawn by an instance rotated, scaled
// non-uniformly, mirrored and moved off round numbers: the walk tests the
// prototype's boxes and triangles against the ray carried into object
// space (shaders/instance.glsl), where the cube's faces lie on its nodes'
// grid planes again. The eyes go through the transform and back in float,
// so only those at least 1e-4 inside a face are kept.
TEST(Watertight, ClosedMeshesSeenFromInsideAnInstanceThroughTheBvh) {
    glm::dmat4 m(glm::dvec4(0.0, 1.3, 0.2, 0.0), glm::dvec4(-0.9, 0.0, 0.1, 0.0), glm::dvec4(0.1, -0.2, -1.7, 0.0),
                 glm::dvec4(0.1234567, -3.7654321, 12.5, 1.0));
    ASSERT_LT(glm::determinant(glm::dmat3(m)), 0.0);
    std::vector<View> views;
    for (View v : cubeViews())
        if (glm::all(glm::greaterThanEqual(glm::min(v.eye, 1.0 - v.eye), glm::dvec3(1e-4)))) views.push_back(v);
    ASSERT_GE(views.size(), 6u);
    expectClosed(kCube, views, TracePath::Bvh, &m);
}

TEST(Watertight, ClosedMeshesSeenFromInsideThroughRayQueries) {
    if (!testContext().deviceInfo().rayQuery)
        GTEST_SKIP() << "device '" << testContext().deviceInfo().name << "' lacks VK_KHR_ray_query";
    expectClosed(kCube, cubeViews(), TracePath::RayQuery);
    expectClosed(icosphere({0, 0, 0}, 1.0, 4), sphereViews(), TracePath::RayQuery);
    expectClosed(torus(2.0, 0.5, 64, 32), torusViews(), TracePath::RayQuery);
}

// ---- Seen from outside, against brute force ----

struct FloatRay {
    glm::vec3 origin, dir;
};

// Each ray's nearest hit distance through `renderer`'s scene along its trace
// path (RayCaster: the tracer's own traceClosest, render/ray_cast.h), -1
// for a miss.
std::vector<float> castRays(const Renderer& renderer, const std::vector<FloatRay>& rays) {
    std::vector<double> origins, directions;
    for (const FloatRay& r : rays)
        for (int i = 0; i < 3; ++i) {
            origins.push_back(r.origin[i]);
            directions.push_back(r.dir[i]);
        }
    const double tMax = std::numeric_limits<double>::infinity();
    RayCaster caster(testContext());
    CastResult cast = caster.cast(renderer, {origins, directions, std::span<const double>(&tMax, 1)});
    for (float& t : cast.t)
        if (std::isinf(t)) t = -1.0f;
    return cast.t;
}

// The mesh with its vertices rounded to float, as the renderer packs them:
// the reference tests the triangles the device has.
Tris asFloat(const Tris& mesh) {
    Tris out;
    for (const Triangle& t : mesh)
        out.push_back({glm::dvec3(glm::vec3(t.v0)), glm::dvec3(glm::vec3(t.v1)), glm::dvec3(glm::vec3(t.v2))});
    return out;
}

// The brute-force reference for rays parallel to `dir`: every triangle that
// such a ray can hit, found by projecting the mesh onto the plane across
// dir (a grid of cells, each listing the triangles whose projected bounds,
// padded by far more than the projection's rounding, overlap it; a ray
// parallel to dir meets only triangles whose projection holds its own), then
// watertightTriangle on each.
class ParallelReference {
public:
    ParallelReference(const Tris& mesh, glm::dvec3 dir) : mesh_(mesh), dir_(dir) {
        glm::dvec3 n = glm::normalize(dir);
        u_ = glm::normalize(glm::cross(n, std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
        v_ = glm::cross(n, u_);
        std::vector<glm::dvec4> bounds(mesh.size());  // projected lo.xy, hi.xy
        lo_ = glm::dvec2(1e300);
        glm::dvec2 hi(-1e300);
        for (size_t k = 0; k < mesh.size(); ++k) {
            glm::dvec2 a = project(mesh[k].v0), b = project(mesh[k].v1), c = project(mesh[k].v2);
            glm::dvec2 l = glm::min(a, glm::min(b, c)), h = glm::max(a, glm::max(b, c));
            bounds[k] = {l, h};
            lo_ = glm::min(lo_, l);
            hi = glm::max(hi, h);
        }
        double extent = std::max(hi.x - lo_.x, hi.y - lo_.y) + 1e-300;
        pad_ = 1e-9 * (extent + glm::length(lo_));
        cells_ = std::clamp(int(std::sqrt(double(mesh.size())) / 2), 1, 512);
        cellSize_ = extent / cells_ * (1 + 1e-12);
        // Cell lists in one array (counts, prefix sums, then fill).
        std::vector<uint32_t> count(size_t(cells_) * cells_ + 1, 0);
        auto range = [&](const glm::dvec4& b, glm::ivec2& c0, glm::ivec2& c1) {
            c0 = cellOf(glm::dvec2(b.x, b.y) - pad_);
            c1 = cellOf(glm::dvec2(b.z, b.w) + pad_);
        };
        for (const glm::dvec4& b : bounds) {
            glm::ivec2 c0, c1;
            range(b, c0, c1);
            for (int y = c0.y; y <= c1.y; ++y)
                for (int x = c0.x; x <= c1.x; ++x) ++count[size_t(y) * cells_ + x + 1];
        }
        for (size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
        first_ = count;
        list_.resize(count.back());
        for (size_t k = 0; k < bounds.size(); ++k) {
            glm::ivec2 c0, c1;
            range(bounds[k], c0, c1);
            for (int y = c0.y; y <= c1.y; ++y)
                for (int x = c0.x; x <= c1.x; ++x) list_[count[size_t(y) * cells_ + x]++] = uint32_t(k);
        }
    }

    // The nearest hit distance along dir from `origin` (> 0), or -1.
    double nearest(glm::dvec3 origin) const {
        glm::dvec2 p = project(origin);
        glm::dvec2 cell = (p - lo_) / cellSize_;
        if (!(cell.x >= 0 && cell.y >= 0 && cell.x < cells_ && cell.y < cells_)) return -1;
        size_t c = size_t(cell.y) * cells_ + size_t(cell.x);
        double best = -1;
        for (uint32_t i = first_[c]; i < first_[c + 1]; ++i)
            if (auto h = watertightTriangle(origin, dir_, mesh_[list_[i]]); h && (best < 0 || h->t < best)) best = h->t;
        return best;
    }
    glm::dvec3 u() const { return u_; }
    glm::dvec3 v() const { return v_; }

private:
    glm::dvec2 project(glm::dvec3 p) const { return {glm::dot(p, u_), glm::dot(p, v_)}; }
    glm::ivec2 cellOf(glm::dvec2 p) const {
        glm::dvec2 c = glm::clamp((p - lo_) / cellSize_, glm::dvec2(0), glm::dvec2(cells_ - 1));
        return glm::ivec2(c);
    }
    const Tris& mesh_;
    glm::dvec3 dir_, u_, v_;
    glm::dvec2 lo_;
    double pad_ = 0, cellSize_ = 1;
    int cells_ = 1;
    std::vector<uint32_t> first_, list_;
};

// Rays sharing one direction, from one family.
struct RayBatch {
    const char* family;
    glm::vec3 dir;
    std::vector<glm::vec3> origins;
};

glm::vec3 randomDirection(std::mt19937& random) {
    std::normal_distribution<double> n;
    glm::dvec3 d;
    do d = {n(random), n(random), n(random)};
    while (glm::length(d) < 1e-3);
    return glm::normalize(glm::vec3(d));
}

// The batches of rays tried on `mesh` (float vertices), from outside its
// bounding sphere (centre c, radius r), `packed` its BVH as the renderer has it.
std::vector<RayBatch> outsideRays(const Tris& mesh, const std::vector<gpu::BvhNode>& nodes, uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const Triangle& t : mesh)
        for (glm::dvec3 p : {t.v0, t.v1, t.v2}) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    glm::dvec3 c = (lo + hi) / 2.0;
    double r = glm::length(hi - lo) / 2;
    auto behind = [&](glm::dvec3 target, glm::vec3 d) { return glm::vec3(target - 3 * r * glm::dvec3(d)); };
    std::vector<RayBatch> batches;
    auto frame = [](glm::vec3 d, glm::dvec3& u, glm::dvec3& v) {
        glm::dvec3 n(d);
        u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
        v = glm::cross(glm::normalize(n), u);
    };
    // At random over the mesh's silhouette disc and a little beyond it.
    for (int b = 0; b < 16; ++b) {
        RayBatch batch{"random", randomDirection(random), {}};
        glm::dvec3 u, v;
        frame(batch.dir, u, v);
        for (int k = 0; k < 1024; ++k)
            batch.origins.push_back(behind(c + 1.2 * r * ((2 * unit(random) - 1) * u + (2 * unit(random) - 1) * v), batch.dir));
        batches.push_back(std::move(batch));
    }
    // At vertices, and at points of edges (a tenth of them midpoints).
    for (int b = 0; b < 16; ++b) {
        bool vertices = b < 8;
        RayBatch batch{vertices ? "vertex" : "edge", randomDirection(random), {}};
        for (int k = 0; k < 512; ++k) {
            const Triangle& t = mesh[size_t(unit(random) * double(mesh.size())) % mesh.size()];
            glm::dvec3 corner[3] = {t.v0, t.v1, t.v2};
            int e = int(unit(random) * 3) % 3;
            double s = k % 10 == 0 ? 0.5 : 0.02 + 0.96 * unit(random);
            glm::dvec3 target = vertices ? corner[e] : corner[e] + s * (corner[(e + 1) % 3] - corner[e]);
            batch.origins.push_back(behind(target, batch.dir));
        }
        batches.push_back(std::move(batch));
    }
    // Along each axis both ways, over a 33 x 33 lattice across the bounds.
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {1.0, -1.0}) {
            RayBatch batch{"axis lattice", glm::vec3(0.0f), {}};
            batch.dir[axis] = float(sign);
            int a = (axis + 1) % 3, b = (axis + 2) % 3;
            for (int i = 0; i <= 32; ++i)
                for (int j = 0; j <= 32; ++j) {
                    glm::dvec3 p = c;
                    p[a] = lo[a] + (hi[a] - lo[a]) * i / 32.0;
                    p[b] = lo[b] + (hi[b] - lo[b]) * j / 32.0;
                    p[axis] = c[axis] - sign * 3 * r;
                    batch.origins.push_back(glm::vec3(p));
                }
            batches.push_back(std::move(batch));
        }
    // In the grid planes of the BVH: a child box's decoded bound on an axis,
    // held exactly by the ray (its direction 0 along that axis), through
    // a random point of the box's face.
    std::vector<std::pair<uint32_t, uint32_t>> children;  // node, child
    for (uint32_t n = 0; n < nodes.size(); ++n)
        for (uint32_t k = 0; k < gpu::kBvhWidth; ++k)
            if (((k < 4 ? nodes[n].childInfo0 : nodes[n].childInfo1) >> (8 * (k & 3)) & 0xffu) != 0)
                children.push_back({n, k});
    for (int b = 0; b < 16 && !children.empty(); ++b) {
        int axis = b % 3;
        glm::dvec3 d(randomDirection(random));
        d[axis] = 0;
        if (glm::length(d) < 1e-3) d[(axis + 1) % 3] = 1;
        RayBatch batch{"grid plane", glm::normalize(glm::vec3(d)), {}};
        batch.dir[axis] = 0.0f;
        for (int k = 0; k < 512; ++k) {
            auto [n, child] = children[size_t(unit(random) * double(children.size())) % children.size()];
            Aabb box = decodeChildBox(nodes[n], child);
            glm::dvec3 p;
            for (int i = 0; i < 3; ++i) p[i] = box.min[i] + unit(random) * (double(box.max[i]) - box.min[i]);
            p[axis] = k % 2 ? box.max[axis] : box.min[axis];
            glm::vec3 o = behind(p, batch.dir);
            o[axis] = float(p[axis]);
            batch.origins.push_back(o);
        }
        batches.push_back(std::move(batch));
    }
    return batches;
}

// Every ray of outsideRays(mesh) through `trace`, against the reference. A
// ray is decided when the reference gives the same answer for it and for
// four rays beside it (moved by eta across it, eta far above the
// rounding of the shader's float arithmetic): all hit, or all miss. Elsewhere
// (a silhouette within eta of it) either answer is right. A decided hit
// that the tracer misses, or hits at a t outside the five rays' range
// (widened by 1e-5 relative: a slip through the near side that hits the far
// side), or a decided miss that the tracer hits, is a failure.
void expectWatertightFromOutside(const char* name, const Tris& mesh, TracePath trace, uint32_t seed) {
    SCOPED_TRACE(name);
    Scene scene;
    Mesh m;
    m.triangles = mesh;
    Object o;
    o.shape = m;
    scene.objects.push_back(o);
    RenderSettings settings{.width = 8, .height = 8, .samplesPerPixel = 1, .maxDepth = 0, .trace = trace};
    Renderer renderer(testContext(), scene, settings);
    ASSERT_EQ(renderer.trace(), trace);
    std::vector<gpu::BvhNode> nodes = packScene(scene, settings).bvhNodes;
    std::vector<RayBatch> batches = outsideRays(mesh, nodes, seed);
    std::vector<FloatRay> rays;
    for (const RayBatch& b : batches)
        for (glm::vec3 origin : b.origins) rays.push_back({origin, b.dir});
    std::vector<float> got = castRays(renderer, rays);

    glm::dvec3 lo(1e300), hi(-1e300);
    for (const Triangle& t : mesh)
        for (glm::dvec3 p : {t.v0, t.v1, t.v2}) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    const double eta = 1e-5 * (glm::length((lo + hi) / 2.0) + 4 * glm::length(hi - lo));
    size_t next = 0, hits = 0, misses = 0, undecided = 0, failures = 0, aimed = 0;
    // Lavapipe's own triangle test (ray queries on a CPU device) is not
    // watertight at vertices: a few rays aimed exactly at a vertex of the
    // fine torus pass between its triangles and hit the far side (the
    // Vulkan specification's "Watertightness" asks a closed fan to report
    // at least one hit). That test is the driver's, not ours: such slips are
    // counted and printed, not failed, and only there; the ray must still
    // hit the mesh. Every other ray, and every ray on the BVH path, must
    // agree.
    const bool driverVertexSlipsAllowed = trace == TracePath::RayQuery && testContext().deviceInfo().type == "cpu";
    size_t driverSlips = 0;
    for (const RayBatch& b : batches) {
        ParallelReference reference(mesh, glm::dvec3(b.dir));
        const std::string family = b.family;
        if (family == "vertex" || family == "edge") aimed += b.origins.size();
        for (glm::vec3 origin : b.origins) {
            float t = got[next++];
            glm::dvec3 o(origin);
            double t0 = reference.nearest(o), tLo = t0, tHi = t0;
            int hitCount = t0 > 0;
            for (glm::dvec3 side : {reference.u(), -reference.u(), reference.v(), -reference.v()}) {
                double ts = reference.nearest(o + eta * side);
                hitCount += ts > 0;
                tLo = std::min(tLo, ts);
                tHi = std::max(tHi, ts);
            }
            if (hitCount != 0 && hitCount != 5) {
                ++undecided;
                continue;
            }
            bool hit = hitCount == 5;
            (hit ? hits : misses)++;
            bool ok = hit ? (t > 0 && t >= tLo * (1 - 1e-5) && t <= tHi * (1 + 1e-5)) : t < 0;
            if (!ok && hit && t > 0 && driverVertexSlipsAllowed && family == "vertex") {
                ++driverSlips;
                continue;
            }
            if (!ok && ++failures <= 10)
                ADD_FAILURE() << family << " ray from (" << origin.x << ", " << origin.y << ", " << origin.z
                              << ") along (" << b.dir.x << ", " << b.dir.y << ", " << b.dir.z << "): brute force "
                              << (hit ? "hits at t " + std::to_string(t0) : std::string("misses")) << ", the tracer "
                              << (t > 0 ? "hits at t " + std::to_string(t) : std::string("misses"));
        }
    }
    EXPECT_EQ(failures, 0u) << "of " << rays.size() << " rays";
    if (driverSlips > 0)
        std::printf("[ watertight ] %s: %zu rays aimed at vertices slipped through the driver's triangle test to the "
                    "far side\n", name, driverSlips);
    // The comparison must have something to decide: most rays are clear
    // hits or misses, and there are both. Rays aimed at vertices and edges
    // may lie on the silhouette (on a cube most do); of the others at most
    // one in 20 is undecided.
    EXPECT_GT(hits, rays.size() / 4);
    EXPECT_GT(misses, rays.size() / 50);
    EXPECT_LT(undecided, aimed + (rays.size() - aimed) / 20);
    std::printf("[ watertight ] %s, %zu triangles: %zu rays, %zu hits, %zu misses, %zu undecided\n", name, mesh.size(),
                rays.size(), hits, misses, undecided);
}

// The meshes seen from outside: the cube at round numbers and moved off
// them, a subdivided sphere, a coarse and a fine torus.
void expectMeshesWatertightFromOutside(TracePath trace) {
    expectWatertightFromOutside("unit cube", kCube, trace, 1);
    expectWatertightFromOutside("moved cube", asFloat(oddCube()), trace, 2);
    expectWatertightFromOutside("icosphere", asFloat(icosphere({0.3, -0.2, 0.1}, 1.0, kOutsideSphereLevels)), trace, 3);
    expectWatertightFromOutside("torus", asFloat(torus(2.0, 0.5, 64, 32)), trace, 4);
    expectWatertightFromOutside("fine torus", asFloat(torus(2.0, 0.7, 256, 128)), trace, 5);
}

TEST(Watertight, ClosedMeshesSeenFromOutsideMatchBruteForceThroughTheBvh) {
    expectMeshesWatertightFromOutside(TracePath::Bvh);
}

TEST(Watertight, ClosedMeshesSeenFromOutsideMatchBruteForceThroughRayQueries) {
    if (!testContext().deviceInfo().rayQuery)
        GTEST_SKIP() << "device '" << testContext().deviceInfo().name << "' lacks VK_KHR_ray_query";
    expectMeshesWatertightFromOutside(TracePath::RayQuery);
}

}  // namespace
}  // namespace whitted::test

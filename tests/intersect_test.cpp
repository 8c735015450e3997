// The shader's intersection functions (run on the device through
// tests/shaders/intersect_test.comp) against independent double-precision
// CPU evaluations, on many seeded random rays per shape.
#include <cstdint>

#include "intersect_test_comp.h"  // kIntersectTestCompSpv
#include "shapes/shapes.h"
#include "test_support.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"

#include <cstring>
#include <functional>
#include <numbers>
#include <optional>
#include <random>

namespace whitted::test {
namespace {

struct CpuHit {
    double t;
    glm::dvec3 normal;
};
struct Ray64 {
    glm::dvec3 origin, dir;
};

// ---- Double-precision references (textbook forms, not the shader's) ------

std::optional<CpuHit> cpuSphere(const Sphere& s, const Ray64& r) {
    glm::dvec3 f = r.origin - s.center;
    double b = glm::dot(f, r.dir), c = glm::dot(f, f) - s.radius * s.radius;
    double disc = b * b - c;
    if (disc < 0) return std::nullopt;
    for (double t : {-b - std::sqrt(disc), -b + std::sqrt(disc)})
        if (t > 0) return CpuHit{t, (r.origin + t * r.dir - s.center) / s.radius};
    return std::nullopt;
}

std::optional<CpuHit> cpuPlane(const Plane& p, const Ray64& r) {
    double denom = glm::dot(p.normal, r.dir);
    if (denom == 0) return std::nullopt;
    double t = glm::dot(p.point - r.origin, p.normal) / denom;
    if (t <= 0) return std::nullopt;
    return CpuHit{t, p.normal};
}

// Möller–Trumbore.
std::optional<CpuHit> cpuTriangle(const Triangle& tri, const Ray64& r) {
    glm::dvec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
    glm::dvec3 p = glm::cross(r.dir, e2);
    double det = glm::dot(e1, p);
    if (det == 0) return std::nullopt;
    glm::dvec3 s = r.origin - tri.v0;
    double u = glm::dot(s, p) / det;
    glm::dvec3 q = glm::cross(s, e1);
    double v = glm::dot(r.dir, q) / det;
    if (u < 0 || v < 0 || u + v > 1) return std::nullopt;
    double t = glm::dot(e2, q) / det;
    if (t <= 0) return std::nullopt;
    return CpuHit{t, glm::normalize(glm::cross(e1, e2))};
}

std::optional<CpuHit> cpuBox(const Box& b, const Ray64& r) {
    std::optional<CpuHit> best;
    // Each of the six faces as a rectangle.
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            if (r.dir[axis] == 0) continue;
            double plane = side ? b.max[axis] : b.min[axis];
            double t = (plane - r.origin[axis]) / r.dir[axis];
            if (t <= 0 || (best && t >= best->t)) continue;
            glm::dvec3 p = r.origin + t * r.dir;
            bool inside = true;
            for (int k = 0; k < 3; ++k)
                if (k != axis && (p[k] < b.min[k] || p[k] > b.max[k])) inside = false;
            if (!inside) continue;
            glm::dvec3 n(0);
            n[axis] = side ? 1 : -1;
            best = CpuHit{t, n};
        }
    return best;
}

std::optional<CpuHit> cpuCylinder(const Cylinder& c, const Ray64& r) {
    // Local frame with the axis as z.
    glm::dvec3 w = glm::normalize(c.axis);
    glm::dvec3 u = glm::normalize(glm::cross(std::abs(w.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0), w));
    glm::dvec3 v = glm::cross(w, u);
    glm::dvec3 o = r.origin - c.base;
    glm::dvec3 lo(glm::dot(o, u), glm::dot(o, v), glm::dot(o, w));
    glm::dvec3 ld(glm::dot(r.dir, u), glm::dot(r.dir, v), glm::dot(r.dir, w));
    std::optional<CpuHit> best;
    auto consider = [&](double t, glm::dvec3 localNormal) {
        if (t > 0 && (!best || t < best->t))
            best = CpuHit{t, localNormal.x * u + localNormal.y * v + localNormal.z * w};
    };
    double a = ld.x * ld.x + ld.y * ld.y;
    if (a > 0) {
        double b = lo.x * ld.x + lo.y * ld.y, cc = lo.x * lo.x + lo.y * lo.y - c.radius * c.radius;
        double disc = b * b - a * cc;
        if (disc >= 0)
            for (double t : {(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a}) {
                glm::dvec3 p = lo + t * ld;
                if (p.z >= 0 && p.z <= c.height) consider(t, glm::dvec3(p.x, p.y, 0) / c.radius);
            }
    }
    if (ld.z != 0)
        for (double h : {0.0, c.height}) {
            double t = (h - lo.z) / ld.z;
            glm::dvec3 p = lo + t * ld;
            if (p.x * p.x + p.y * p.y <= c.radius * c.radius) consider(t, glm::dvec3(0, 0, h == 0 ? -1 : 1));
        }
    return best;
}

// ---- Running the shader's functions ---------------------------------------

struct GpuHit {
    bool hit;
    float t;
    glm::vec3 normal;
    float selfHit;
};

std::vector<GpuHit> gpuIntersect(const gpu::Primitive& prim, const std::vector<Ray64>& rays) {
    VulkanContext& ctx = testContext();
    uint32_t before = ctx.validationMessageCount();
    const vk::DescriptorType types[] = {vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer,
                                        vk::DescriptorType::eStorageBuffer};
    ComputePipeline pipeline = createComputePipeline(ctx, kIntersectTestCompSpv, types, sizeof(uint32_t));
    std::vector<glm::vec4> rayData;
    for (const Ray64& r : rays) {
        rayData.push_back(glm::vec4(glm::vec3(r.origin), 0));
        rayData.push_back(glm::vec4(glm::vec3(r.dir), 0));
    }
    auto usage = vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferSrc;
    Buffer primBuf = createDeviceBuffer(ctx, &prim, sizeof prim, usage);
    Buffer rayBuf = createDeviceBuffer(ctx, rayData.data(), rayData.size() * sizeof(glm::vec4), usage);
    Buffer resultBuf = createDeviceBuffer(ctx, nullptr, rayData.size() * sizeof(glm::vec4), usage);

    vk::DescriptorPoolSize size{vk::DescriptorType::eStorageBuffer, 3};
    vk::raii::DescriptorPool pool(ctx.device, {.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                               .maxSets = 1, .poolSizeCount = 1, .pPoolSizes = &size});
    vk::DescriptorSetLayout layout = *pipeline.setLayout;
    vk::raii::DescriptorSet set = std::move(
        vk::raii::DescriptorSets(ctx.device, {.descriptorPool = *pool, .descriptorSetCount = 1, .pSetLayouts = &layout})
            .front());
    vk::DescriptorBufferInfo infos[] = {{*primBuf.buffer, 0, VK_WHOLE_SIZE},
                                        {*rayBuf.buffer, 0, VK_WHOLE_SIZE},
                                        {*resultBuf.buffer, 0, VK_WHOLE_SIZE}};
    std::vector<vk::WriteDescriptorSet> writes;
    for (uint32_t i = 0; i < 3; ++i)
        writes.push_back({.dstSet = *set, .dstBinding = i, .descriptorCount = 1,
                          .descriptorType = vk::DescriptorType::eStorageBuffer, .pBufferInfo = &infos[i]});
    ctx.device.updateDescriptorSets(writes, nullptr);

    uint32_t count = uint32_t(rays.size());
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
        cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline.pipeline);
        cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline.layout, 0, *set, nullptr);
        cmd.pushConstants<uint32_t>(*pipeline.layout, vk::ShaderStageFlagBits::eCompute, 0, count);
        cmd.dispatch((count + 63) / 64, 1, 1);
    });
    std::vector<glm::vec4> out(rayData.size());
    readBuffer(ctx, resultBuf, out.data(), out.size() * sizeof(glm::vec4));
    EXPECT_EQ(ctx.validationMessageCount(), before);

    std::vector<GpuHit> hits;
    for (uint32_t i = 0; i < count; ++i)
        hits.push_back({out[2 * i].w >= 0, out[2 * i].w, glm::vec3(out[2 * i]), out[2 * i + 1].x});
    return hits;
}

// ---- Property test ----------------------------------------------------------

using CpuIntersect = std::function<std::optional<CpuHit>(const Ray64&)>;

// Random rays from a box around the shape towards random points near it.
// A ray counts only when the CPU answer is stable under tiny perturbations
// of its origin (otherwise it grazes an edge or a silhouette, where float
// and double may legitimately disagree).
void checkShape(const gpu::Primitive& prim, const CpuIntersect& cpu, glm::dvec3 lo, glm::dvec3 hi, int rayCount = 4000) {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto inBox = [&](glm::dvec3 a, glm::dvec3 b) {
        return glm::dvec3(a.x + (b.x - a.x) * unit(rng), a.y + (b.y - a.y) * unit(rng), a.z + (b.z - a.z) * unit(rng));
    };
    glm::dvec3 center = 0.5 * (lo + hi), extent = hi - lo;
    std::vector<Ray64> rays;
    for (int i = 0; i < rayCount; ++i) {
        glm::dvec3 origin = inBox(center - 2.0 * extent, center + 2.0 * extent);
        glm::dvec3 target = inBox(center - 0.6 * extent, center + 0.6 * extent);
        if (glm::length(target - origin) < 1e-6) continue;
        rays.push_back({origin, glm::normalize(target - origin)});
    }
    std::vector<GpuHit> gpu = gpuIntersect(prim, rays);

    int compared = 0, hits = 0;
    const double eps = 1e-4 * glm::length(extent);
    for (size_t i = 0; i < rays.size(); ++i) {
        std::optional<CpuHit> want = cpu(rays[i]);
        bool stable = true;
        for (int k = 0; k < 6 && stable; ++k) {
            Ray64 jittered = rays[i];
            jittered.origin[k / 2] += (k % 2 ? eps : -eps);
            std::optional<CpuHit> other = cpu(jittered);
            stable = other.has_value() == want.has_value() &&
                     (!want || glm::dot(other->normal, want->normal) > 0.999);
        }
        if (!stable) continue;
        ++compared;
        ASSERT_EQ(gpu[i].hit, want.has_value()) << "ray " << i << " hit/miss disagrees";
        EXPECT_EQ(gpu[i].selfHit, 0.0f) << "ray " << i << " re-hits its own surface after offsetting";
        if (!want) continue;
        ++hits;
        EXPECT_NEAR(gpu[i].t, want->t, 1e-4 * std::max(1.0, want->t)) << "ray " << i;
        EXPECT_GT(glm::dot(glm::dvec3(gpu[i].normal), want->normal), 0.9999) << "ray " << i;
    }
    EXPECT_GT(compared, rayCount * 9 / 10);
    EXPECT_GT(hits, rayCount / 5);
}

TEST(Intersect, SphereMatchesDoublePrecision) {
    Sphere s{{0.5, -1, 2}, 1.3};
    checkShape(packSphere(s, 0), [&](const Ray64& r) { return cpuSphere(s, r); }, s.center - 1.3, s.center + 1.3);
}

TEST(Intersect, FarSphereMatchesDoublePrecision) {
    Sphere s{{300, 200, -500}, 40};
    checkShape(packSphere(s, 0), [&](const Ray64& r) { return cpuSphere(s, r); }, s.center - 40.0, s.center + 40.0);
}

TEST(Intersect, CylinderMatchesDoublePrecision) {
    Cylinder c{{0.2, -0.5, 0.1}, glm::normalize(glm::dvec3(0.3, 1, -0.2)), 0.7, 2.0};
    checkShape(packCylinder(c, 0), [&](const Ray64& r) { return cpuCylinder(c, r); }, glm::dvec3(-1.5, -1, -1.5),
               glm::dvec3(1.5, 2, 1.5));
}

TEST(Intersect, VerticalCylinderMatchesDoublePrecision) {
    Cylinder c{{0, 0, 0}, {0, 1, 0}, 0.5, 1.0};
    checkShape(packCylinder(c, 0), [&](const Ray64& r) { return cpuCylinder(c, r); }, glm::dvec3(-0.5, 0, -0.5),
               glm::dvec3(0.5, 1, 0.5));
}

TEST(Intersect, BoxMatchesDoublePrecision) {
    Box b{{-1, 0, -0.5}, {0.5, 2, 1.5}};
    checkShape(packBox(b, 0), [&](const Ray64& r) { return cpuBox(b, r); }, b.min, b.max);
}

TEST(Intersect, TriangleMatchesDoublePrecision) {
    Triangle t{{-1, 0, 0}, {1, 0.2, -0.3}, {0, 1.5, 0.4}};
    checkShape(packTriangle(t, 0), [&](const Ray64& r) { return cpuTriangle(t, r); }, glm::dvec3(-1, 0, -0.3),
               glm::dvec3(1, 1.5, 0.4));
}

TEST(Intersect, PlaneMatchesDoublePrecision) {
    Plane p{{0, -1, 0}, glm::normalize(glm::dvec3(0.1, 1, 0.2))};
    checkShape(packPlane(p, 0), [&](const Ray64& r) { return cpuPlane(p, r); }, glm::dvec3(-2, -1.5, -2),
               glm::dvec3(2, -0.5, 2));
}

// Rays aimed exactly at points of a surface's edge (a cylinder's cap rim, a
// box's edge) from a side where both surfaces meeting there face the ray
// enter the solid right at that point: each must hit, at the distance to
// the point. A miss is a hole at a crease (light leaking through, the
// seed's bugs); a far hit would be a phantom. `aim` returns the edge point
// and the outward normals of the two faces meeting there.
struct EdgePoint {
    glm::dvec3 point, normal1, normal2;
};
void checkEdgeRays(const gpu::Primitive& prim, const std::function<EdgePoint(double)>& aim, const char* what) {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::vector<Ray64> rays;
    std::vector<double> distances;
    for (int i = 0; i < 4000; ++i) {
        EdgePoint e = aim(unit(rng));
        // A direction back towards the point from where both faces are
        // seen from the front, at any angle, grazing ones included.
        glm::dvec3 outward = glm::normalize(e.normal1 + e.normal2);
        glm::dvec3 away = glm::normalize(outward + 0.9 * glm::dvec3(normal(rng), normal(rng), normal(rng)));
        if (glm::dot(away, e.normal1) <= 1e-3 || glm::dot(away, e.normal2) <= 1e-3) continue;
        glm::dvec3 point = e.point;
        double distance = 0.5 + 5.0 * unit(rng);
        rays.push_back({point + distance * away, -away});
        distances.push_back(distance);
    }
    std::vector<GpuHit> h = gpuIntersect(prim, rays);
    int misses = 0, wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        if (!h[i].hit) ++misses;
        else if (std::abs(h[i].t - distances[i]) > 1e-4 * distances[i]) ++wrong;
    }
    ASSERT_GT(rays.size(), 1000u);
    EXPECT_EQ(misses, 0) << what << ": rays aimed at the edge that miss";
    EXPECT_EQ(wrong, 0) << what << ": rays aimed at the edge that hit elsewhere";
}

TEST(Intersect, RaysAtACylinderCapRimHitIt) {
    Cylinder c{{0.2, -0.5, 0.1}, glm::normalize(glm::dvec3(0.3, 1, -0.2)), 0.7, 2.0};
    glm::dvec3 u = glm::normalize(glm::cross(c.axis, glm::dvec3(1, 0, 0))), v = glm::cross(c.axis, u);
    for (bool top : {false, true})
        checkEdgeRays(packCylinder(c, 0), [&](double f) {
            double phi = 2 * std::numbers::pi * f;
            glm::dvec3 radial = std::cos(phi) * u + std::sin(phi) * v;
            glm::dvec3 capNormal = top ? c.axis : -c.axis;
            return EdgePoint{c.base + (top ? c.height : 0.0) * c.axis + c.radius * radial, radial, capNormal};
        }, top ? "top rim" : "bottom rim");
}

TEST(Intersect, RaysAtABoxEdgeHitIt) {
    Box b{{-1, 0, -0.5}, {0.5, 2, 1.5}};
    // The edge along x at y = max, z = max; the edge along z at x = min, y = min.
    checkEdgeRays(packBox(b, 0), [&](double f) {
        return EdgePoint{glm::dvec3(glm::mix(b.min.x, b.max.x, f), b.max.y, b.max.z), {0, 1, 0}, {0, 0, 1}};
    }, "x edge");
    checkEdgeRays(packBox(b, 0), [&](double f) {
        return EdgePoint{glm::dvec3(b.min.x, b.min.y, glm::mix(b.min.z, b.max.z, f)), {-1, 0, 0}, {0, -1, 0}};
    }, "z edge");
}

// A plane seen at shallow angles, down to a thousandth of a radian, is hit
// where it should be, and a ray leaving the hit point does not hit it again.
TEST(Intersect, PlaneAtGrazingAnglesIsHit) {
    Plane p{{0.3, -1, 0.2}, glm::normalize(glm::dvec3(0.1, 1, 0.2))};
    glm::dvec3 u = glm::normalize(glm::cross(p.normal, glm::dvec3(1, 0, 0))), v = glm::cross(p.normal, u);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Ray64> rays;
    std::vector<glm::dvec3> targets;
    for (int i = 0; i < 2000; ++i) {
        double elevation = std::pow(10.0, -3.0 + 2.0 * unit(rng));  // 0.001 .. 0.1 rad
        double phi = 2 * std::numbers::pi * unit(rng);
        glm::dvec3 along = std::cos(phi) * u + std::sin(phi) * v;
        glm::dvec3 dir = glm::normalize(std::cos(elevation) * along - std::sin(elevation) * p.normal);
        glm::dvec3 target = p.point + 10.0 * (unit(rng) - 0.5) * u + 10.0 * (unit(rng) - 0.5) * v;
        rays.push_back({target - 20.0 * dir, dir});
        targets.push_back(target);
    }
    std::vector<GpuHit> h = gpuIntersect(packPlane(p, 0), rays);
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(h[i].hit) << "ray " << i;
        glm::dvec3 hitPoint = rays[i].origin + double(h[i].t) * rays[i].dir;
        // A float plane seen at elevation e places the hit within about
        // float rounding / sin(e) along the ray; check the point lies on the
        // plane instead, which is what shading and shadows depend on.
        EXPECT_NEAR(glm::dot(hitPoint - p.point, p.normal), 0.0, 1e-5) << "ray " << i;
        EXPECT_EQ(h[i].selfHit, 0.0f) << "ray " << i << " re-hits the plane after offsetting";
    }
}

// Rays aimed exactly at the edge two triangles share must hit at least one
// of them: no ray slips through a mesh (the seed's holes seen by shadow
// rays). Uses consistently wound, non-axis-aligned triangles and rays from
// all sides, except where the edge is a silhouette for the ray (the eye on
// the front of one triangle and the back of the other): there the triangles
// fold over each other in projection and a grazing ray rightly hits neither.
TEST(Intersect, SharedEdgeIsWatertight) {
    glm::dvec3 a(-0.731, 0.112, -2.37), b(0.913, 0.871, -1.93), c(-0.2, 1.9, -2.8), d(0.4, -1.3, -1.6);
    Triangle t1{a, b, c}, t2{b, a, d};
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Ray64> rays;
    for (int i = 0; i < 4000; ++i) {
        glm::dvec3 onEdge = glm::mix(a, b, unit(rng));
        glm::dvec3 origin(unit(rng) * 8 - 4, unit(rng) * 8 - 4, unit(rng) * 8 - 4);
        double side1 = glm::dot(glm::cross(b - a, c - a), origin - a);
        double side2 = glm::dot(glm::cross(a - b, d - b), origin - a);
        if ((side1 > 0) != (side2 > 0)) continue;  // silhouette edge
        rays.push_back({origin, glm::normalize(onEdge - origin)});
    }
    std::vector<GpuHit> h1 = gpuIntersect(packTriangle(t1, 0), rays);
    std::vector<GpuHit> h2 = gpuIntersect(packTriangle(t2, 0), rays);
    ASSERT_GT(rays.size(), 1000u);
    int holes = 0;
    for (size_t i = 0; i < rays.size(); ++i)
        if (!h1[i].hit && !h2[i].hit) ++holes;
    EXPECT_EQ(holes, 0) << "rays through the shared edge that hit neither triangle";
}

// A ray that starts inside a cylinder leaves through the side or a cap and
// never reports a cap's plane outside the radius (the seed's phantom
// cylinder shadows): check rays from inside along many directions.
TEST(Intersect, CylinderFromInsideHitsItsOwnSurface) {
    Cylinder c{{0, 0, 0}, {0, 1, 0}, 0.5, 1.0};
    std::mt19937 rng(7);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::vector<Ray64> rays;
    for (int i = 0; i < 2000; ++i)
        rays.push_back({glm::dvec3(0.1, 0.4, -0.2), glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)))});
    std::vector<GpuHit> h = gpuIntersect(packCylinder(c, 0), rays);
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(h[i].hit) << "ray " << i << " escaped a closed cylinder";
        glm::dvec3 p = rays[i].origin + double(h[i].t) * rays[i].dir;
        double radial = std::hypot(p.x, p.z);
        EXPECT_LE(radial, 0.5 + 1e-5);
        EXPECT_GE(p.y, -1e-5);
        EXPECT_LE(p.y, 1.0 + 1e-5);
        std::optional<CpuHit> want = cpuCylinder(c, rays[i]);
        ASSERT_TRUE(want.has_value());
        EXPECT_NEAR(h[i].t, want->t, 1e-4);
    }
}

}  // namespace
}  // namespace whitted::test

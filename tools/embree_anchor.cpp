// whitted_embree_anchor: the benchmark's limit anchor. Traces whitted's camera
// rays and shadow rays of a scene with Embree 3's packet API on every core
// and prints rays per second as JSON (tools/bench/runners.py runs it beside
// whitted on the same scene and size; tools/README.md, "Embree anchor").
//
//   whitted_embree_anchor SCENE.xml [--width W] [--height H] [--spp N] [--seed S]
//                         [--threads T] [--repeats R] [--packet 4|8|16|best]
//
// The rays are whitted's own: the camera of shaders/camera.glsl through the
// sample positions of shaders/sampling.glsl (one ray through each pixel's
// centre at 1 sample per pixel, Kensler's correlated multi-jittered pattern
// above), and from each camera ray's hit one shadow ray to each light that
// faces the surface (shaders/shading.glsl's rule, from the point moved off
// the surface as shaders/ray.glsl's offsetRay does). Secondary rays are not
// traced: the anchor is for primary plus shadow rays.
//
// Shapes: triangles and meshes (RTC_GEOMETRY_TYPE_TRIANGLE), boxes (12
// triangles each: the same surface), spheres (RTC_GEOMETRY_TYPE_SPHERE_POINT),
// and planes, unbounded, tested analytically per ray after Embree as whitted
// tests them beside its BVH. A scene with cylinders or csg objects is not
// traced: the JSON says "supported": false and why.
//
// Exit statuses as whitted's: 0 success (also for an unsupported scene),
// 1 failure, 2 bad input. This program is for the benchmark only; whitted
// itself does not link Embree.
#include "device_types.h"  // hashPcg, the shader's pixel seed
#include "scene/scene_loader.h"

#include <CLI/CLI.hpp>
#include <embree3/rtcore.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace whitted;

// ---- whitted's sample pattern (shaders/sampling.glsl), bit for bit ----

uint32_t cmjPermute(uint32_t i, uint32_t l, uint32_t p) {
    uint32_t w = l - 1u;
    w |= w >> 1; w |= w >> 2; w |= w >> 4; w |= w >> 8; w |= w >> 16;
    do {
        i ^= p; i *= 0xe170893du; i ^= p >> 16; i ^= (i & w) >> 4;
        i ^= p >> 8; i *= 0x0929eb3fu; i ^= p >> 23; i ^= (i & w) >> 1;
        i *= 1u | p >> 27; i *= 0x6935fa69u; i ^= (i & w) >> 11;
        i *= 0x74dcb303u; i ^= (i & w) >> 2; i *= 0x9e501cc3u;
        i ^= (i & w) >> 2; i *= 0xc860a3dfu; i &= w; i ^= i >> 5;
    } while (i >= l);
    return (i + p) % l;
}

float cmjRandFloat(uint32_t i, uint32_t p) {
    i ^= p; i ^= i >> 17; i ^= i >> 10; i *= 0xb36534e5u; i ^= i >> 12;
    i ^= i >> 21; i *= 0x93fc4795u; i ^= 0xdf6e307fu; i ^= i >> 17;
    i *= 1u | p >> 18;
    return float(i) * (1.0f / 4294967808.0f);
}

glm::vec2 cmjSample(uint32_t s, uint32_t n, uint32_t p) {
    uint32_t m = uint32_t(std::sqrt(float(n)));
    uint32_t rows = (n + m - 1u) / m;
    s = cmjPermute(s, n, p * 0x51633e2du);
    uint32_t sx = cmjPermute(s % m, m, p * 0x68bc21ebu);
    uint32_t sy = cmjPermute(s / m, rows, p * 0x02e5be93u);
    float jx = cmjRandFloat(s, p * 0x967a889bu);
    float jy = cmjRandFloat(s, p * 0x368cc8b7u);
    return {(float(sx) + (float(sy) + jx) / float(rows)) / float(m), (float(s) + jy) / float(n)};
}

glm::vec2 pixelSampleOffset(uint32_t s, uint32_t n, uint32_t pixelSeed) {
    if (n == 1u) return glm::vec2(0.5f);
    return cmjSample(s, n, pixelSeed);
}

// shaders/ray.glsl's offsetRay (Wächter and Binder 2019).
glm::vec3 offsetRay(glm::vec3 p, glm::vec3 n) {
    const float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f, kIntScale = 256.0f;
    glm::vec3 out;
    for (int k = 0; k < 3; ++k) {
        int offsetInt = int(kIntScale * n[k]);
        int bits = std::bit_cast<int>(p[k]) + (p[k] < 0.0f ? -offsetInt : offsetInt);
        out[k] = std::abs(p[k]) < kOrigin ? p[k] + kFloatScale * n[k] : std::bit_cast<float>(bits);
    }
    return out;
}

// The camera frame of host/render/gpu_scene.cpp's packCamera, in float as the shader has it.
struct CameraFrame {
    glm::vec3 eye, forward, right, up;
};

CameraFrame cameraFrame(const Camera& camera, int width, int height) {
    glm::dvec3 forward = glm::normalize(camera.windowCenter - camera.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::dvec3 up = glm::cross(right, forward);
    double tanHalf = std::tan(glm::radians(camera.verticalFovDegrees) / 2.0);
    double aspect = double(width) / double(height);
    return {glm::vec3(camera.eye), glm::vec3(forward), glm::vec3(right * tanHalf * aspect), glm::vec3(up * tanHalf)};
}

// shaders/camera.glsl's generateCameraRay: its direction.
glm::vec3 cameraDirection(const CameraFrame& c, glm::vec2 pixel, glm::vec2 size) {
    glm::vec2 ndc(2.0f * pixel.x / size.x - 1.0f, 1.0f - 2.0f * pixel.y / size.y);
    return glm::normalize(c.forward + ndc.x * c.right + ndc.y * c.up);
}

// ---- the scene as Embree geometry ----

struct Surface {
    bool lit = false;  // kd > 0 or ks > 0: the shader traces shadow rays from it (nextShadowRay)
};

struct PlaneShape {
    glm::vec3 point, normal;
    uint32_t surface;
};

struct AnchorLight {
    glm::vec3 position;  // point and spot lights
    glm::vec3 toLight;   // directional: the unit direction towards the light
    bool directional;
};

struct AnchorScene {
    RTCScene scene = nullptr;
    std::vector<Surface> surfaces;            // per object
    std::vector<uint32_t> triangleSurface;    // per triangle of the triangle geometry
    std::vector<std::array<glm::vec3, 3>> triangleNormals;  // per triangle; zero: flat
    std::vector<uint32_t> sphereSurface;
    std::vector<PlaneShape> planes;
    std::vector<AnchorLight> lights;
    unsigned triangleGeometry = RTC_INVALID_GEOMETRY_ID, sphereGeometry = RTC_INVALID_GEOMETRY_ID;
    size_t triangles = 0, spheres = 0, boxes = 0;
    std::set<std::string> unsupported;
};

void addTriangle(AnchorScene& a, std::vector<glm::vec3>& vertices, glm::dvec3 v0, glm::dvec3 v1, glm::dvec3 v2,
                 uint32_t surface, const std::array<glm::vec3, 3>& normals) {
    vertices.push_back(glm::vec3(v0));
    vertices.push_back(glm::vec3(v1));
    vertices.push_back(glm::vec3(v2));
    a.triangleSurface.push_back(surface);
    a.triangleNormals.push_back(normals);
}

AnchorScene buildScene(RTCDevice device, const Scene& scene) {
    AnchorScene a;
    std::vector<glm::vec3> vertices;
    std::vector<glm::vec4> spheres;
    const std::array<glm::vec3, 3> flat{glm::vec3(0), glm::vec3(0), glm::vec3(0)};
    for (const Object& object : scene.objects) {
        uint32_t surface = uint32_t(a.surfaces.size());
        a.surfaces.push_back({object.material.diffuse > 0.0 || object.material.specular > 0.0});
        if (const auto* t = std::get_if<Triangle>(&object.shape)) {
            addTriangle(a, vertices, t->v0, t->v1, t->v2, surface, flat);
        } else if (const auto* mesh = std::get_if<Mesh>(&object.shape)) {
            for (size_t k = 0; k < mesh->triangles.size(); ++k) {
                const Triangle& t = mesh->triangles[k];
                std::array<glm::vec3, 3> normals = flat;
                if (!mesh->normals.empty())
                    normals = {glm::vec3(mesh->normals[k][0]), glm::vec3(mesh->normals[k][1]),
                               glm::vec3(mesh->normals[k][2])};
                addTriangle(a, vertices, t.v0, t.v1, t.v2, surface, normals);
            }
        } else if (const auto* box = std::get_if<Box>(&object.shape)) {
            // The box's six faces as twelve triangles.
            glm::dvec3 lo = box->min, hi = box->max;
            auto corner = [&](int i) { return glm::dvec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z); };
            const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
            for (const auto& f : faces) {
                addTriangle(a, vertices, corner(f[0]), corner(f[1]), corner(f[2]), surface, flat);
                addTriangle(a, vertices, corner(f[0]), corner(f[2]), corner(f[3]), surface, flat);
            }
            ++a.boxes;
        } else if (const auto* sphere = std::get_if<Sphere>(&object.shape)) {
            spheres.push_back(glm::vec4(glm::vec3(sphere->center), float(sphere->radius)));
            a.sphereSurface.push_back(surface);
        } else if (const auto* plane = std::get_if<Plane>(&object.shape)) {
            a.planes.push_back({glm::vec3(plane->point), glm::vec3(plane->normal), surface});
        } else if (std::holds_alternative<Cylinder>(object.shape)) {
            a.unsupported.insert("cylinder");
        } else {
            a.unsupported.insert("csg");
        }
    }
    for (const Light& light : scene.lights) {
        bool directional = light.type == Light::Type::Directional;
        a.lights.push_back({glm::vec3(light.position), glm::vec3(-light.direction), directional});
    }
    if (!a.unsupported.empty()) return a;

    a.scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(a.scene, RTC_BUILD_QUALITY_HIGH);
    a.triangles = vertices.size() / 3;
    if (a.triangles) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
        std::memcpy(v, vertices.data(), vertices.size() * sizeof(glm::vec3));
        auto* index = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), a.triangles));
        for (uint32_t k = 0; k < 3 * a.triangles; ++k) index[k] = k;
        rtcCommitGeometry(g);
        a.triangleGeometry = rtcAttachGeometry(a.scene, g);
        rtcReleaseGeometry(g);
    }
    a.spheres = spheres.size();
    if (a.spheres) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
        std::memcpy(v, spheres.data(), spheres.size() * sizeof(glm::vec4));
        rtcCommitGeometry(g);
        a.sphereGeometry = rtcAttachGeometry(a.scene, g);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(a.scene);
    return a;
}

// The nearest plane crossing in (0, tMax) of a ray, or tMax; sets *plane.
float nearestPlane(const AnchorScene& a, glm::vec3 o, glm::vec3 d, float tMax, int* plane) {
    *plane = -1;
    for (size_t k = 0; k < a.planes.size(); ++k) {
        const PlaneShape& p = a.planes[k];
        float denom = glm::dot(d, p.normal);
        if (denom == 0.0f) continue;
        float t = glm::dot(p.point - o, p.normal) / denom;
        if (t > 0.0f && t < tMax) {
            tMax = t;
            *plane = int(k);
        }
    }
    return tMax;
}

// ---- tracing ----

struct Counts {
    uint64_t camera = 0, shadow = 0;
};

struct Settings {
    int width = 0, height = 0;
    uint32_t spp = 1, seed = 0;
    bool shadows = true;
};

template <int N> struct Packet;
template <> struct Packet<4> {
    using Hit = RTCRayHit4; using Ray = RTCRay4;
    static constexpr int kW = 2;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, Hit* h) { rtcIntersect4(v, s, c, h); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded4(v, s, c, r); }
};
template <> struct Packet<8> {
    using Hit = RTCRayHit8; using Ray = RTCRay8;
    static constexpr int kW = 4;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, Hit* h) { rtcIntersect8(v, s, c, h); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded8(v, s, c, r); }
};
template <> struct Packet<16> {
    using Hit = RTCRayHit16; using Ray = RTCRay16;
    static constexpr int kW = 4;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, Hit* h) { rtcIntersect16(v, s, c, h); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded16(v, s, c, r); }
};

// Fills one packet of camera rays: a kW x N/kW block of pixels, one sample each.
template <int N>
void fillCameraPacket(const CameraFrame& camera, const Settings& s, int x0, int y0, uint32_t sample, int* valid,
                      typename Packet<N>::Hit& rh, Counts& counts) {
    constexpr int kW = Packet<N>::kW;
    glm::vec2 size(float(s.width), float(s.height));
    for (int i = 0; i < N; ++i) {
        int x = x0 + i % kW, y = y0 + i / kW;
        valid[i] = x < s.width && y < s.height ? -1 : 0;
        glm::vec3 d(0, 0, 1);
        if (valid[i]) {
            uint32_t pixelSeed = whitted::gpu::hashPcg((uint32_t(y) * uint32_t(s.width) + uint32_t(x)) ^ s.seed);
            glm::vec2 offset = pixelSampleOffset(sample, s.spp, pixelSeed);
            d = cameraDirection(camera, glm::vec2(float(x), float(y)) + offset, size);
            ++counts.camera;
        }
        rh.ray.org_x[i] = camera.eye.x; rh.ray.org_y[i] = camera.eye.y; rh.ray.org_z[i] = camera.eye.z;
        rh.ray.dir_x[i] = d.x; rh.ray.dir_y[i] = d.y; rh.ray.dir_z[i] = d.z;
        rh.ray.tnear[i] = 0.0f;
        rh.ray.tfar[i] = 3.0e38f;
        rh.ray.time[i] = 0.0f;
        rh.ray.mask[i] = ~0u;
        rh.ray.id[i] = unsigned(i);
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
}

// Each lane's hit: point, geometric normal facing the ray, shading normal, lit.
template <int N>
struct PacketHits {
    glm::vec3 point[N], ng[N], ns[N];
    bool lit[N];
};

template <int N>
void shadePacketHits(const AnchorScene& a, const int* valid, const typename Packet<N>::Hit& rh, PacketHits<N>& h) {
    for (int i = 0; i < N; ++i) {
        h.lit[i] = false;
        if (!valid[i]) continue;
        glm::vec3 o(rh.ray.org_x[i], rh.ray.org_y[i], rh.ray.org_z[i]);
        glm::vec3 d(rh.ray.dir_x[i], rh.ray.dir_y[i], rh.ray.dir_z[i]);
        float tfar = rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID ? 3.0e38f : rh.ray.tfar[i];
        int plane;
        float t = nearestPlane(a, o, d, tfar, &plane);
        glm::vec3 n, shading;
        uint32_t surface;
        if (plane >= 0) {
            n = a.planes[size_t(plane)].normal;
            shading = n;
            surface = a.planes[size_t(plane)].surface;
        } else if (rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID) {
            n = glm::normalize(glm::vec3(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]));
            shading = n;
            unsigned prim = rh.hit.primID[i];
            if (rh.hit.geomID[i] == a.triangleGeometry) {
                surface = a.triangleSurface[prim];
                const auto& vn = a.triangleNormals[prim];
                if (vn[0] != glm::vec3(0)) {
                    float u = rh.hit.u[i], v = rh.hit.v[i];
                    glm::vec3 m = (1.0f - u - v) * vn[0] + u * vn[1] + v * vn[2];
                    if (glm::dot(m, m) > 1e-12f) shading = glm::normalize(m);
                }
            } else {
                surface = a.sphereSurface[prim];
            }
        } else {
            continue;  // background
        }
        bool front = glm::dot(d, n) < 0.0f;
        if (!front) n = -n;
        if (glm::dot(shading, n) < 0.0f) shading = -shading;
        float facing = glm::dot(shading, -d);
        if (facing < 1e-3f) shading = glm::normalize(shading + (1e-3f - facing) * -d);
        h.point[i] = offsetRay(o + t * d, n);
        h.ng[i] = n;
        h.ns[i] = shading;
        h.lit[i] = a.surfaces[surface].lit;
    }
}

// Per light, one packet of shadow rays from the lanes' hits.
template <int N>
void traceShadowPackets(const AnchorScene& a, const PacketHits<N>& h, Counts& counts) {
    using P = Packet<N>;
    for (const AnchorLight& light : a.lights) {
        alignas(64) int shadowValid[N];
        alignas(64) typename P::Ray ray;
        int any = 0;
        for (int i = 0; i < N; ++i) {
            shadowValid[i] = 0;
            ray.org_x[i] = ray.org_y[i] = ray.org_z[i] = 0.0f;
            ray.dir_x[i] = ray.dir_y[i] = 0.0f;
            ray.dir_z[i] = 1.0f;
            ray.tnear[i] = 0.0f;
            ray.tfar[i] = 0.0f;
            ray.time[i] = 0.0f;
            ray.mask[i] = ~0u;
            ray.id[i] = unsigned(i);
            ray.flags[i] = 0;
            if (!h.lit[i]) continue;
            glm::vec3 l;
            float dist;
            if (light.directional) {
                l = light.toLight;
                dist = 3.0e38f;
            } else {
                glm::vec3 toLight = light.position - h.point[i];
                dist = glm::length(toLight);
                l = toLight / dist;
            }
            if (glm::dot(h.ns[i], l) <= 0.0f || glm::dot(h.ng[i], l) <= 0.0f) continue;
            ++counts.shadow;
            int plane;
            if (nearestPlane(a, h.point[i], l, dist, &plane) < dist) continue;  // a plane blocks it
            shadowValid[i] = -1;
            any = 1;
            ray.org_x[i] = h.point[i].x; ray.org_y[i] = h.point[i].y; ray.org_z[i] = h.point[i].z;
            ray.dir_x[i] = l.x; ray.dir_y[i] = l.y; ray.dir_z[i] = l.z;
            ray.tfar[i] = dist;
        }
        if (any && a.scene) {
            RTCIntersectContext shadowContext;
            rtcInitIntersectContext(&shadowContext);
            P::occluded(shadowValid, a.scene, &shadowContext, &ray);
        }
    }
}

// One packet of camera rays, then per light one packet of shadow rays from their hits.
template <int N>
void tracePacket(const AnchorScene& a, const CameraFrame& camera, const Settings& s, int x0, int y0, uint32_t sample,
                 Counts& counts) {
    using P = Packet<N>;
    alignas(64) int valid[N];
    alignas(64) typename P::Hit rh;
    fillCameraPacket<N>(camera, s, x0, y0, sample, valid, rh, counts);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    if (a.scene) P::intersect(valid, a.scene, &context, &rh);
    if (!s.shadows) return;
    PacketHits<N> hits;
    shadePacketHits<N>(a, valid, rh, hits);
    traceShadowPackets<N>(a, hits, counts);
}

// Traces every sample of the image on `threads` threads, rows of packets
// handed out in turn. Returns the counts.
template <int N>
Counts traceImage(const AnchorScene& a, const CameraFrame& camera, const Settings& s, int threads) {
    constexpr int kW = Packet<N>::kW, kH = N / kW;
    int rows = (s.height + kH - 1) / kH;
    std::atomic<int> next{0};
    std::vector<Counts> perThread(static_cast<size_t>(threads));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            Counts& c = perThread[size_t(t)];
            for (int row; (row = next.fetch_add(1)) < rows;) {
                for (int x0 = 0; x0 < s.width; x0 += kW)
                    for (uint32_t sample = 0; sample < s.spp; ++sample)
                        tracePacket<N>(a, camera, s, x0, row * kH, sample, c);
            }
        });
    }
    for (auto& thread : pool) thread.join();
    Counts total;
    for (const Counts& c : perThread) {
        total.camera += c.camera;
        total.shadow += c.shadow;
    }
    return total;
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

template <int N>
nlohmann::json measure(const AnchorScene& a, const CameraFrame& camera, Settings s, int threads, int repeats) {
    double best = std::numeric_limits<double>::infinity(), bestCamera = best;
    Counts counts, cameraCounts;
    for (int r = 0; r < repeats; ++r) {
        s.shadows = true;
        auto start = std::chrono::steady_clock::now();
        counts = traceImage<N>(a, camera, s, threads);
        best = std::min(best, seconds(start));
        s.shadows = false;
        start = std::chrono::steady_clock::now();
        cameraCounts = traceImage<N>(a, camera, s, threads);
        bestCamera = std::min(bestCamera, seconds(start));
    }
    uint64_t rays = counts.camera + counts.shadow;
    return {{"packet", N}, {"camera_rays", counts.camera}, {"shadow_rays", counts.shadow}, {"seconds", best},
            {"rays_per_s", double(rays) / best}, {"camera_only_seconds", bestCamera},
            {"camera_rays_per_s", double(cameraCounts.camera) / bestCamera}};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"whitted_embree_anchor: whitted's camera and shadow rays traced by Embree, rays per second as JSON"};
    std::string scenePath, packet = "best";
    int width = 0, height = 0, repeats = 3;
    int threads = int(std::max(1u, std::thread::hardware_concurrency()));
    Settings s;
    app.add_option("scene", scenePath, "scene XML file")->required();
    app.add_option("--width", width, "image width [scene's]")->check(CLI::Range(1, 16384));
    app.add_option("--height", height, "image height [scene's]")->check(CLI::Range(1, 16384));
    app.add_option("--spp", s.spp, "samples per pixel, whitted's uniform pattern")->check(CLI::Range(1, 4096))
        ->capture_default_str();
    app.add_option("--seed", s.seed, "whitted's --seed")->capture_default_str();
    app.add_option("--threads", threads, "threads [every core]")->check(CLI::Range(1, 1024));
    app.add_option("--repeats", repeats, "timed repeats; the fastest counts")->check(CLI::Range(1, 100))
        ->capture_default_str();
    app.add_option("--packet", packet, "packet width: 4, 8, 16, or best (each measured, the fastest reported)")
        ->check(CLI::IsMember({"4", "8", "16", "best"}))->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    Scene scene;
    auto loadStart = std::chrono::steady_clock::now();
    try {
        scene = loadScene(scenePath);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    }
    double loadSeconds = seconds(loadStart);
    s.width = width ? width : scene.camera.width;
    s.height = height ? height : scene.camera.height;

    RTCDevice device = rtcNewDevice(nullptr);
    if (!device) {
        std::cerr << "whitted_embree_anchor: cannot create an Embree device (error " << rtcGetDeviceError(nullptr)
                  << ")\n";
        return 1;
    }
    auto buildStart = std::chrono::steady_clock::now();
    AnchorScene a = buildScene(device, scene);
    double buildSeconds = seconds(buildStart);
    nlohmann::json out = {{"scene", scenePath}, {"embree", RTC_VERSION_STRING}, {"width", s.width},
                          {"height", s.height}, {"spp", s.spp}, {"seed", s.seed}, {"threads", threads},
                          {"repeats", repeats}, {"triangles", a.triangles}, {"boxes_as_triangles", a.boxes},
                          {"spheres", a.spheres}, {"planes", a.planes.size()}, {"lights", a.lights.size()},
                          {"load_s", loadSeconds},
                          {"native_ray16", rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)},
                          {"native_ray8", rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)}};
    if (!a.unsupported.empty()) {
        std::string what;
        for (const auto& u : a.unsupported) what += (what.empty() ? "" : ", ") + u;
        out["supported"] = false;
        out["reason"] = "the anchor traces triangles, meshes, boxes, spheres and planes; this scene has " + what;
        std::cout << out.dump(2) << "\n";
        rtcReleaseDevice(device);
        return 0;
    }
    out["supported"] = true;
    out["build_s"] = buildSeconds;
    CameraFrame camera = cameraFrame(scene.camera, s.width, s.height);
    std::vector<nlohmann::json> runs;
    if (packet == "4" || packet == "best") runs.push_back(measure<4>(a, camera, s, threads, repeats));
    if (packet == "8" || packet == "best") runs.push_back(measure<8>(a, camera, s, threads, repeats));
    if (packet == "16" || packet == "best") runs.push_back(measure<16>(a, camera, s, threads, repeats));
    auto fastest = std::max_element(runs.begin(), runs.end(), [](const nlohmann::json& x, const nlohmann::json& y) {
        return x["rays_per_s"].get<double>() < y["rays_per_s"].get<double>();
    });
    out["packets"] = runs;
    for (const char* key : {"packet", "camera_rays", "shadow_rays", "seconds", "rays_per_s", "camera_rays_per_s"})
        out[key] = (*fastest)[key];
    std::cout << out.dump(2) << "\n";
    rtcReleaseScene(a.scene);
    rtcReleaseDevice(device);
    return 0;
}

#include "render/gpu_scene.h"

#include "render/gpu_instances.h"

#include "display_types.h"  // DisplayParams, laid out here with the others
#include "shapes/shapes.h"
#include "tracer_types.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <stdexcept>

namespace whitted {

// The GLSL side reads these with std430 (storage, push constants) and
// std140 (uniform) rules; every size and offset below is the one those
// rules give the GLSL declaration (shaders/device_types.h, tracer_types.h,
// display_types.h).
static_assert(sizeof(gpu::Primitive) == 64 && offsetof(gpu::Primitive, a) == 0 &&
              offsetof(gpu::Primitive, b) == 16 && offsetof(gpu::Primitive, c) == 32 &&
              offsetof(gpu::Primitive, shape) == 48 && offsetof(gpu::Primitive, material) == 52 &&
              offsetof(gpu::Primitive, extra0) == 56 && offsetof(gpu::Primitive, extra1) == 60);
static_assert(sizeof(gpu::Material) == 192 && offsetof(gpu::Material, diffuse) == 0 &&
              offsetof(gpu::Material, specular) == 16 && offsetof(gpu::Material, ka) == 32 &&
              offsetof(gpu::Material, kd) == 36 && offsetof(gpu::Material, ks) == 40 &&
              offsetof(gpu::Material, shininess) == 44 && offsetof(gpu::Material, kr) == 48 &&
              offsetof(gpu::Material, kt) == 52 && offsetof(gpu::Material, ior) == 56 &&
              offsetof(gpu::Material, checkerColor) == 64 && offsetof(gpu::Material, checkerSize) == 76 &&
              offsetof(gpu::Material, checkerOrigin) == 80 && offsetof(gpu::Material, absorption) == 96 &&
              offsetof(gpu::Material, diffuseTexture) == 112 && offsetof(gpu::Material, normalMap) == 116 &&
              offsetof(gpu::Material, emissionTexture) == 120 &&
              offsetof(gpu::Material, flags) == 60 && offsetof(gpu::Material, textureScale) == 128 &&
              offsetof(gpu::Material, normalStrength) == 132 && offsetof(gpu::Material, glossExponent) == 136 &&
              offsetof(gpu::Material, roughnessTexture) == 124 && offsetof(gpu::Material, roughness) == 140 &&
              offsetof(gpu::Material, transmissionColor) == 144 &&
              offsetof(gpu::Material, emission) == 160 && offsetof(gpu::Material, ambientColor) == 176);
static_assert(sizeof(gpu::SurfaceAttributes) == 48 && offsetof(gpu::SurfaceAttributes, uv0) == 0 &&
              offsetof(gpu::SurfaceAttributes, uv1) == 8 && offsetof(gpu::SurfaceAttributes, uv2) == 16 &&
              offsetof(gpu::SurfaceAttributes, tangents) == 32 &&
              offsetof(gpu::SurfaceAttributes, hasTangents) == 44);
static_assert(sizeof(gpu::Light) == 96 && offsetof(gpu::Light, position) == 0 && offsetof(gpu::Light, type) == 12 &&
              offsetof(gpu::Light, color) == 16 && offsetof(gpu::Light, falloff) == 28 &&
              offsetof(gpu::Light, direction) == 32 && offsetof(gpu::Light, cosInner) == 44 &&
              offsetof(gpu::Light, cosOuter) == 48 && offsetof(gpu::Light, radius) == 52 &&
              offsetof(gpu::Light, shadowSamples) == 56 && offsetof(gpu::Light, twoSided) == 60 &&
              offsetof(gpu::Light, u) == 64 && offsetof(gpu::Light, v) == 80);
static_assert(sizeof(gpu::BvhNode) == 80 && offsetof(gpu::BvhNode, origin) == 0 &&
              offsetof(gpu::BvhNode, exponents) == 12 && offsetof(gpu::BvhNode, childBase) == 16 &&
              offsetof(gpu::BvhNode, primitiveBase) == 20 && offsetof(gpu::BvhNode, childInfo0) == 24 &&
              offsetof(gpu::BvhNode, childInfo1) == 28 && offsetof(gpu::BvhNode, quantX) == 32 &&
              offsetof(gpu::BvhNode, quantY) == 48 && offsetof(gpu::BvhNode, quantZ) == 64);
static_assert(sizeof(gpu::CsgNode) == 16 && offsetof(gpu::CsgNode, op) == 0 &&
              offsetof(gpu::CsgNode, leaf) == 4);
static_assert(sizeof(gpu::EnvironmentParams) == 80 && offsetof(gpu::EnvironmentParams, kind) == 12 &&
              offsetof(gpu::EnvironmentParams, horizon) == 16 && offsetof(gpu::EnvironmentParams, image) == 28 &&
              offsetof(gpu::EnvironmentParams, ground) == 32 && offsetof(gpu::EnvironmentParams, rotation) == 44 &&
              offsetof(gpu::EnvironmentParams, intensity) == 48 && offsetof(gpu::EnvironmentParams, visible) == 52 &&
              offsetof(gpu::EnvironmentParams, shadowSamples) == 56 &&
              offsetof(gpu::EnvironmentParams, distributionAddress) == 64 &&
              offsetof(gpu::EnvironmentParams, imageSize) == 72);
static_assert(sizeof(gpu::InstanceRecord) == 112 && offsetof(gpu::InstanceRecord, worldFromObject1) == 16 &&
              offsetof(gpu::InstanceRecord, objectFromWorld0) == 48 && offsetof(gpu::InstanceRecord, rootNode) == 96 &&
              offsetof(gpu::InstanceRecord, object) == 100 && offsetof(gpu::InstanceRecord, material) == 104);
static_assert(sizeof(gpu::FrameParams) == 304 && offsetof(gpu::FrameParams, eye) == 0 &&
              offsetof(gpu::FrameParams, projection) == 12 &&
              offsetof(gpu::FrameParams, forward) == 16 && offsetof(gpu::FrameParams, apertureRadius) == 28 &&
              offsetof(gpu::FrameParams, right) == 32 && offsetof(gpu::FrameParams, focusDistance) == 44 &&
              offsetof(gpu::FrameParams, up) == 48 && offsetof(gpu::FrameParams, ambientLight) == 64 &&
              offsetof(gpu::FrameParams, width) == 80 && offsetof(gpu::FrameParams, height) == 84 &&
              offsetof(gpu::FrameParams, primitiveCount) == 88 &&
              offsetof(gpu::FrameParams, lightCount) == 92 &&
              offsetof(gpu::FrameParams, samplesPerPixel) == 96 &&
              offsetof(gpu::FrameParams, maxDepth) == 100 && offsetof(gpu::FrameParams, options) == 104 &&
              offsetof(gpu::FrameParams, seed) == 108 && offsetof(gpu::FrameParams, bvhNodeCount) == 112 &&
              offsetof(gpu::FrameParams, firstListPrimitive) == 116 &&
              offsetof(gpu::FrameParams, listPrimitiveCount) == 120 &&
              offsetof(gpu::FrameParams, primitiveAddress) == 128 &&
              offsetof(gpu::FrameParams, bvhNodeAddress) == 136 &&
              offsetof(gpu::FrameParams, materialAddress) == 144 &&
              offsetof(gpu::FrameParams, lightAddress) == 152 &&
              offsetof(gpu::FrameParams, csgNodeAddress) == 160 &&
              offsetof(gpu::FrameParams, attributeAddress) == 168 &&
              offsetof(gpu::FrameParams, outputAddress) == 176 &&
              offsetof(gpu::FrameParams, pixelListAddress) == 184 &&
              offsetof(gpu::FrameParams, guideAddress) == 192 &&
              offsetof(gpu::FrameParams, sampleStatsAddress) == 200 &&
              offsetof(gpu::FrameParams, environment) == 208 && offsetof(gpu::FrameParams, instanceAddress) == 288);
static_assert(sizeof(gpu::TileParams) == 80 && offsetof(gpu::TileParams, tileOrigin) == 0 &&
              offsetof(gpu::TileParams, tileSize) == 8 && offsetof(gpu::TileParams, firstSample) == 16 &&
              offsetof(gpu::TileParams, sampleCount) == 20 && offsetof(gpu::TileParams, patternSize) == 24 &&
              offsetof(gpu::TileParams, flags) == 28 && offsetof(gpu::TileParams, outputOrigin) == 32 &&
              offsetof(gpu::TileParams, outputSize) == 40 && offsetof(gpu::TileParams, guideOrigin) == 48 &&
              offsetof(gpu::TileParams, guideSize) == 56 && offsetof(gpu::TileParams, listFirst) == 64 &&
              offsetof(gpu::TileParams, listCount) == 68 && offsetof(gpu::TileParams, rayTreeAddress) == 72);
static_assert(sizeof(gpu::RayCounters) == 16 && offsetof(gpu::RayCounters, primary) == 0 &&
              offsetof(gpu::RayCounters, shadow) == 4 && offsetof(gpu::RayCounters, secondary) == 8);
static_assert(sizeof(gpu::DisplayParams) == 48 && offsetof(gpu::DisplayParams, kind) == 0 &&
              offsetof(gpu::DisplayParams, layer) == 4 && offsetof(gpu::DisplayParams, channel) == 8 &&
              offsetof(gpu::DisplayParams, width) == 16 && offsetof(gpu::DisplayParams, height) == 20 &&
              offsetof(gpu::DisplayParams, scalarScale) == 32 &&
              offsetof(gpu::DisplayParams, depthMedian) == 36);

namespace {

// The slot of a texture in the kBindingTextures array, given on first use.
uint32_t textureSlot(const TextureRef& texture, std::vector<std::shared_ptr<const TextureData>>& slots) {
    if (!texture) return gpu::kNoTexture;
    auto it = std::find(slots.begin(), slots.end(), texture.data);
    if (it != slots.end()) return uint32_t(it - slots.begin());
    if (slots.size() == gpu::kMaxTextures)
        throw std::runtime_error("the scene uses more than " + std::to_string(gpu::kMaxTextures) +
                                 " texture files, the most a render binds");
    slots.push_back(texture.data);
    return uint32_t(slots.size() - 1);
}

gpu::Material packMaterial(const Material& m, std::vector<std::shared_ptr<const TextureData>>& textures) {
    return {.diffuse = glm::vec3(m.diffuseColor),
            .specular = glm::vec3(m.specularColor),
            .ka = float(m.ambient),
            .kd = float(m.diffuse),
            .ks = float(m.specular),
            .shininess = float(m.shininess),
            .kr = float(m.reflection),
            .kt = float(m.transmission),
            .ior = float(m.ior),
            .flags = (m.fresnel ? gpu::kMaterialFresnel : 0u) | (m.ambientColor ? gpu::kMaterialAmbientColor : 0u) |
                     (m.roughness > 0 ? gpu::kMaterialGlossy : 0u),
            .checkerColor = glm::vec3(m.checkerColor),
            .checkerSize = float(m.checkerSize),
            .checkerOrigin = glm::vec3(m.checkerOrigin),
            .absorption = glm::vec3(m.absorption),
            .diffuseTexture = textureSlot(m.diffuseTexture, textures),
            .normalMap = textureSlot(m.normalMap, textures),
            .emissionTexture = textureSlot(m.emissionTexture, textures),
            .roughnessTexture = m.roughness > 0 ? textureSlot(m.roughnessTexture, textures) : gpu::kNoTexture,
            .textureScale = float(m.textureScale),
            .normalStrength = float(m.normalStrength),
            .glossExponent = m.roughness > 0 ? float(glossyLobeExponent(m.roughness)) : 0.0f,
            .roughness = float(m.roughness),
            .transmissionColor = glm::vec3(m.transmissionColor),
            .emission = glm::vec3(m.emission),
            .ambientColor = glm::vec3(m.ambientColor.value_or(glm::dvec3(0)))};
}

// The light as the shader's loop takes it (shaders/shading.glsl).
gpu::Light packLight(const Light& l) {
    constexpr uint32_t kTypes[] = {gpu::kLightPoint, gpu::kLightSpot, gpu::kLightDirectional, gpu::kLightRect};
    return {.position = glm::vec3(l.position),
            .type = kTypes[int(l.type)],
            .color = glm::vec3(l.color * l.intensity),
            .falloff = l.falloff == Light::Falloff::InverseSquare ? gpu::kFalloffInverseSquare : gpu::kFalloffNone,
            .direction = glm::vec3(glm::normalize(l.direction)),
            .cosInner = float(std::cos(glm::radians(l.innerAngleDegrees))),
            .cosOuter = float(std::cos(glm::radians(l.outerAngleDegrees))),
            .radius = l.type == Light::Type::Rect ? 0.0f : float(l.radius),
            .shadowSamples = l.area() ? uint32_t(l.shadowSamples) : 1u,
            .twoSided = l.twoSided ? 1u : 0u,
            .u = glm::vec3(l.u),
            .v = glm::vec3(l.v)};
}

}  // namespace

// Whether a mesh object needs per-triangle surface attributes.
bool needsAttributes(const Object& object) {
    const Mesh* mesh = std::get_if<Mesh>(&object.shape);
    return mesh && !mesh->uvs.empty() && object.material.textured();
}


// Triangle i's texture coordinates and, where all three are usable (model
// files write zero vectors where theirs were not), its vertex tangents.
gpu::SurfaceAttributes surfaceAttributes(const Mesh& mesh, size_t i) {
    const auto& uv = mesh.uvs[i];
    gpu::SurfaceAttributes at{.uv0 = glm::vec2(uv[0]), .uv1 = glm::vec2(uv[1]), .uv2 = glm::vec2(uv[2])};
    if (mesh.tangents.empty()) return at;
    const auto& t = mesh.tangents[i];
    if (glm::length(t[0]) > 0.5 && glm::length(t[1]) > 0.5 && glm::length(t[2]) > 0.5) {
        at.tangents = glm::uvec3(encodeOctahedral(t[0]), encodeOctahedral(t[1]), encodeOctahedral(t[2]));
        at.hasTangents = 1u;
    }
    return at;
}

// Pads a primitive's bounds by a few float ulps: the shader intersects
// float-rounded shapes.
Aabb padded(Aabb b) {
    glm::vec3 pad = 1e-6f * (glm::abs(b.min) + glm::abs(b.max)) + 1e-30f;
    b.min -= pad;
    b.max += pad;
    return b;
}

namespace {

// items[k] = old items[source[k]] for every k, following the permutation's
// cycles (source is left as the identity).
template <typename T>
void permuteInPlace(std::vector<T>& items, std::vector<uint32_t>& source) {
    for (uint32_t start = 0; start < source.size(); ++start) {
        if (source[start] == start) continue;
        T carried = items[start];
        uint32_t k = start;
        while (source[k] != start) {
            uint32_t next = source[k];
            items[k] = items[next];
            source[k] = k;
            k = next;
        }
        items[k] = carried;
        source[k] = k;
    }
}

// Two 64-bit lanes of multiply-rotate hashing over a byte string (not
// cryptographic: it tells a mesh moved or edited from itself unchanged).
struct GeometryHash {
    uint64_t a = 0x243F6A8885A308D3ull, b = 0x13198A2E03707344ull;
    void mix(uint64_t w) {
        a = std::rotl(a ^ w, 29) * 0x9E3779B97F4A7C15ull;
        b = std::rotl(b + w, 23) * 0xC2B2AE3D27D4EB4Full;
    }
    // Four independent lanes over 32-byte blocks (one multiply chain a lane
    // would wait on each multiply), folded into the two at the end.
    void add(const void* data, size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        uint64_t c = ~a, d = ~b;
        size_t blocks = bytes / 32;
        for (size_t i = 0; i < blocks; ++i) {
            uint64_t w[4];
            std::memcpy(w, p + 32 * i, 32);
            a = std::rotl(a ^ w[0], 29) * 0x9E3779B97F4A7C15ull;
            b = std::rotl(b + w[1], 23) * 0xC2B2AE3D27D4EB4Full;
            c = std::rotl(c ^ w[2], 31) * 0x165667B19E3779F9ull;
            d = std::rotl(d + w[3], 27) * 0xD6E8FEB86659FD93ull;
        }
        mix(c);
        mix(d);
        for (size_t i = 32 * blocks; i < bytes; ++i) mix(p[i]);
        mix(bytes);
    }
    template <typename T>
    void add(const std::vector<T>& v) {
        add(v.data(), v.size() * sizeof(T));
    }
};

// A mesh object's part (its own tree, packed triangles and attributes),
// found by its geometry's hash or built now; null when the object is not
// one (too small, no room left in the cache, or bounds that are not
// finite). `kept` counts the triangles of the parts this pack uses,
// `built` those of the parts it built.
BvhPartCache::Entry* partFor(const Object& object, uint32_t material, BvhPartCache& cache, size_t& kept,
                             uint64_t& built, double& seconds) {
    const Mesh* mesh = std::get_if<Mesh>(&object.shape);
    if (!mesh || mesh->triangles.size() < kBvhPartMinTriangles) return nullptr;
    auto start = std::chrono::steady_clock::now();
    struct Timer {
        std::chrono::steady_clock::time_point start;
        double& seconds;
        ~Timer() { seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
    } timer{start, seconds};
    bool attributes = needsAttributes(object);
    GeometryHash h;
    h.add(mesh->triangles);
    h.add(mesh->normals);
    if (attributes) {
        h.add(mesh->uvs);
        h.add(mesh->tangents);
    }
    for (const auto& e : cache.entries)
        if (!e->used && e->hash[0] == h.a && e->hash[1] == h.b && e->triangles == mesh->triangles.size() &&
            e->attributes == attributes) {
            e->used = true;
            kept += e->triangles;
            return e.get();
        }
    if (kept + mesh->triangles.size() > kBvhPartMaxTriangles) return nullptr;
    std::vector<gpu::Primitive> primitives;
    std::vector<Aabb> bounds;
    primitives.reserve(mesh->triangles.size());
    bounds.reserve(mesh->triangles.size());
    appendPrimitives(object.shape, material, primitives, bounds);
    for (Aabb& b : bounds) {
        if (!b.finite()) return nullptr;
        b = padded(b);
    }
    auto entry = std::make_unique<BvhPartCache::Entry>();
    entry->hash[0] = h.a;
    entry->hash[1] = h.b;
    entry->triangles = mesh->triangles.size();
    entry->attributes = attributes;
    entry->tree = buildWideBvh(bounds);
    // Stored in leaf order, so that the part's order is the identity.
    entry->primitives.reserve(primitives.size());
    for (uint32_t k : entry->tree.order) entry->primitives.push_back(primitives[k]);
    if (attributes) {
        entry->surface.reserve(primitives.size());
        for (uint32_t k : entry->tree.order) entry->surface.push_back(surfaceAttributes(*mesh, k));
    }
    entry->meshOrder = entry->tree.order;
    for (uint32_t i = 0; i < entry->tree.order.size(); ++i) entry->tree.order[i] = i;
    entry->builtBy = cache.packs;
    entry->used = true;
    kept += entry->triangles;
    built += entry->triangles;
    cache.entries.push_back(std::move(entry));
    return cache.entries.back().get();
}

}  // namespace

// Camera frame: image right = cross(forward, up), right and up scaled to the
// half extents of the window at unit distance.
void packCamera(const Camera& camera, int width, int height, gpu::FrameParams& p) {
    glm::dvec3 forward = glm::normalize(camera.windowCenter - camera.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::dvec3 up = glm::cross(right, forward);
    // Orthographic: the window's half extents in the scene, about the eye.
    bool orthographic = camera.projection == Camera::Projection::Orthographic;
    double halfHeight = orthographic ? camera.windowHeight / 2.0 : std::tan(glm::radians(camera.verticalFovDegrees) / 2.0);
    double aspect = double(width) / double(height);
    p.eye = glm::vec3(camera.eye);
    p.apertureRadius = float(camera.apertureRadius);
    p.focusDistance = float(camera.focusDistanceOrDefault());
    p.projection = orthographic ? gpu::kProjectionOrthographic : gpu::kProjectionPerspective;
    if (!orthographic && camera.intrinsics) {
        // From K (scene/camera_matrices.h), for the camera's width x height
        // and so for any render size: the window's half extents are
        // width / 2fx and height / 2fy, its centre off the axis by where the
        // principal point is off the image's centre (pixel centres at
        // integers, image centre at (width - 1) / 2). forward is then not
        // unit; generateCameraRay normalizes the sum.
        const Camera::Intrinsics& k = *camera.intrinsics;
        double w = camera.width, h = camera.height;
        double offRight = ((w - 1) / 2.0 - k.cx) / k.fx, offUp = (k.cy - (h - 1) / 2.0) / k.fy;
        p.forward = glm::vec3(forward + offRight * right + offUp * up);
        p.right = glm::vec3(right * (w / (2.0 * k.fx)));
        p.up = glm::vec3(up * (h / (2.0 * k.fy)));
        return;
    }
    p.forward = glm::vec3(forward);
    p.right = glm::vec3(right * halfHeight * aspect);
    p.up = glm::vec3(up * halfHeight);
}

namespace {

// A mesh object with a tree of its own (BvhPartCache): its primitives'
// range among the gathered ones.
struct PartRange {
    uint32_t first, count;
    const WideBvh* tree;
    bool reused;  // taken from the cache, built by an earlier pack
};

// Every object's primitives in the objects' order, before the BVH orders
// them.
struct GatheredPrimitives {
    std::vector<gpu::Primitive> primitives;
    // The bounds of the primitives outside the parts, in their order.
    std::vector<Aabb> bounds;
    // Csg objects: their leaves and programs go into csg, the materials of
    // children with their own after the objects' (an object's material
    // index stays its index).
    CsgArrays csg;
    std::vector<uint32_t> leafInObject;  // csg.leaves' share of primitiveInObject
    std::vector<PartRange> partRanges;
    bool attributes = false;   // surface attributes are packed (some textured mesh needs them)
    size_t partTriangles = 0;  // the triangles of the parts this pack uses
    uint64_t partsBuilt = 0;   // those of the parts it built
    double partSeconds = 0;    // finding and building the parts
};

// A mesh object's part: its primitives, already in the part's leaf order,
// given the object's material and index; each triangle's index in the mesh
// and its surface attributes follow the same order.
void appendPart(const BvhPartCache::Entry& part, uint32_t objectIndex, bool attributes, GatheredPrimitives& out,
                GpuScene& g) {
    size_t first = out.primitives.size();
    out.primitives.insert(out.primitives.end(), part.primitives.begin(), part.primitives.end());
    for (size_t k = first; k < out.primitives.size(); ++k) {
        out.primitives[k].material = objectIndex;
        gpu::setPrimitiveObject(out.primitives[k], objectIndex);
    }
    out.partRanges.push_back({uint32_t(first), uint32_t(part.primitives.size()), &part.tree, false});
    g.primitiveInObject.insert(g.primitiveInObject.end(), part.meshOrder.begin(), part.meshOrder.end());
    if (!attributes) return;
    if (part.attributes) g.attributes.insert(g.attributes.end(), part.surface.begin(), part.surface.end());
    else g.attributes.resize(g.attributes.size() + part.primitives.size(), gpu::SurfaceAttributes{});
}

// The first step of packScene: each object's primitives and their bounds,
// a mesh's from its part where it has one; and into g, each primitive's
// index within its object and, when a textured mesh needs them, its
// surface attributes.
GatheredPrimitives gatherPrimitives(const Scene& scene, const RenderSettings& settings, BvhPartCache* parts,
                                    GpuScene& g) {
    GatheredPrimitives out;
    // Sized up front: a large mesh grown by doubling would hold up to twice
    // its size while the BVH is built.
    size_t count = countSceneArrays(scene).primitives;
    out.primitives.reserve(count);
    out.bounds.reserve(count);
    out.csg.firstMaterial = uint32_t(scene.objects.size());
    bool attributes = std::any_of(scene.objects.begin(), scene.objects.end(), needsAttributes) ||
                      std::any_of(scene.prototypes.begin(), scene.prototypes.end(), [](const Prototype& p) {
                          return std::any_of(p.objects.begin(), p.objects.end(), needsAttributes);
                      });
    out.attributes = attributes;
    if (attributes) g.attributes.reserve(count);
    g.primitiveInObject.reserve(count);
    if (parts)
        for (auto& e : parts->entries) e->used = false;
    for (uint32_t objectIndex = 0; objectIndex < scene.objects.size(); ++objectIndex) {
        const Object& object = scene.objects[objectIndex];
        uint32_t material = objectIndex;  // objects and their materials share the index
        size_t first = out.primitives.size();
        // Every primitive a hit can report (a csg object's leaves, not the
        // csg primitive itself) names its object for the object_id mask.
        if (const Csg* c = std::get_if<Csg>(&object.shape)) {
            size_t firstLeaf = out.csg.leaves.size();
            out.primitives.push_back(packCsg(*c, material, out.csg));
            out.bounds.push_back(boundsCsg(*c));
            for (size_t k = firstLeaf; k < out.csg.leaves.size(); ++k) {
                gpu::setPrimitiveObject(out.csg.leaves[k], objectIndex);
                out.leafInObject.push_back(uint32_t(k - firstLeaf));
            }
        } else if (const BvhPartCache::Entry* part =
                       parts && settings.useBvh ? partFor(object, material, *parts, out.partTriangles,
                                                          out.partsBuilt, out.partSeconds)
                                                : nullptr) {
            appendPart(*part, objectIndex, attributes, out, g);
            out.partRanges.back().reused = part->builtBy != parts->packs;
            continue;
        } else {
            appendPrimitives(object.shape, material, out.primitives, out.bounds);
            for (size_t k = first; k < out.primitives.size(); ++k) gpu::setPrimitiveObject(out.primitives[k], objectIndex);
        }
        for (size_t k = first; k < out.primitives.size(); ++k) g.primitiveInObject.push_back(uint32_t(k - first));
        if (!attributes) continue;
        if (needsAttributes(object)) {
            const Mesh& mesh = std::get<Mesh>(object.shape);
            for (size_t i = 0; i < mesh.uvs.size(); ++i) g.attributes.push_back(surfaceAttributes(mesh, i));
        } else {
            g.attributes.resize(g.attributes.size() + (out.primitives.size() - first), gpu::SurfaceAttributes{});
        }
    }
    return out;
}

// The instances' stand-ins after the objects' primitives, each a part of
// its own (a one-leaf tree) for the joined BVH.
void appendInstances(const InstancePack& instances, GatheredPrimitives& out, GpuScene& g) {
    for (size_t i = 0; i < instances.proxies.size(); ++i) {
        out.partRanges.push_back({uint32_t(out.primitives.size()), 1u, &instances.leafTrees[i], false});
        out.primitives.push_back(instances.proxies[i]);
        g.primitiveInObject.push_back(0u);
        if (out.attributes) g.attributes.push_back(gpu::SurfaceAttributes{});
        ++out.partTriangles;
    }
}

// The primitives outside the parts, split: bounded ones go into the BVH
// with their bounds padded by a few float ulps (the shader intersects
// float-rounded shapes); unbounded ones (planes), and every one when the
// BVH is off, go into the list the shader tests after the tree.
struct BoundedSplit {
    std::vector<uint32_t> bounded, unbounded;  // indices into the gathered primitives
    std::vector<Aabb> boundedBounds;
};

BoundedSplit splitBounded(const GatheredPrimitives& gathered, bool useBvh) {
    BoundedSplit split;
    size_t part = 0, j = 0;  // the next part range, the next entry of bounds
    for (uint32_t i = 0; i < gathered.primitives.size(); ++i) {
        if (part < gathered.partRanges.size() && i == gathered.partRanges[part].first) {
            i += gathered.partRanges[part++].count - 1;
            continue;
        }
        const Aabb& b = gathered.bounds[j++];
        if (useBvh && b.finite()) {
            split.bounded.push_back(i);
            split.boundedBounds.push_back(padded(b));
        } else {
            split.unbounded.push_back(i);
        }
    }
    return split;
}

// The BVH over the bounded primitives into g.bvhNodes and g.bvhStats: one
// tree built now, or, with parts, the tree of every other bounded primitive
// joined with the parts' trees. Returns the BVH's leaves in order, each as
// its index in the gathered primitives.
std::vector<uint32_t> buildSceneBvh(BoundedSplit& split, const GatheredPrimitives& gathered, BvhPartCache* parts,
                                    GpuScene& g) {
    auto start = std::chrono::steady_clock::now();
    std::vector<uint32_t> order;
    if (gathered.partRanges.empty()) {
        Bvh bvh = buildBvh(split.boundedBounds);
        std::vector<Aabb>().swap(split.boundedBounds);
        g.bvhNodes = collapseToWide(bvh.nodes, bvh.primitiveOrder);
        g.bvhStats = bvh.stats;
        g.bvhStats.wideNodeCount = uint32_t(g.bvhNodes.size());
        g.bvhStats.primitivesBuilt = split.bounded.size();
        order = std::move(bvh.primitiveOrder);
        for (uint32_t& k : order) k = split.bounded[k];
    } else {
        WideBvh rest;
        std::vector<const WideBvh*> trees;
        std::vector<uint32_t> treeFirst;
        if (!split.boundedBounds.empty()) {
            rest = buildWideBvh(split.boundedBounds);
            for (uint32_t& k : rest.order) k = split.bounded[k];
            trees.push_back(&rest);
            treeFirst.push_back(0);
        }
        std::vector<Aabb>().swap(split.boundedBounds);
        for (const PartRange& r : gathered.partRanges) {
            trees.push_back(r.tree);
            treeFirst.push_back(r.first);
        }
        g.bvhNodes = joinWide(trees, treeFirst, order, g.bvhStats);
        g.bvhStats.parts = uint32_t(gathered.partRanges.size());
        g.bvhStats.partsReused = uint32_t(std::count_if(gathered.partRanges.begin(), gathered.partRanges.end(),
                                                        [](const PartRange& r) { return r.reused; }));
        g.bvhStats.primitivesBuilt = split.bounded.size() + gathered.partsBuilt;
    }
    if (parts) {
        std::erase_if(parts->entries, [](const auto& e) { return !e->used; });
        ++parts->packs;
    }
    if (g.bvhNodes.size() > gpu::kBvhMaxNodes)
        throw std::runtime_error("the scene's BVH has " + std::to_string(g.bvhNodes.size()) +
                                 " nodes, more than the shader addresses (" + std::to_string(gpu::kBvhMaxNodes) + ")");
    g.bvhStats.buildSeconds =
        gathered.partSeconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return order;
}

// The gathered primitives into g.primitives in their final order (the
// BVH's leaves, then the list), moved in place without a second copy, with
// their attributes and indices within their objects; then the prototypes'
// primitives; the csg leaves after every other primitive.
void placePrimitives(GatheredPrimitives& gathered, std::vector<uint32_t> source, const PrototypePack& prototypes,
                     GpuScene& g) {
    g.primitives = std::move(gathered.primitives);
    if (!g.attributes.empty()) {  // the same order as the primitives
        std::vector<uint32_t> sourceCopy = source;
        permuteInPlace(g.attributes, sourceCopy);
    }
    {
        std::vector<uint32_t> sourceCopy = source;
        permuteInPlace(g.primitiveInObject, sourceCopy);
    }
    permuteInPlace(g.primitives, source);
    g.primitives.insert(g.primitives.end(), prototypes.primitives.begin(), prototypes.primitives.end());
    g.primitiveInObject.insert(g.primitiveInObject.end(), prototypes.primitiveInObject.begin(),
                               prototypes.primitiveInObject.end());
    if (gathered.attributes)
        g.attributes.insert(g.attributes.end(), prototypes.attributes.begin(), prototypes.attributes.end());
    // Each csg primitive's a.w becomes the index of its first leaf there.
    uint32_t leafBase = uint32_t(g.primitives.size());
    for (gpu::Primitive& p : g.primitives)
        if (p.shape == gpu::kShapeCsg) gpu::setCsgFirstLeaf(p, leafBase + gpu::csgLeaves(p).x);
    g.primitives.insert(g.primitives.end(), gathered.csg.leaves.begin(), gathered.csg.leaves.end());
    g.primitiveInObject.insert(g.primitiveInObject.end(), gathered.leafInObject.begin(), gathered.leafInObject.end());
    g.csgNodes = std::move(gathered.csg.nodes);
}

// The frame's parameters: the camera, the image, the counts of what was
// packed and the render's options. The BVH's leaves are the first
// `treeCount` primitives, the list the `listCount` after them.
void packFrameParams(const Scene& scene, const RenderSettings& settings, size_t treeCount, size_t listCount,
                     GpuScene& g) {
    packCamera(scene.camera, g.width, g.height, g.params);
    g.params.ambientLight = glm::vec3(scene.ambientLight);
    g.params.width = uint32_t(g.width);
    g.params.height = uint32_t(g.height);
    g.params.primitiveCount = uint32_t(g.primitives.size());
    g.params.lightCount = uint32_t(g.lights.size());
    g.params.samplesPerPixel = uint32_t(settings.samplesPerPixel);
    g.params.maxDepth = uint32_t(settings.maxDepth);
    g.params.options = (settings.auxiliary ? gpu::kOptionWriteAovs : 0u) |
                       (settings.textureLodZero ? gpu::kOptionTextureLodZero : 0u) |
                       (settings.auxiliary && settings.ids ? gpu::kOptionWriteIds : 0u);
    if (settings.auxiliary) g.params.options |= uint32_t(settings.aovBounces) << gpu::kOptionAovBouncesShift;
    g.params.seed = uint32_t(settings.seed);
    g.params.bvhNodeCount = uint32_t(g.bvhNodes.size());
    g.params.firstListPrimitive = uint32_t(treeCount);
    g.params.listPrimitiveCount = uint32_t(listCount);
}

}  // namespace

// In steps: the materials, textures and lights; the objects' primitives;
// the BVH over the bounded ones; the primitives in the BVH's order; the
// frame's parameters.
GpuScene packScene(const Scene& scene, const RenderSettings& settings, BvhPartCache* parts) {
    GpuScene g;
    g.width = settings.width > 0 ? settings.width : scene.camera.width;
    g.height = settings.height > 0 ? settings.height : scene.camera.height;
    GpuShading shading = packShading(scene);
    g.materials = std::move(shading.materials);
    g.textures = std::move(shading.textures);
    g.lights = std::move(shading.lights);
    g.environmentDistribution = std::move(shading.environment.distribution);

    GatheredPrimitives gathered = gatherPrimitives(scene, settings, parts, g);
    // Instances: their prototypes' trees, and their stand-ins as parts of the scene's BVH.
    uint32_t instanceMaterialBase = uint32_t(g.materials.size() - instanceMaterials(scene).size());
    auto prototypesStart = std::chrono::steady_clock::now();
    PrototypePack prototypes = packPrototypes(scene, instanceMaterialBase, gathered.attributes);
    double prototypeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - prototypesStart).count();
    size_t prototypeObjects = 0;
    for (const Prototype& p : scene.prototypes) prototypeObjects += p.objects.size();
    InstancePack instances = packInstances(scene, prototypes, instanceMaterialBase + uint32_t(prototypeObjects));
    appendInstances(instances, gathered, g);
    BoundedSplit split = splitBounded(gathered, settings.useBvh);
    size_t treeCount = split.bounded.size() + gathered.partTriangles;
    if (treeCount > gpu::kBvhMaxPrimitives)
        throw std::runtime_error("the scene has " + std::to_string(treeCount) +
                                 " bounded primitives, more than the shader's BVH addresses (" +
                                 std::to_string(gpu::kBvhMaxPrimitives) + ")");
    std::vector<Aabb>().swap(gathered.bounds);
    std::vector<uint32_t> source = buildSceneBvh(split, gathered, parts, g);
    source.insert(source.end(), split.unbounded.begin(), split.unbounded.end());
    placePrimitives(gathered, std::move(source), prototypes, g);
    if (!instances.records.empty()) {
        uint32_t nodeBase = uint32_t(g.bvhNodes.size());
        uint32_t primitiveBase = uint32_t(treeCount + split.unbounded.size());
        std::vector<gpu::BvhNode> nodes = prototypeNodes(prototypes, nodeBase, primitiveBase);
        g.bvhNodes.insert(g.bvhNodes.end(), nodes.begin(), nodes.end());
        for (uint32_t p = 0; p < prototypes.trees.size(); ++p)
            g.prototypeRanges.push_back({primitiveBase + prototypes.firstPrimitive[p],
                                         uint32_t(prototypes.trees[p].order.size())});
        for (size_t i = 0; i < scene.instances.size(); ++i) {
            gpu::InstanceRecord& r = instances.records[i];
            r.rootNode += nodeBase;
            r.firstPrimitive = g.prototypeRanges[scene.instances[i].prototype].x;
            g.instancePrototypes.push_back(scene.instances[i].prototype);
        }
        g.instances = std::move(instances.records);
        // The statistics count the prototypes' trees too (built once each, however many instances).
        g.bvhStats.buildSeconds += prototypeSeconds;
        g.bvhStats.wideNodeCount += uint32_t(nodes.size());
        g.bvhStats.primitivesBuilt += prototypes.primitives.size();
        g.prototypeShapes = prototypes.shapes;
    }
    packFrameParams(scene, settings, treeCount, split.unbounded.size(), g);
    g.params.environment = shading.environment.params;
    if (settings.transparentBackground) g.params.environment.visible = 0u;
    if (settings.uniformEnvironmentSampling && !g.environmentDistribution.empty()) {
        glm::uvec2 size = g.params.environment.imageSize;
        std::vector<float> flat(size_t(size.x) * size.y, 1.0f);
        g.environmentDistribution = environmentDistribution(int(size.x), int(size.y), flat);
    }
    return g;
}

GpuShading packShading(const Scene& scene) {
    GpuShading g;
    // The order of packScene: each object's material, then the csg
    // children's own, as packCsg collects them.
    CsgArrays csg;
    csg.firstMaterial = uint32_t(scene.objects.size());
    for (const Object& object : scene.objects) {
        uint32_t material = uint32_t(g.materials.size());
        g.materials.push_back(packMaterial(object.material, g.textures));
        if (const Csg* c = std::get_if<Csg>(&object.shape)) packCsg(*c, material, csg);
    }
    for (const Material& m : csg.materials) g.materials.push_back(packMaterial(m, g.textures));
    for (const Material& m : instanceMaterials(scene)) g.materials.push_back(packMaterial(m, g.textures));
    for (const Light& light : scene.lights) g.lights.push_back(packLight(light));
    g.environment = packEnvironment(scene, g.textures);
    return g;
}

SceneArrayCounts countSceneArrays(const Scene& scene) {
    SceneArrayCounts counts;
    uint64_t leaves = 0, childMaterials = 0;
    for (const Object& object : scene.objects) {
        counts.primitives += primitiveCount(object.shape);
        if (const Csg* csg = std::get_if<Csg>(&object.shape)) {
            leaves += csgLeafCount(*csg);
            childMaterials += csgOwnMaterialCount(*csg);
        }
    }
    // Instances: a stand-in each in the scene's tree; each prototype's
    // primitives once, under a tree of its own.
    uint64_t prototypePrimitives = 0, prototypeNodes = 0;
    for (const Prototype& prototype : scene.prototypes) {
        uint64_t n = 0;
        for (const Object& object : prototype.objects) n += primitiveCount(object.shape);
        prototypePrimitives += n;
        prototypeNodes += std::max<uint64_t>(n, 2) - 1;
    }
    counts.primitives += scene.instances.size();
    counts.bvhNodes = std::max<uint64_t>(counts.primitives, 2) - 1 + prototypeNodes;  // collapseToWide's bound
    counts.primitives += leaves + prototypePrimitives;
    counts.materials = scene.objects.size() + childMaterials + instanceMaterials(scene).size();
    counts.lights = scene.lights.size();
    return counts;
}

std::optional<std::string> sceneArraysTooLarge(const SceneArrayCounts& counts, const BufferLimits& limits) {
    // The shader indexes the arrays with 32-bit signed-safe indices (the BVH
    // tags leaf entries with bit 31): at most 2^31 - 1 elements each.
    constexpr uint64_t kMaxIndexCount = (uint64_t(1) << 31) - 1;
    struct Array {
        uint64_t count;
        uint64_t elementSize;
        const char* what;
    };
    const Array arrays[] = {{counts.primitives, sizeof(gpu::Primitive), "primitives (triangles count one each)"},
                            {counts.bvhNodes, sizeof(gpu::BvhNode), "BVH nodes (at most)"},
                            {counts.materials, sizeof(gpu::Material), "materials (one per object)"},
                            {counts.lights, sizeof(gpu::Light), "lights"}};
    auto mib = [](uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; };
    for (const Array& a : arrays) {
        uint64_t bytes = a.count * a.elementSize;
        uint64_t limit = std::min(limits.maxBufferSize, limits.maxAllocationSize);
        const char* name =
            limits.maxAllocationSize <= limits.maxBufferSize ? "maxMemoryAllocationSize" : "maxBufferSize";
        if (bytes > limit)
            return "the scene's " + std::to_string(a.count) + " " + a.what + " need " + std::to_string(bytes) +
                   " bytes (" + mib(bytes) + ") in one buffer, more than this device's " + name + " of " +
                   std::to_string(limit) + " bytes (" + mib(limit) + ", " + std::to_string(limit / a.elementSize) +
                   " of them)";
        if (a.count > kMaxIndexCount)
            return "the scene's " + std::to_string(a.count) + " " + a.what +
                   " are more than the shader's 32-bit indices address (" + std::to_string(kMaxIndexCount) + ")";
    }
    return std::nullopt;
}

}  // namespace whitted

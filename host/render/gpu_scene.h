// Packs the CPU scene into the std430 arrays and uniforms of device_types.h.
#pragma once

#include "accel/bvh.h"
#include "device_types.h"
#include "render/gpu_environment.h"
#include "render/render_settings.h"
#include "io/texture.h"
#include "scene/scene.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace whitted {

struct GpuScene {
    std::vector<gpu::Primitive> primitives;
    std::vector<gpu::Material> materials;
    std::vector<gpu::Light> lights;
    std::vector<gpu::BvhNode> bvhNodes;  // empty: brute force over all primitives
    std::vector<gpu::CsgNode> csgNodes;  // the csg objects' programs (empty: no csg)
    // One entry per primitive (same order) when a textured mesh needs them, else empty.
    std::vector<gpu::SurfaceAttributes> attributes;
    // Each primitive's index among its object's, in the primitives' order
    // (host only, for Renderer.cast_rays' primitive ids, render/ray_cast.h):
    // a mesh's triangle index, a csg leaf's place among the csg object's
    // leaves (in the order its tree lists them), 0 for any other shape and
    // for a csg primitive itself.
    std::vector<uint32_t> primitiveInObject;
    // The images of the kBindingTextures array, by slot (Material.diffuseTexture, normalMap).
    std::vector<std::shared_ptr<const TextureData>> textures;
    // An image environment's importance-sampling distribution (FrameParams.environment), else empty.
    std::vector<float> environmentDistribution;
    // The instances (render/gpu_instances.h): empty without; then the
    // prototypes' nodes follow the scene's in bvhNodes, their primitives
    // the list's in primitives, and prototypeShapes holds their shapes' bits.
    std::vector<gpu::InstanceRecord> instances;
    uint32_t prototypeShapes = 0;
    std::vector<glm::uvec2> prototypeRanges;  // each prototype's first primitive and count (ray queries' BLASes)
    std::vector<uint32_t> instancePrototypes;  // each instance's prototype
    BvhStats bvhStats;
    gpu::FrameParams params{};
    int width = 0;
    int height = 0;
};

// The BVH parts of one renderer's packs, kept between them (accel/bvh.h
// joinWide; Renderer::setScene): a mesh of at least kBvhPartMinTriangles
// triangles gets a tree of its own, kept here with its packed triangles and
// surface attributes under a 128-bit hash of its geometry. A later pack that
// finds the same geometry (the object unmoved and unedited; its material
// may differ) takes them as they are, and builds only the trees of what
// changed: moved or edited meshes, the tree of every other bounded
// primitive, and the top level over the parts. Entries the last pack did
// not use are dropped; at most kBvhPartMaxTriangles triangles are kept (a
// larger mesh beyond them is packed into the one tree of the others).
struct BvhPartCache {
    struct Entry {
        uint64_t hash[2] = {0, 0};
        size_t triangles = 0;
        bool attributes = false;  // the surface attributes were packed (needsAttributes)
        std::vector<gpu::Primitive> primitives;  // in the tree's leaf order (tree.order is the identity)
        std::vector<uint32_t> meshOrder;         // each one's triangle index in the mesh
        std::vector<gpu::SurfaceAttributes> surface;
        WideBvh tree;
        uint64_t builtBy = 0;  // the pack that built it
        bool used = false;     // by the pack under way
    };
    std::vector<std::unique_ptr<Entry>> entries;
    uint64_t packs = 0;  // packs made with this cache
};
inline constexpr size_t kBvhPartMinTriangles = 4096;
inline constexpr size_t kBvhPartMaxTriangles = size_t(8) << 20;

// parts: null packs one tree over every bounded primitive; else meshes of
// kBvhPartMinTriangles or more get trees of their own, joined, taken from or
// added to `parts` (GpuScene::bvhStats says how many were reused).
GpuScene packScene(const Scene& scene, const RenderSettings& settings, BvhPartCache* parts = nullptr);

// The camera's fields of FrameParams (eye, projection, forward, right, up)
// for a width x height image: what shaders/camera.glsl's generateCameraRay reads.
void packCamera(const Camera& camera, int width, int height, gpu::FrameParams& p);

// Only the materials (and the texture slots they name) and the lights of
// packScene, without the shapes or their BVH: what a material or light edit
// re-uploads (Renderer::setMaterials, setLights).
struct GpuShading {
    std::vector<gpu::Material> materials;
    std::vector<std::shared_ptr<const TextureData>> textures;
    std::vector<gpu::Light> lights;
    GpuEnvironment environment;  // its image, if any, is the last of `textures`
};
GpuShading packShading(const Scene& scene);

// Element counts of the scene's device arrays, known before packing: the
// BVH's node count is its bound 2n - 1 for n bounded primitives.
struct SceneArrayCounts {
    uint64_t primitives = 0;
    uint64_t bvhNodes = 0;
    uint64_t materials = 0;
    uint64_t lights = 0;
};
SceneArrayCounts countSceneArrays(const Scene& scene);

// What one scene array may take on the device: the shader reads each array
// through its buffer's device address, so it must fit one VkBuffer
// (maxBufferSize) in one allocation (maxMemoryAllocationSize).
struct BufferLimits {
    uint64_t maxBufferSize = UINT64_MAX;  // unknown without Vulkan 1.3 or VK_KHR_maintenance4
    uint64_t maxAllocationSize = 0;
};

// Why the scene's arrays do not fit the limits (the first array too large,
// its count, bytes and the limit), or nothing when they do.
std::optional<std::string> sceneArraysTooLarge(const SceneArrayCounts& counts, const BufferLimits& limits);

}  // namespace whitted

// The ray-tree inspector: every ray behind one pixel, recorded by the tracer
// itself (the build of shaders/whitted.comp with -DWHITTED_RAY_TREE,
// shaders/ray_tree.glsl) on a Renderer's uploaded scene. The record holds
// each ray's kind, hit, weight, local terms and contribution, and each
// shadow ray's outcome; the contributions add up to the pixel's colour as a
// uniform one-sample render gives it (the pixel's centre sample).
#pragma once

#include "ray_tree_types.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"
#include "vk/context.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace whitted {

struct RayTree {
    int x = 0, y = 0;           // the pixel
    int width = 0, height = 0;  // of the image
    int maxDepth = 0;
    std::vector<gpu::RayTreeRay> rays;  // in the order traced; rays[0] the camera ray
    std::vector<gpu::RayTreeShadowRay> shadowRays;
    std::vector<gpu::RayTreeCrossing> crossings;  // each shadow ray's in order along it (by t)
    uint32_t dropped = 0;  // rays, shadow rays or crossings beyond the record's capacity (ray_tree_types.h)

    // The sum of the rays' contributions: the pixel's colour.
    glm::vec3 color() const;
    // The rays spawned by ray i, in the order traced.
    std::vector<uint32_t> children(uint32_t i) const;
    // Ray i's shadow rays, and a shadow ray's crossings, as far as the
    // record holds them (what did not fit is counted in `dropped`).
    std::span<const gpu::RayTreeShadowRay> shadowRaysOf(uint32_t i) const;
    std::span<const gpu::RayTreeCrossing> crossingsOf(const gpu::RayTreeShadowRay& shadow) const;
    // The one walk of the tree, for every view of it (the text of `whitted
    // trace`, the window's panel): depth first from each root (the camera
    // ray), a ray's children in the order traced. enter(ray, level) comes
    // first (level 0 for a root) and says whether to go into the ray's
    // children; leave(ray) follows them, for each ray entered into.
    void walk(const std::function<bool(uint32_t ray, int level)>& enter,
              const std::function<void(uint32_t ray)>& leave = {}) const;
};

// Names for the record's tags: "camera", "reflection", "refraction",
// "total internal reflection"; "lit", "blocked", "filtered"; "sphere", ...
const char* rayKindName(uint32_t kind);
const char* shadowOutcomeName(uint32_t outcome);
const char* shapeName(uint32_t shape);
// The object a material index belongs to, as the text shows it: `object 2
// "glass ball"` (the name where it has one); a csg part's own material:
// `csg part material 7`.
std::string objectLabel(const Scene& scene, uint32_t material);
// The tree as indented text: one line a ray (kind, depth, object, t,
// contribution), its shadow rays beneath it, then its children.
std::string rayTreeText(const RayTree& tree, const Scene& scene);

// The settings a ray tree is recorded with (`whitted trace`, Python's
// trace_pixel): one sample through the pixel's centre, uniform, no auxiliary
// layers, the whole image in one band.
RenderSettings rayTreeSettings(int width, int height, int maxDepth);

// Runs the recording build beside one Renderer: its pipeline is built on
// the first trace and again when the renderer's path or specialization
// changes (a new scene), so the window can trace pixel after pixel.
class RayTreeRecorder {
public:
    explicit RayTreeRecorder(VulkanContext& ctx);
    // The tree of pixel (x, y) of `renderer`'s image with its current scene
    // and camera. Throws std::invalid_argument for a pixel outside the image.
    RayTree trace(const Renderer& renderer, int x, int y);

private:
    VulkanContext& ctx_;
    MirroredBuffer record_;  // one gpu::RayTreeRecord, written by the shader, read by the host
    ComputePipeline pipeline_;
    std::optional<std::pair<TracePath, Specialization>> builtFor_;
};

}  // namespace whitted

#include "render/ray_tree.h"

#include "render/bands.h"
#include "render/device_policy.h"
#include "tracer_types.h"

#include "whitted_comp_ray_tree.h"            // kWhittedCompRayTreeSpv: shaders/whitted.comp with -DWHITTED_RAY_TREE
#include "whitted_comp_ray_tree_ray_query.h"  // kWhittedCompRayTreeRayQuerySpv: the same with -DWHITTED_RAY_QUERY

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>

namespace whitted {

// The recorder's structs as the shader lays them out (std430; ray_tree_types.h).
static_assert(sizeof(gpu::RayTreeRay) == 160 && offsetof(gpu::RayTreeRay, origin) == 0 &&
              offsetof(gpu::RayTreeRay, kind) == 12 && offsetof(gpu::RayTreeRay, direction) == 16 &&
              offsetof(gpu::RayTreeRay, depth) == 28 && offsetof(gpu::RayTreeRay, point) == 32 &&
              offsetof(gpu::RayTreeRay, t) == 44 && offsetof(gpu::RayTreeRay, normal) == 48 &&
              offsetof(gpu::RayTreeRay, primitive) == 60 && offsetof(gpu::RayTreeRay, weight) == 64 &&
              offsetof(gpu::RayTreeRay, material) == 76 && offsetof(gpu::RayTreeRay, ambient) == 80 &&
              offsetof(gpu::RayTreeRay, shape) == 92 && offsetof(gpu::RayTreeRay, diffuse) == 96 &&
              offsetof(gpu::RayTreeRay, frontFace) == 108 && offsetof(gpu::RayTreeRay, specular) == 112 &&
              offsetof(gpu::RayTreeRay, parent) == 124 && offsetof(gpu::RayTreeRay, emission) == 128 &&
              offsetof(gpu::RayTreeRay, firstShadowRay) == 140 && offsetof(gpu::RayTreeRay, contribution) == 144 &&
              offsetof(gpu::RayTreeRay, shadowRayCount) == 156);
static_assert(sizeof(gpu::RayTreeShadowRay) == 128 && offsetof(gpu::RayTreeShadowRay, origin) == 0 &&
              offsetof(gpu::RayTreeShadowRay, ray) == 12 && offsetof(gpu::RayTreeShadowRay, direction) == 16 &&
              offsetof(gpu::RayTreeShadowRay, light) == 28 && offsetof(gpu::RayTreeShadowRay, visibility) == 32 &&
              offsetof(gpu::RayTreeShadowRay, distance) == 44 && offsetof(gpu::RayTreeShadowRay, diffuse) == 48 &&
              offsetof(gpu::RayTreeShadowRay, outcome) == 60 && offsetof(gpu::RayTreeShadowRay, specular) == 64 &&
              offsetof(gpu::RayTreeShadowRay, blocker) == 76 && offsetof(gpu::RayTreeShadowRay, transmittance) == 80 &&
              offsetof(gpu::RayTreeShadowRay, blockerT) == 92 && offsetof(gpu::RayTreeShadowRay, absorption) == 96 &&
              offsetof(gpu::RayTreeShadowRay, firstCrossing) == 108 &&
              offsetof(gpu::RayTreeShadowRay, crossingCount) == 112 &&
              offsetof(gpu::RayTreeShadowRay, blockerMaterial) == 116 &&
              offsetof(gpu::RayTreeShadowRay, droppedCrossings) == 120);
static_assert(sizeof(gpu::RayTreeCrossing) == 32 && offsetof(gpu::RayTreeCrossing, filterColour) == 0 &&
              offsetof(gpu::RayTreeCrossing, t) == 12 && offsetof(gpu::RayTreeCrossing, primitive) == 16 &&
              offsetof(gpu::RayTreeCrossing, material) == 20);
static_assert(offsetof(gpu::RayTreeRecord, rayCount) == 0 && offsetof(gpu::RayTreeRecord, dropped) == 12 &&
              offsetof(gpu::RayTreeRecord, rays) == 16 &&
              offsetof(gpu::RayTreeRecord, shadowRays) == 16 + gpu::kRayTreeMaxRays * sizeof(gpu::RayTreeRay) &&
              offsetof(gpu::RayTreeRecord, crossings) ==
                  offsetof(gpu::RayTreeRecord, shadowRays) + gpu::kRayTreeMaxShadowRays * sizeof(gpu::RayTreeShadowRay));

glm::vec3 RayTree::color() const {
    glm::vec3 sum(0.0f);
    for (const gpu::RayTreeRay& r : rays) sum += r.contribution;
    return sum;
}

std::vector<uint32_t> RayTree::children(uint32_t i) const {
    std::vector<uint32_t> out;
    for (uint32_t j = 0; j < rays.size(); ++j)
        if (rays[j].parent == i) out.push_back(j);
    return out;
}

std::span<const gpu::RayTreeShadowRay> RayTree::shadowRaysOf(uint32_t i) const {
    const gpu::RayTreeRay& r = rays[i];
    size_t first = std::min<size_t>(r.firstShadowRay, shadowRays.size());
    return std::span(shadowRays).subspan(first, std::min<size_t>(r.shadowRayCount, shadowRays.size() - first));
}

std::span<const gpu::RayTreeCrossing> RayTree::crossingsOf(const gpu::RayTreeShadowRay& shadow) const {
    size_t first = std::min<size_t>(shadow.firstCrossing, crossings.size());
    return std::span(crossings).subspan(first, std::min<size_t>(shadow.crossingCount, crossings.size() - first));
}

void RayTree::walk(const std::function<bool(uint32_t, int)>& enter, const std::function<void(uint32_t)>& leave) const {
    // Each ray's children in the order traced (a ray's parent is traced
    // before it), then a walk with an explicit stack: (ray, level, entered).
    std::vector<std::vector<uint32_t>> childrenOf(rays.size());
    std::vector<uint32_t> roots;
    for (uint32_t j = 0; j < rays.size(); ++j)
        (rays[j].parent < rays.size() ? childrenOf[rays[j].parent] : roots).push_back(j);
    struct Step {
        uint32_t ray;
        int level;
        bool leaving;
    };
    std::vector<Step> stack;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root) stack.push_back({*root, 0, false});
    while (!stack.empty()) {
        Step step = stack.back();
        stack.pop_back();
        if (step.leaving) {
            if (leave) leave(step.ray);
            continue;
        }
        if (!enter(step.ray, step.level)) continue;
        stack.push_back({step.ray, step.level, true});
        const std::vector<uint32_t>& children = childrenOf[step.ray];
        for (auto c = children.rbegin(); c != children.rend(); ++c) stack.push_back({*c, step.level + 1, false});
    }
}

const char* rayKindName(uint32_t kind) {
    switch (kind) {
        case gpu::kRayCamera: return "camera";
        case gpu::kRayReflection: return "reflection";
        case gpu::kRayRefraction: return "refraction";
        case gpu::kRayTotalInternal: return "total internal reflection";
        default: return "unknown";
    }
}

const char* shadowOutcomeName(uint32_t outcome) {
    switch (outcome) {
        case gpu::kShadowLit: return "lit";
        case gpu::kShadowBlocked: return "blocked";
        case gpu::kShadowFiltered: return "filtered";
        default: return "unknown";
    }
}

const char* shapeName(uint32_t shape) {
    switch (shape) {
        case gpu::kShapeSphere: return "sphere";
        case gpu::kShapeCylinder: return "cylinder";
        case gpu::kShapePlane: return "plane";
        case gpu::kShapeTriangle: return "triangle";
        case gpu::kShapeBox: return "box";
        case gpu::kShapeCsg: return "csg";
        default: return "unknown";
    }
}

std::string objectLabel(const Scene& scene, uint32_t material) {
    if (material >= scene.objects.size()) return "csg part material " + std::to_string(material);
    std::string label = "object " + std::to_string(material);
    if (!scene.objects[material].name.empty()) label += " \"" + scene.objects[material].name + "\"";
    return label;
}

namespace {
std::string rgb(glm::vec3 c) {
    char text[64];
    std::snprintf(text, sizeof text, "(%.6g %.6g %.6g)", c.r, c.g, c.b);
    return text;
}
}  // namespace

std::string rayTreeText(const RayTree& tree, const Scene& scene) {
    std::string out = "pixel " + std::to_string(tree.x) + "," + std::to_string(tree.y) + " of " +
                      std::to_string(tree.width) + "x" + std::to_string(tree.height) + ", max depth " +
                      std::to_string(tree.maxDepth) + ": colour " + rgb(tree.color()) + ", " +
                      std::to_string(tree.rays.size()) + " rays, " + std::to_string(tree.shadowRays.size()) +
                      " shadow rays\n";
    if (tree.dropped > 0)
        out += "(not fully recorded: " + std::to_string(tree.dropped) +
               " rays, shadow rays or crossings did not fit the record and are left out)\n";
    tree.walk([&](uint32_t i, int indent) {
        const gpu::RayTreeRay& r = tree.rays[i];
        std::string pad(size_t(2 * indent), ' ');
        out += pad + rayKindName(r.kind) + " [depth " + std::to_string(r.depth) + "] ";
        if (r.primitive == gpu::kNoObject) {
            out += "misses (background)";
        } else {
            char t[32];
            std::snprintf(t, sizeof t, "%.6g", r.t);
            out += std::string(shapeName(r.shape)) + " of " + objectLabel(scene, r.material) + " at t " + t +
                   (r.frontFace ? " (outside)" : " (inside)");
        }
        out += "  contribution " + rgb(r.contribution) + "\n";
        for (const gpu::RayTreeShadowRay& sr : tree.shadowRaysOf(i)) {
            out += pad + "  shadow ray to light " + std::to_string(sr.light) + ": " + shadowOutcomeName(sr.outcome);
            if (sr.outcome == gpu::kShadowBlocked) out += " by " + objectLabel(scene, sr.blockerMaterial);
            if (sr.outcome == gpu::kShadowFiltered && sr.crossingCount > 0) {
                out += " by";
                for (const gpu::RayTreeCrossing& c : tree.crossingsOf(sr))
                    out += " " + objectLabel(scene, c.material) + " " + rgb(c.filterColour);
            }
            if (sr.droppedCrossings > 0)
                out += " (and " + std::to_string(sr.droppedCrossings) + " crossings not recorded)";
            out += "  diffuse " + rgb(sr.diffuse) + " specular " + rgb(sr.specular) + "\n";
        }
        return true;
    });
    return out;
}

RayTreeRecorder::RayTreeRecorder(VulkanContext& ctx) : ctx_(ctx) {
    DeviceActivity activity(*ctx.events, "making the ray tree's record");
    record_ = MirroredBuffer(ctx, sizeof(gpu::RayTreeRecord),
                             vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress);
}

RayTree RayTreeRecorder::trace(const Renderer& renderer, int x, int y) {
    if (x < 0 || y < 0 || x >= renderer.width() || y >= renderer.height())
        throw std::invalid_argument("pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                                    std::to_string(renderer.width()) + "x" + std::to_string(renderer.height()) +
                                    " image");
    // The recording build with the renderer's specialization and a set
    // layout made as the renderer's, so that its descriptor set binds here.
    std::pair<TracePath, Specialization> key{renderer.trace(), renderer.specialization()};
    if (builtFor_ != key) {
        std::span<const uint32_t> spirv = key.first == TracePath::RayQuery
                                              ? std::span<const uint32_t>(kWhittedCompRayTreeRayQuerySpv)
                                              : std::span<const uint32_t>(kWhittedCompRayTreeSpv);
        pipeline_ = createTracerPipeline(ctx_, spirv, key.first, key.second, sizeof(gpu::TileParams));
        builtFor_ = key;
    }

    constexpr size_t kHeader = offsetof(gpu::RayTreeRecord, rays);
    std::memset(record_.host(), 0, kHeader);
    vk::DeviceAddress address = record_.device().address;
    // One pixel, its centre sample (a pattern of one), nothing written to
    // the renderer's sums (an empty output rectangle).
    gpu::TileParams tile{.tileOrigin = glm::uvec2(uint32_t(x), uint32_t(y)),
                         .tileSize = glm::uvec2(1, 1),
                         .firstSample = 0,
                         .sampleCount = 1,
                         .patternSize = 1,
                         .outputOrigin = glm::uvec2(0, 0),
                         .outputSize = glm::uvec2(0, 0),
                         .rayTreeAddress = glm::uvec2(uint32_t(address), uint32_t(address >> 32))};
    DeviceActivity activity(*ctx_.events,
                            "tracing the ray tree of pixel " + std::to_string(x) + "," + std::to_string(y));
    ctx_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
        record_.recordUpload(cmd, kHeader);
        cmd.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_.pipeline);
        cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline_.layout, 0, renderer.descriptorSet(), nullptr);
        recordDispatch(cmd, pipeline_, tile, 1, 1);
        record_.recordDownload(cmd, sizeof(gpu::RayTreeRecord));
        vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eShaderWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eHostRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eHost, {}, toHost,
                            nullptr, nullptr);
    });

    const auto* record = static_cast<const gpu::RayTreeRecord*>(record_.host());
    RayTree tree;
    tree.x = x;
    tree.y = y;
    tree.width = renderer.width();
    tree.height = renderer.height();
    tree.maxDepth = renderer.settings().maxDepth;
    tree.rays.assign(record->rays, record->rays + std::min(record->rayCount, gpu::kRayTreeMaxRays));
    tree.shadowRays.assign(record->shadowRays,
                           record->shadowRays + std::min(record->shadowRayCount, gpu::kRayTreeMaxShadowRays));
    tree.crossings.assign(record->crossings,
                          record->crossings + std::min(record->crossingCount, gpu::kRayTreeMaxCrossings));
    tree.dropped = record->dropped;
    // The walk finds a shadow ray's crossings in the BVH's order (or the
    // driver's): each shadow ray's are put in order along it.
    for (const gpu::RayTreeShadowRay& s : tree.shadowRays) {
        size_t first = std::min<size_t>(s.firstCrossing, tree.crossings.size());
        size_t end = std::min<size_t>(first + s.crossingCount, tree.crossings.size());
        std::stable_sort(tree.crossings.begin() + ptrdiff_t(first), tree.crossings.begin() + ptrdiff_t(end),
                         [](const gpu::RayTreeCrossing& a, const gpu::RayTreeCrossing& b) { return a.t < b.t; });
    }
    return tree;
}

RenderSettings rayTreeSettings(int width, int height, int maxDepth) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.maxDepth = maxDepth;
    settings.samplesPerPixel = 1;
    settings.antiAliasing = AntiAliasing::Uniform;
    settings.auxiliary = false;
    settings.bandBytes = 0;
    return settings;
}

}  // namespace whitted

#include "output/render_record.h"

#include "scene/shape_edit.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include <ctime>
#include <fstream>
#include <stdexcept>
#include <sys/resource.h>
#include <unistd.h>

namespace whitted {
namespace {

std::string timestamp(const char* format) {
    std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char buf[64];
    std::strftime(buf, sizeof buf, format, &local);
    return buf;
}

// The csg children with their own materials, in the order the packer gives
// them material indices (host/shapes/csg.cpp, emitCsg: depth first).
void appendChildMaterials(const Csg& csg, size_t object, nlohmann::ordered_json& out) {
    for (const CsgChild& child : csg.children) {
        if (child.ownMaterial)
            out.push_back({{"id", out.size()}, {"name", ""}, {"object", object}, {"line", child.sourceLine}});
        if (const Csg* nested = std::get_if<Csg>(&child.shape)) appendChildMaterials(*nested, object, out);
    }
}

// Instance i is object objects.size() + i, naming its prototype; the
// materials follow render/gpu_instances.h: each prototype object's, then
// each instance's own.
void appendInstances(const Scene& scene, nlohmann::ordered_json& objects, nlohmann::ordered_json& materials) {
    for (const Prototype& p : scene.prototypes)
        for (const Object& o : p.objects)
            materials.push_back(
                {{"id", materials.size()}, {"name", o.name}, {"prototype", p.name}, {"line", o.sourceLine}});
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        size_t id = scene.objects.size() + i;
        objects.push_back({{"id", id}, {"name", instance.name}, {"shape", "instance"},
                           {"prototype", scene.prototypes[instance.prototype].name}, {"line", instance.sourceLine}});
        if (instance.material)
            materials.push_back(
                {{"id", materials.size()}, {"name", instance.name}, {"object", id}, {"line", instance.sourceLine}});
    }
}

}  // namespace

nlohmann::ordered_json maskLegend(const Scene& scene) {
    // Object k's material is material k (its name the object's); the csg
    // children's own materials follow.
    nlohmann::ordered_json objects = nlohmann::ordered_json::array(), materials = nlohmann::ordered_json::array();
    for (size_t k = 0; k < scene.objects.size(); ++k) {
        const Object& o = scene.objects[k];
        objects.push_back({{"id", k}, {"name", o.name}, {"shape", shapeName(o.shape)}, {"line", o.sourceLine}});
        materials.push_back({{"id", k}, {"name", o.name}, {"object", k}, {"line", o.sourceLine}});
    }
    for (size_t k = 0; k < scene.objects.size(); ++k)
        if (const Csg* csg = std::get_if<Csg>(&scene.objects[k].shape)) appendChildMaterials(*csg, k, materials);
    appendInstances(scene, objects, materials);
    return {{"background", 0xffffffffu}, {"objects", objects}, {"materials", materials}};
}

std::string renderRecordJson(const RenderRecord& r) {
    const RenderResult& res = *r.result;
    double seconds = res.renderSeconds > 0 ? res.renderSeconds : 1e-9;
    // Peak resident memory of this process so far (Linux reports KiB).
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::vector<std::string> files;
    for (const std::filesystem::path& f : r.files) files.push_back(f.filename().string());

    // ordered_json: the keys stay in this order in the file.
    nlohmann::ordered_json j = {
        {"whitted_version", WHITTED_VERSION},
        {"created", timestamp("%Y-%m-%dT%H:%M:%S%z")},
        {"scene", r.scenePath.string()},
        {"settings",
         {{"width", res.width},
          {"height", res.height},
          {"spp", r.settings.samplesPerPixel},
          {"max_depth", r.settings.maxDepth},
          {"aov_bounces", r.settings.aovBounces},
          {"tonemap", r.tonemap},
          {"aa", r.settings.antiAliasing == AntiAliasing::Adaptive ? "adaptive" : "uniform"},
          {"aa_threshold", r.settings.aaThreshold},
          {"trace", res.trace == TracePath::RayQuery ? "rayquery" : "bvh"},
          {"full_width", res.layout.fullWidth},
          {"full_height", res.layout.fullHeight},
          {"region", {res.layout.region.x0, res.layout.region.y0, res.layout.region.x1, res.layout.region.y1}},
          {"exposure", r.exposure},
          {"camera", r.camera}}},
        {"sampling",
         {{"camera_samples", res.samplesTaken},
          {"bands", res.bands},
          {"mean_spp", double(res.samplesTaken) / std::max(1.0, double(res.width) * res.height)}}},
        {"device", {{"name", r.device.name}, {"type", r.device.type}, {"driver", r.device.driver}}},
        {"devices", 1 + r.sharedWith.size()},
        {"timings_s",
         {{"load", r.loadSeconds},
          {"bvh_build", res.bvh.buildSeconds},
          {"acceleration_structure_build", res.accelerationStructureSeconds},
          {"pipeline", res.pipelineSeconds},
          {"upload", res.uploadSeconds},
          {"render", res.renderSeconds}}},
        {"bvh",
         {{"nodes", res.bvh.nodeCount},
          {"wide_nodes", res.bvh.wideNodeCount},
          {"leaves", res.bvh.leafCount},
          {"max_depth", res.bvh.maxDepth},
          {"sah_cost", res.bvh.sahCost},
          {"parts", res.bvh.parts},
          {"parts_reused", res.bvh.partsReused},
          {"primitives_built", res.bvh.primitivesBuilt}}},
        {"memory_bytes", {{"device_buffers", res.deviceBytes}, {"peak_rss", uint64_t(usage.ru_maxrss) * 1024}}},
        {"lost_samples", res.lostSamples},
        {"rays",
         {{"primary", res.rays.primary},
          {"shadow", res.rays.shadow},
          {"secondary", res.rays.secondary},
          {"per_second", double(res.rays.total()) / seconds}}},
        {"files", files},
    };
    if (r.masks) j["masks"] = maskLegend(*r.masks);
    // Only where the scene had warnings: the record of a clean scene is unchanged.
    if (!r.warnings.empty()) j["warnings"] = r.warnings;
    if (!r.warningDetails.empty()) j["warning_details"] = r.warningDetails;
    // A path that is not valid UTF-8 is written with U+FFFD rather than refused.
    return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

std::filesystem::path writeHistoryFolder(const std::filesystem::path& root,
                                         const std::function<void(const std::filesystem::path& staging)>& fill) {
    std::filesystem::create_directories(root);
    std::filesystem::path staging = root / (".partial-" + std::to_string(::getpid()) + "-" + timestamp("%H%M%S"));
    std::filesystem::create_directory(staging);
    try {
        fill(staging);
    } catch (...) {
        std::filesystem::remove_all(staging);
        throw;
    }
    std::string base = timestamp("%Y-%m-%d_%H-%M-%S");
    for (int n = 1;; ++n) {
        std::filesystem::path target = root / (n == 1 ? base : base + "_" + std::to_string(n));
        if (std::filesystem::exists(target)) continue;
        std::filesystem::rename(staging, target);
        return target;
    }
}

}  // namespace whitted

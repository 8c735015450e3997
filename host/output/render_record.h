// The render history (the seed's timestamped folders): each render without
// -o goes into renders/YYYY-MM-DD_HH-MM-SS/ with its images, a copy of the
// scene and render.json describing settings, device and timings.
#pragma once

#include "io/atomic_file.h"
#include "render/render_result.h"
#include "scene/scene.h"
#include "vk/device_info.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace whitted {

struct RenderRecord {
    std::filesystem::path scenePath;
    RenderSettings settings;
    std::string tonemap;
    DeviceInfo device;
    std::vector<DeviceInfo> sharedWith;  // further devices that rendered bands (--device all)
    const RenderResult* result = nullptr;
    std::vector<std::filesystem::path> files;
    double loadSeconds = 0;  // reading and checking the scene file
    // The scene's warnings and the lines they sum up (Scene::warningDetails).
    std::vector<std::string> warnings;
    std::vector<std::string> warningDetails;
    // With mask images (object_id, material_id): the scene whose objects and
    // materials their ids index; the record then lists them ("masks").
    const Scene* masks = nullptr;
    double exposure = 0;  // --exposure EV
    std::string camera;   // --camera INDEX|NAME as given; empty: the scene's (a model's first) camera
};

// The masks' legend: index -> name of every object and every material, as
// the ids of object_id and material_id number them (README "Auxiliary images").
nlohmann::ordered_json maskLegend(const Scene& scene);

// The record as JSON text.
std::string renderRecordJson(const RenderRecord& record);

// A new history entry under `root` (the seed's renders/ folder): `fill`
// writes every file into a staging folder, which is then renamed to the
// next free timestamped name and returned. If `fill` throws, the staging
// folder is removed, so an interrupted render never leaves a half-filled entry.
std::filesystem::path writeHistoryFolder(const std::filesystem::path& root,
                                         const std::function<void(const std::filesystem::path& staging)>& fill);

}  // namespace whitted

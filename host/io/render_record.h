// The render history (the seed's timestamped folders): each render without
// -o goes into renders/YYYY-MM-DD_HH-MM-SS/ with its images, a copy of the
// scene and render.json describing settings, device and timings.
#pragma once

#include "render/renderer.h"
#include "vk/context.h"

#include <filesystem>
#include <string>
#include <vector>

namespace whitted {

struct RenderRecord {
    std::filesystem::path scenePath;
    RenderSettings settings;
    std::string tonemap;
    DeviceInfo device;
    const RenderResult* result = nullptr;
    std::vector<std::filesystem::path> files;
    double loadSeconds = 0;  // reading and checking the scene file
};

// The record as JSON text.
std::string renderRecordJson(const RenderRecord& record);

// A new, empty staging folder for a history entry under `root`; commit it
// with commitHistoryFolder once every file is written, so that an
// interrupted render never leaves a half-filled entry.
std::filesystem::path beginHistoryFolder(const std::filesystem::path& root);
std::filesystem::path commitHistoryFolder(const std::filesystem::path& staging, const std::filesystem::path& root);

// Writes text to a file atomically (temporary file, then rename).
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace whitted

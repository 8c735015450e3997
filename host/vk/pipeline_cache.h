// Compiled pipelines kept between runs: a VkPipelineCache seeded from, and
// saved to, one file per device under the user's cache folder, so that the
// driver's compilation of the shaders is paid once rather than on every run.
// The cache is an optimisation only: a missing, stale or corrupt file is
// ignored, and a folder that cannot be written costs one warning line.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>
#include <vulkan/vulkan_raii.hpp>

namespace whitted {

// Where the cache files go: WHITTED_PIPELINE_CACHE names the folder, or turns
// the cache off when "0" (an empty path is returned then); unset, it is
// $XDG_CACHE_HOME/whitted, else ~/.cache/whitted (XDG Base Directory spec).
std::filesystem::path pipelineCacheFolderFromEnvironment();

// The file for a device: the data of one cache fits one device and driver
// build only, so its name holds vendorID, deviceID, driverVersion and
// pipelineCacheUUID.
std::string pipelineCacheFileName(const vk::PhysicalDeviceProperties& properties);

// Whether `data` starts with the VkPipelineCacheHeaderVersionOne this device
// writes (Vulkan spec, "Pipeline Cache": fields least significant byte first,
// whatever the host's byte order).
bool pipelineCacheHeaderMatches(std::span<const uint8_t> data, const vk::PhysicalDeviceProperties& properties);

class PipelineCache {
public:
    // Seeds the cache from `folder`/pipelineCacheFileName() when that file is
    // whole and made by this device and driver. An empty folder: in memory
    // only, nothing read or written.
    PipelineCache(const vk::raii::Device& device, const vk::PhysicalDeviceProperties& properties,
                  const std::filesystem::path& folder);

    // The cache to create pipelines with (a null one if even an empty cache
    // could not be created).
    const vk::raii::PipelineCache& cache() const { return cache_; }
    const std::filesystem::path& file() const { return file_; }  // empty when not persisted
    bool seededFromFile() const { return seeded_; }

    // Writes the cache's contents to file() (temporary file, then rename) if
    // they changed since they were read or last written. Never throws: the
    // first failure prints one warning on stderr, later ones nothing.
    void save();

private:
    vk::raii::PipelineCache cache_{nullptr};
    std::filesystem::path file_;
    uint64_t savedHash_ = 0;  // of the contents on disk, to skip writing them again
    bool seeded_ = false;
    bool warned_ = false;
};

}  // namespace whitted

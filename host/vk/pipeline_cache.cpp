#include "vk/pipeline_cache.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

namespace whitted {
namespace {

// The file: this prefix, then the bytes vkGetPipelineCacheData returned. Its
// size and hash catch a truncated or damaged file before the driver is given
// it; the Vulkan header alone would not, and not every driver survives bad
// data behind a good header.
constexpr char kMagic[8] = {'w', 'h', 'i', 't', 't', 'e', 'd', 'P'};
struct FilePrefix {
    char magic[8];
    uint64_t dataSize;
    uint64_t dataHash;
};

// A file larger than this is not read back: the cache is then rebuilt from
// this run's pipelines alone, which bounds its growth when scenes ask for many
// shader specialisations.
constexpr uintmax_t kMaxFileBytes = 64u << 20;

// FNV-1a, 64 bits.
uint64_t hashBytes(std::span<const uint8_t> data) {
    uint64_t h = 14695981039346656037ull;
    for (uint8_t b : data) h = (h ^ b) * 1099511628211ull;
    return h;
}

uint32_t readLittleEndian32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

std::string hex(uint64_t value, int digits) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%0*llx", digits, static_cast<unsigned long long>(value));
    return buf;
}

// The driver's data from `file`, or nothing when the file is missing, too
// large, damaged or made for another device or driver.
std::vector<uint8_t> readCacheFile(const std::filesystem::path& file, const vk::PhysicalDeviceProperties& properties) {
    std::error_code ec;
    uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec || size < sizeof(FilePrefix) || size > kMaxFileBytes) return {};
    std::ifstream in(file, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < sizeof(FilePrefix)) return {};
    FilePrefix prefix;
    std::memcpy(&prefix, bytes.data(), sizeof prefix);
    std::span<const uint8_t> data = std::span<const uint8_t>(bytes).subspan(sizeof prefix);
    if (std::memcmp(prefix.magic, kMagic, sizeof kMagic) != 0 || prefix.dataSize != data.size() ||
        prefix.dataHash != hashBytes(data) || !pipelineCacheHeaderMatches(data, properties))
        return {};
    return {data.begin(), data.end()};
}

}  // namespace

std::filesystem::path pipelineCacheFolderFromEnvironment() {
    auto variable = [](const char* name) -> std::string {
        const char* value = std::getenv(name);
        return value ? value : "";
    };
    std::string setting = variable("WHITTED_PIPELINE_CACHE");
    if (setting == "0") return {};
    if (!setting.empty()) return setting;
    // The XDG spec: a relative path in XDG_CACHE_HOME is invalid, ignore it.
    std::filesystem::path xdg = variable("XDG_CACHE_HOME");
    if (xdg.is_absolute()) return xdg / "whitted";
    std::filesystem::path home = variable("HOME");
    if (home.is_absolute()) return home / ".cache" / "whitted";
    return {};
}

std::string pipelineCacheFileName(const vk::PhysicalDeviceProperties& properties) {
    std::string uuid;
    for (uint8_t b : properties.pipelineCacheUUID) uuid += hex(b, 2);
    return "pipelines-" + hex(properties.vendorID, 4) + "-" + hex(properties.deviceID, 4) + "-" +
           hex(properties.driverVersion, 8) + "-" + uuid + ".bin";
}

bool pipelineCacheHeaderMatches(std::span<const uint8_t> data, const vk::PhysicalDeviceProperties& properties) {
    constexpr size_t kHeaderSize = sizeof(VkPipelineCacheHeaderVersionOne);  // 32
    if (data.size() < kHeaderSize) return false;
    uint32_t headerSize = readLittleEndian32(&data[0]);
    return headerSize >= kHeaderSize && headerSize <= data.size() &&
           readLittleEndian32(&data[4]) == uint32_t(VK_PIPELINE_CACHE_HEADER_VERSION_ONE) &&
           readLittleEndian32(&data[8]) == properties.vendorID &&
           readLittleEndian32(&data[12]) == properties.deviceID &&
           std::memcmp(&data[16], properties.pipelineCacheUUID.data(), VK_UUID_SIZE) == 0;
}

PipelineCache::PipelineCache(const vk::raii::Device& device, const vk::PhysicalDeviceProperties& properties,
                             const std::filesystem::path& folder) {
    if (!folder.empty()) file_ = folder / pipelineCacheFileName(properties);
    std::vector<uint8_t> initial = file_.empty() ? std::vector<uint8_t>{} : readCacheFile(file_, properties);
    try {
        cache_ = vk::raii::PipelineCache(
            device, vk::PipelineCacheCreateInfo{.initialDataSize = initial.size(), .pInitialData = initial.data()});
        seeded_ = !initial.empty();
        if (seeded_) savedHash_ = hashBytes(initial);
    } catch (const vk::SystemError&) {
        // The driver refused the data after all: start empty.
        try {
            cache_ = vk::raii::PipelineCache(device, vk::PipelineCacheCreateInfo{});
        } catch (const vk::SystemError&) {
            // Out of memory for even that: pipelines are then created uncached.
        }
    }
}

void PipelineCache::save() {
    if (file_.empty() || !*cache_) return;
    std::filesystem::path temporary;
    try {
        std::vector<uint8_t> data = cache_.getData();
        uint64_t hash = hashBytes(data);
        if (data.empty() || hash == savedHash_) return;
        FilePrefix prefix{};
        std::memcpy(prefix.magic, kMagic, sizeof kMagic);
        prefix.dataSize = data.size();
        prefix.dataHash = hash;

        // A name of its own per process, so that two runs saving at once each
        // rename a whole file into place.
        std::filesystem::create_directories(file_.parent_path());
        temporary =
            file_.parent_path() / ("." + file_.filename().string() + "." + std::to_string(::getpid()) + ".partial");
        {
            std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
            out.write(reinterpret_cast<const char*>(&prefix), sizeof prefix);
            out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
            if (!out.flush()) throw std::runtime_error("cannot write " + temporary.string());
        }
        std::filesystem::rename(temporary, file_);
        savedHash_ = hash;
    } catch (const std::exception& e) {
        std::error_code ignored;
        if (!temporary.empty()) std::filesystem::remove(temporary, ignored);
        if (!warned_)
            std::fprintf(stderr,
                         "whitted: warning: pipeline cache not saved (%s); shaders will be compiled again next run "
                         "(WHITTED_PIPELINE_CACHE=0 turns the cache off)\n",
                         e.what());
        warned_ = true;
    }
}

}  // namespace whitted

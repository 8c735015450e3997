#include "io/render_record.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/resource.h>
#include <unistd.h>

namespace whitted {
namespace {

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

std::string timestamp(const char* format) {
    std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char buf[64];
    std::strftime(buf, sizeof buf, format, &local);
    return buf;
}

}  // namespace

std::string renderRecordJson(const RenderRecord& r) {
    const RenderResult& res = *r.result;
    double seconds = res.renderSeconds > 0 ? res.renderSeconds : 1e-9;
    std::ostringstream j;
    j << "{\n";
    j << "  \"whitted_version\": " << jsonString(WHITTED_VERSION) << ",\n";
    j << "  \"created\": " << jsonString(timestamp("%Y-%m-%dT%H:%M:%S%z")) << ",\n";
    j << "  \"scene\": " << jsonString(r.scenePath.string()) << ",\n";
    j << "  \"settings\": {\"width\": " << res.width << ", \"height\": " << res.height
      << ", \"spp\": " << r.settings.samplesPerPixel << ", \"max_depth\": " << r.settings.maxDepth
      << ", \"tonemap\": " << jsonString(r.tonemap) << ", \"aa\": "
      << jsonString(r.settings.antiAliasing == AntiAliasing::Adaptive ? "adaptive" : "uniform")
      << ", \"aa_threshold\": " << r.settings.aaThreshold << ", \"full_width\": " << res.layout.fullWidth
      << ", \"full_height\": " << res.layout.fullHeight << ", \"region\": [" << res.layout.region.x0 << ", "
      << res.layout.region.y0 << ", " << res.layout.region.x1 << ", " << res.layout.region.y1 << "]},\n";
    j << "  \"sampling\": {\"camera_samples\": " << res.samplesTaken << ", \"mean_spp\": "
      << double(res.samplesTaken) / std::max(1.0, double(res.width) * res.height) << ", \"bands\": " << res.bands
      << "},\n";
    j << "  \"device\": {\"name\": " << jsonString(r.device.name) << ", \"type\": " << jsonString(r.device.type)
      << ", \"driver\": " << jsonString(r.device.driver) << "},\n";
    j << "  \"timings_s\": {\"load\": " << r.loadSeconds << ", \"bvh_build\": " << res.bvh.buildSeconds
      << ", \"pipeline\": " << res.pipelineSeconds << ", \"upload\": " << res.uploadSeconds
      << ", \"render\": " << res.renderSeconds << "},\n";
    j << "  \"bvh\": {\"nodes\": " << res.bvh.nodeCount << ", \"leaves\": " << res.bvh.leafCount
      << ", \"max_depth\": " << res.bvh.maxDepth << ", \"sah_cost\": " << res.bvh.sahCost << "},\n";
    // Peak resident memory of this process so far (Linux reports KiB).
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    j << "  \"memory_bytes\": {\"device_buffers\": " << res.deviceBytes
      << ", \"peak_rss\": " << uint64_t(usage.ru_maxrss) * 1024 << "},\n";
    j << "  \"lost_samples\": " << res.lostSamples << ",\n";
    j << "  \"rays\": {\"primary\": " << res.rays.primary << ", \"shadow\": " << res.rays.shadow
      << ", \"secondary\": " << res.rays.secondary << ", \"per_second\": " << double(res.rays.total()) / seconds
      << "},\n";
    j << "  \"files\": [";
    for (size_t i = 0; i < r.files.size(); ++i)
        j << (i ? ", " : "") << jsonString(r.files[i].filename().string());
    j << "]\n}\n";
    return j.str();
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

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
    std::filesystem::path temporary = path.parent_path() / ("." + path.filename().string() + ".partial");
    {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        if (!out.flush()) throw std::runtime_error(path.string() + ": cannot write file");
    }
    std::filesystem::rename(temporary, path);
}

}  // namespace whitted

// whitted_kit: what tools/gpu_check.sh needs beside whitted on a machine
// with nothing installed (no Python, no numpy, no OpenImageIO). Built for the
// GPU kit (tools/gpu_kit.sh) and with the tests (tests/CMakeLists.txt).
//
//   whitted_kit psnr IMAGE.png REFERENCE.png [--diff DIFF.png]
//       PSNR of two 8-bit images as tools/bench/measures.py's psnr() computes
//       it: RGB on [0, 1], 10 log10(1 / MSE); prints one JSON object
//       {"psnr_db": D or null when identical, "max_abs_diff": codes,
//       "differing_pixels": N}. --diff writes |IMAGE - REFERENCE| x 8 as PNG.
//   whitted_kit measure RECORD.json [RECORD.json...]
//       one whitted render's numbers from its record, as
//       tools/bench/measures.py's whitted_measures() reads them, and the camera
//       plus shadow rays per second (the benchmark's whitted/Embree measure);
//       prints one JSON object. Several records (repeats of one render):
//       {"runs": [...], "median": {render_s, mrays_per_s,
//       primary_shadow_mrays_per_s}}.
//   whitted_kit mesh-obj TRIANGLES OUT.obj
//       the OBJ file of `tools/generate_scenes.py mesh TRIANGLES OUT.xml`, byte
//       for byte (the benchmark's mesh1m: a displaced sphere); the kit carries
//       the generator's XML and the OBJ's SHA-256 and checks the file made.
//
// Exit statuses as whitted's: 0 success, 1 failure (a file not read or not
// written), 2 bad arguments.
#include <png.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

constexpr int kFailure = 1;
constexpr int kBadInput = 2;

// An 8-bit image as RGBA bytes (libpng's simplified API: grey and RGB
// expanded, alpha kept, no colour conversion between 8-bit formats).
struct Rgba8 {
    int width = 0;
    int height = 0;
    std::vector<png_byte> bytes;
};

bool readPng(const std::string& path, Rgba8& out) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str())) {
        std::cerr << "whitted_kit: " << path << ": " << image.message << "\n";
        return false;
    }
    image.format = PNG_FORMAT_RGBA;
    out.width = int(image.width);
    out.height = int(image.height);
    out.bytes.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, out.bytes.data(), 0, nullptr)) {
        std::cerr << "whitted_kit: " << path << ": " << image.message << "\n";
        png_image_free(&image);
        return false;
    }
    return true;
}

int psnrCommand(const std::string& imagePath, const std::string& referencePath, const std::string& diffPath) {
    Rgba8 a, b;
    if (!readPng(imagePath, a) || !readPng(referencePath, b)) return kFailure;
    if (a.width != b.width || a.height != b.height) {
        std::cerr << "whitted_kit: " << imagePath << " is " << a.width << "x" << a.height << ", its reference "
                  << referencePath << " " << b.width << "x" << b.height << "\n";
        return kFailure;
    }
    const size_t pixels = size_t(a.width) * a.height;
    double sum = 0;
    int maxDiff = 0;
    size_t differing = 0;
    std::vector<png_byte> diff(diffPath.empty() ? 0 : pixels * 3);
    for (size_t p = 0; p < pixels; ++p) {
        bool differs = false;
        for (int c = 0; c < 3; ++c) {
            const int d = std::abs(int(a.bytes[p * 4 + c]) - int(b.bytes[p * 4 + c]));
            const double e = d / 255.0;
            sum += e * e;
            maxDiff = std::max(maxDiff, d);
            differs = differs || d != 0;
            if (!diff.empty()) diff[p * 3 + c] = png_byte(std::min(255, d * 8));
        }
        differing += differs;
    }
    const double mse = sum / double(pixels * 3);
    nlohmann::ordered_json result = {{"psnr_db", nullptr}, {"max_abs_diff", maxDiff}, {"differing_pixels", differing}};
    if (mse > 0) result["psnr_db"] = 10.0 * std::log10(1.0 / mse);
    if (!diff.empty()) {
        png_image out{};
        out.version = PNG_IMAGE_VERSION;
        out.width = png_uint_32(a.width);
        out.height = png_uint_32(a.height);
        out.format = PNG_FORMAT_RGB;
        if (!png_image_write_to_file(&out, diffPath.c_str(), 0, diff.data(), 0, nullptr)) {
            std::cerr << "whitted_kit: " << diffPath << ": " << out.message << "\n";
            return kFailure;
        }
    }
    std::cout << result.dump() << "\n";
    return 0;
}

// One record's numbers, or a null object (and a message) when it cannot be read.
nlohmann::ordered_json measures(const std::string& recordPath) {
    std::ifstream in(recordPath);
    if (!in) {
        std::cerr << "whitted_kit: " << recordPath << ": could not be opened\n";
        return nullptr;
    }
    try {
        const nlohmann::json record = nlohmann::json::parse(in);
        const auto& rays = record.at("rays");
        const auto& timings = record.at("timings_s");
        const double render = timings.at("render").get<double>();
        const double primaryShadow = rays.at("primary").get<double>() + rays.at("shadow").get<double>();
        nlohmann::ordered_json out = {
            {"trace", record.at("settings").value("trace", "")},
            {"load_s", timings.at("load")},
            {"bvh_build_s", timings.at("bvh_build")},
            {"acceleration_structure_build_s", timings.value("acceleration_structure_build", 0.0)},
            {"pipeline_s", timings.at("pipeline")},
            {"upload_s", timings.at("upload")},
            {"render_s", render},
            {"rays", {{"primary", rays.at("primary")}, {"shadow", rays.at("shadow")},
                      {"secondary", rays.at("secondary")}}},
            {"rays_per_s", rays.at("per_second")},
            {"mrays_per_s", rays.at("per_second").get<double>() / 1e6},
            {"primary_shadow_mrays_per_s", render > 0 ? primaryShadow / render / 1e6 : 0.0},
            {"camera_samples", record.at("sampling").value("camera_samples", 0)},
            {"device", record.at("device").at("name")},
            {"device_type", record.at("device").value("type", "")},
            {"driver", record.at("device").value("driver", "")},
            {"device_buffer_bytes", record.at("memory_bytes").at("device_buffers")},
            {"peak_rss_bytes", record.at("memory_bytes").at("peak_rss")},
            {"lost_samples", record.value("lost_samples", 0)}};
        return out;
    } catch (const nlohmann::json::exception& e) {
        std::cerr << "whitted_kit: " << recordPath << ": not a whitted render record (" << e.what() << ")\n";
        return nullptr;
    }
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

int measureCommand(const std::vector<std::string>& recordPaths) {
    nlohmann::ordered_json runs = nlohmann::ordered_json::array();
    for (const std::string& path : recordPaths) {
        runs.push_back(measures(path));
        if (runs.back().is_null()) return kFailure;
    }
    if (runs.size() == 1) {
        std::cout << runs[0].dump() << "\n";
        return 0;
    }
    nlohmann::ordered_json middle = nlohmann::ordered_json::object();
    for (const char* key : {"render_s", "mrays_per_s", "primary_shadow_mrays_per_s"}) {
        std::vector<double> values;
        for (const auto& run : runs) values.push_back(run.at(key).get<double>());
        middle[key] = median(values);
    }
    std::cout << nlohmann::ordered_json({{"runs", runs}, {"median", middle}}).dump() << "\n";
    return 0;
}

// tools/generate_scenes.py's displaced_sphere() and obj_text(), the same
// operations in the same order on doubles (this file is compiled without
// floating-point contraction), printed with the same formats ("%.7g" is
// Python's ":.7g").
double displacedRadius(double theta, double phi) {
    return 1.0 + 0.04 * std::sin(7 * theta) * std::cos(9 * phi) + 0.015 * std::sin(23 * theta + 17 * phi);
}

void spherePoint(double theta, double phi, double p[3]) {
    const double r = displacedRadius(theta, phi);
    p[0] = r * std::sin(theta) * std::cos(phi);
    p[1] = r * std::cos(theta);
    p[2] = -r * std::sin(theta) * std::sin(phi);
}

int meshObjCommand(long triangles, const std::string& outPath) {
    if (triangles < 8 || triangles > 20000000) {
        std::cerr << "whitted_kit: triangle count " << triangles << " is outside 8..20000000\n";
        return kBadInput;
    }
    long rings = std::max(2L, long(std::ceil(std::sqrt(double(triangles) / 4.0))));
    while (2 * rings * (2 * rings) - 2 * (2 * rings) < triangles) ++rings;
    const long segments = 2 * rings;
    std::vector<double> vertices, normals;
    const double h = 1e-4;
    for (long i = 0; i <= rings; ++i) {
        const double theta = M_PI * double(i) / double(rings);
        for (long j = 0; j < segments; ++j) {
            const double phi = 2 * M_PI * double(j) / double(segments);
            double v[3], n[3];
            spherePoint(theta, phi, v);
            vertices.insert(vertices.end(), v, v + 3);
            if (i == 0 || i == rings) {
                normals.insert(normals.end(), {0.0, i == 0 ? 1.0 : -1.0, 0.0});
                continue;
            }
            double a[3], b[3], c[3], d[3], dt[3], dp[3];
            spherePoint(theta + h, phi, a);
            spherePoint(theta - h, phi, b);
            spherePoint(theta, phi + h, c);
            spherePoint(theta, phi - h, d);
            for (int k = 0; k < 3; ++k) dt[k] = a[k] - b[k], dp[k] = c[k] - d[k];
            const double nx = dp[1] * dt[2] - dp[2] * dt[1], ny = dp[2] * dt[0] - dp[0] * dt[2],
                         nz = dp[0] * dt[1] - dp[1] * dt[0];
            const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
            n[0] = nx / length, n[1] = ny / length, n[2] = nz / length;
            if (n[0] * v[0] + n[1] * v[1] + n[2] * v[2] < 0) n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
            normals.insert(normals.end(), n, n + 3);
        }
    }
    std::vector<long> faces;
    for (long i = 0; i < rings; ++i)
        for (long j = 0; j < segments; ++j) {
            const long a = i * segments + j, b = i * segments + (j + 1) % segments;
            const long c = (i + 1) * segments + j, d = (i + 1) * segments + (j + 1) % segments;
            if (i != 0) faces.insert(faces.end(), {a, c, b});
            if (i != rings - 1) faces.insert(faces.end(), {b, c, d});
        }

    // Under a temporary name, renamed when complete (nothing half-written).
    const std::string partial = outPath + ".partial";
    std::unique_ptr<FILE, int (*)(FILE*)> out(std::fopen(partial.c_str(), "w"), std::fclose);
    if (!out) {
        std::cerr << "whitted_kit: " << partial << ": could not be created\n";
        return kFailure;
    }
    std::fprintf(out.get(), "# displaced sphere, %zu triangles, generated by tools/generate_scenes.py\n",
                 faces.size() / 3);
    for (size_t k = 0; k < vertices.size(); k += 3)
        std::fprintf(out.get(), "v %.7g %.7g %.7g\n", vertices[k], vertices[k + 1], vertices[k + 2]);
    for (size_t k = 0; k < normals.size(); k += 3)
        std::fprintf(out.get(), "vn %.6g %.6g %.6g\n", normals[k], normals[k + 1], normals[k + 2]);
    for (size_t k = 0; k < faces.size(); k += 3)
        std::fprintf(out.get(), "f %ld//%ld %ld//%ld %ld//%ld\n", faces[k] + 1, faces[k] + 1, faces[k + 1] + 1,
                     faces[k + 1] + 1, faces[k + 2] + 1, faces[k + 2] + 1);
    const bool written = std::fflush(out.get()) == 0 && !std::ferror(out.get());
    out.reset();
    if (!written || std::rename(partial.c_str(), outPath.c_str()) != 0) {
        std::remove(partial.c_str());
        std::cerr << "whitted_kit: " << outPath << ": could not be written\n";
        return kFailure;
    }
    return 0;
}

int usage() {
    std::cerr << "usage: whitted_kit psnr IMAGE.png REFERENCE.png [--diff DIFF.png]\n"
                 "       whitted_kit measure RECORD.json [RECORD.json...]\n"
                 "       whitted_kit mesh-obj TRIANGLES OUT.obj\n";
    return kBadInput;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 3 && args[0] == "psnr") return psnrCommand(args[1], args[2], "");
    if (args.size() == 5 && args[0] == "psnr" && args[3] == "--diff") return psnrCommand(args[1], args[2], args[4]);
    if (args.size() >= 2 && args[0] == "measure") return measureCommand({args.begin() + 1, args.end()});
    if (args.size() == 3 && args[0] == "mesh-obj") {
        char* end = nullptr;
        const long triangles = std::strtol(args[1].c_str(), &end, 10);
        if (args[1].empty() || *end != '\0') return usage();
        return meshObjCommand(triangles, args[2]);
    }
    return usage();
}

#include "output/aov_output.h"

#include "display_types.h"  // idColorRgb8
#include "io/image_io.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <future>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <unistd.h>
#include <stdexcept>
#include <thread>

namespace whitted {
namespace {

enum class AovKind { Color, Scalar, Depth, Normal, Samples, Id };

struct AovSpec {
    AovInfo info;
    AovKind kind;
    uint32_t layer;
    int channel;      // for Scalar and Id (0 object, 1 material)
    float pngScale;   // for Scalar: 8-bit value = value * pngScale
};

const std::vector<AovSpec>& aovSpecs() {
    using enum AovKind;
    static const std::vector<AovSpec> specs = {
        {{"ambient", "ambient colour component ka Cd A"}, Color, gpu::kAovAmbient, 0, 1},
        {{"diffuse", "diffuse colour component, all lights"}, Color, gpu::kAovDiffuse, 0, 1},
        {{"specular", "Phong specular colour component, all lights"}, Color, gpu::kAovSpecular, 0, 1},
        {{"reflection", "light arriving by the reflected ray, weighted"}, Color, gpu::kAovReflection, 0, 1},
        {{"transmission", "light arriving by the refracted ray, weighted"}, Color, gpu::kAovTransmission, 0, 1},
        {{"ambient_coef", "ka of the visible surface"}, Scalar, gpu::kAovCoefs0, 0, 1},
        {{"diffuse_coef", "kd of the visible surface"}, Scalar, gpu::kAovCoefs0, 1, 1},
        {{"specular_coef", "ks of the visible surface"}, Scalar, gpu::kAovCoefs0, 2, 1},
        {{"reflection_coef", "kr of the visible surface (black and white)"}, Scalar, gpu::kAovCoefs1, 0, 1},
        {{"transmission_coef", "kt of the visible surface (black and white)"}, Scalar, gpu::kAovCoefs1, 1, 1},
        {{"ior", "index of refraction of the visible surface (8-bit: ior / 3)"}, Scalar, gpu::kAovCoefs1, 2, 1.0f / 3.0f},
        {{"depth", "distance from the eye to the visible surface"}, Depth, gpu::kAovCoefs0, 3, 1},
        {{"normal", "shading normal of the visible surface (8-bit: n / 2 + 0.5)"}, Normal, gpu::kAovNormal, 0, 1},
        {{"samples", "camera samples the pixel took (8-bit: samples / maximum)"}, Samples, gpu::kAovColor, 0, 1},
        // The id layer's place depends on the render (ImageLayout::idLayer).
        {{"object_id", "index of the object the pixel-centre ray hits (8-bit: a colour per id)"}, Id, 0, 0, 1},
        {{"material_id", "index of the material the pixel-centre ray hits (8-bit: a colour per id)"}, Id, 0, 1, 1},
    };
    return specs;
}

// The split images (README "Auxiliary images"): "reflection.K" and
// "transmission.K", K = 1 .. bounces, in layers after gpu::kAovCount.
// Returns nothing for a name of another form.
std::optional<AovSpec> splitSpec(const std::string& name, uint32_t bounces) {
    for (uint32_t part = 0; part < 2; ++part) {
        std::string prefix = part == 0 ? "reflection." : "transmission.";
        if (name.rfind(prefix, 0) != 0) continue;
        std::string digits = name.substr(prefix.size());
        if (digits.empty() || digits.size() > 3 || digits.find_first_not_of("0123456789") != std::string::npos ||
            digits[0] == '0')
            return std::nullopt;
        uint32_t k = uint32_t(std::stoul(digits));
        if (k > bounces)
            throw std::invalid_argument("auxiliary image '" + name + "' needs --aov-bounces " + std::to_string(k) +
                                        " or more (got " + std::to_string(bounces) + ")");
        return AovSpec{{"split", "reflection or transmission at one ray depth"}, AovKind::Color,
                       gpu::kAovCount + part * bounces + k - 1, 0, 1};
    }
    return std::nullopt;
}

AovSpec findSpec(const std::string& name, uint32_t bounces) {
    for (const AovSpec& s : aovSpecs())
        if (name == s.info.name) return s;
    if (std::optional<AovSpec> split = splitSpec(name, bounces)) return *split;
    throw std::invalid_argument("unknown auxiliary image '" + name + "'");
}

// Channels of an image file: colours and normals 3; an id mask 3 in 8-bit
// files (its hash colour), 1 in float files (the id itself).
int channelCount(const AovSpec& spec, bool isFloat) {
    bool colour = spec.kind == AovKind::Color || spec.kind == AovKind::Normal;
    return colour || (spec.kind == AovKind::Id && !isFloat) ? 3 : 1;
}

// A file of floats written once and read back once: values an image needs
// whole before it can be encoded. Unlinked as soon as it is created, so it
// vanishes with the process whatever happens.
class Spool {
public:
    explicit Spool(const std::filesystem::path& folder) {
        std::filesystem::path path = folder / (".whitted-spool-" + std::to_string(::getpid()) + "-" +
                                               std::to_string(reinterpret_cast<uintptr_t>(this)));
        file_ = std::fopen(path.c_str(), "w+b");
        if (!file_) throw std::runtime_error(path.string() + ": cannot create a temporary file: " + std::strerror(errno));
        std::filesystem::remove(path);
    }
    ~Spool() { std::fclose(file_); }
    void write(std::span<const float> v) {
        if (std::fwrite(v.data(), sizeof(float), v.size(), file_) != v.size())
            throw std::runtime_error(std::string("cannot write a temporary file: ") + std::strerror(errno));
    }
    void rewind() { std::rewind(file_); }
    void read(std::span<float> v) {
        if (std::fread(v.data(), sizeof(float), v.size(), file_) != v.size())
            throw std::runtime_error("cannot read back a temporary file");
    }

private:
    std::FILE* file_;
};

}  // namespace

// One output file: how its pixels come from a band, and, for images that
// need the whole picture first, the spool and the statistics gathered.
struct ImageFileSink::File {
    AovSpec spec;
    std::unique_ptr<ImageStreamWriter> writer;
    int channels = 3;
    bool isFloat = false;
    bool seedTonemap = false;  // colour with --tonemap seed, 8-bit
    std::unique_ptr<Spool> spool;
    float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();  // seed: min, max
    std::vector<uint64_t> histogram;  // 8-bit depth: counts of the upper 16 bits of the distances
    uint64_t hits = 0;
    bool alpha = false;  // the main image with coverage as a fourth channel

    bool spooled() const { return spool != nullptr; }
};

ImageFileSink::ImageFileSink(const std::filesystem::path& mainImage, const std::vector<std::string>& aovs,
                             Tonemap tonemap, const ImageLayout& layout, int maxSamples, double exposure, bool alpha)
    : layout_(layout), maxSamples_(maxSamples), colourScale_(float(std::exp2(exposure))) {
    if (alpha && (tonemap == Tonemap::Seed || layout.layerCount <= gpu::kAovCoefs1))
        throw std::logic_error("an image with alpha needs the clamp tone mapping and the auxiliary layers");
    const PixelRegion& r = layout.region;
    ImageWindow window{layout.fullWidth, layout.fullHeight, r.x0, r.y0};
    std::filesystem::path folder = mainImage.parent_path().empty() ? "." : mainImage.parent_path();
    auto add = [&](const std::filesystem::path& path, const AovSpec& spec, bool withAlpha) {
        auto file = std::make_unique<File>();
        file->spec = spec;
        file->isFloat = isFloatFormat(path);
        file->alpha = withAlpha;
        file->channels = channelCount(spec, file->isFloat) + (withAlpha ? 1 : 0);
        PixelEncoding encoding = spec.kind == AovKind::Id && file->isFloat ? PixelEncoding::Uint32 : PixelEncoding::Linear8;
        if (spec.kind == AovKind::Color) {
            file->seedTonemap = !file->isFloat && tonemap == Tonemap::Seed;
            if (!file->seedTonemap) encoding = withAlpha ? PixelEncoding::Srgb8Alpha : PixelEncoding::Srgb8;
        }
        if (file->seedTonemap || (spec.kind == AovKind::Depth && !file->isFloat)) file->spool = std::make_unique<Spool>(folder);
        if (spec.kind == AovKind::Depth && !file->isFloat) file->histogram.assign(1u << 16, 0);
        file->writer = std::make_unique<ImageStreamWriter>(path, r.width(), r.height(), file->channels, encoding, window);
        files_.push_back(std::move(file));
    };
    add(mainImage, AovSpec{{"image", "the image"}, AovKind::Color, gpu::kAovColor, 0, 1}, alpha);
    uint32_t splitLayers = layout.layerCount - (layout.ids ? 1 : 0);
    uint32_t bounces = splitLayers > gpu::kAovCount ? (splitLayers - gpu::kAovCount) / 2 : 0;
    for (const std::string& name : aovs) {
        AovSpec spec = findSpec(name, bounces);
        if (spec.kind == AovKind::Id) {
            if (!layout.ids) throw std::logic_error("mask images requested from a render without the id layer");
            spec.layer = layout.idLayer();
        }
        if (spec.kind != AovKind::Samples && layout.layerCount <= spec.layer)
            throw std::logic_error("auxiliary images requested from a render without auxiliary layers");
        add(aovPath(mainImage, name), spec, false);
    }
}

ImageFileSink::~ImageFileSink() = default;  // unfinished writers remove their temporaries

namespace {

// A band's values of one image, as its file takes them: `isFloat` for a
// float file (EXR), else scaled for 8 bits; depth where nothing was hit is
// `noHit`; samples are divided by `maxSamples` in 8-bit files.
void bandValues(const AovSpec& spec, const BandView& band, int channels, bool isFloat, float noHit, int maxSamples,
                float colourScale, std::vector<float>& v) {
    size_t n = size_t(band.rows) * band.width;
    v.assign(n * channels, 0.0f);
    std::span<const float> layer = spec.kind == AovKind::Samples ? std::span<const float>() : band.layer(spec.layer);
    switch (spec.kind) {
        case AovKind::Color:
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < 3; ++c) v[i * 3 + c] = layer[i * 4 + c] * colourScale;
            break;
        case AovKind::Scalar:
            for (size_t i = 0; i < n; ++i) v[i] = layer[i * 4 + spec.channel] * (isFloat ? 1.0f : spec.pngScale);
            break;
        case AovKind::Depth: {
            // Mean distance over the samples that hit; noHit where nothing was.
            std::span<const float> hits = band.layer(gpu::kAovCoefs1);  // w: fraction of samples that hit
            for (size_t i = 0; i < n; ++i) {
                float h = hits[i * 4 + 3];
                v[i] = h > 0 ? layer[i * 4 + 3] / h : noHit;
            }
            break;
        }
        case AovKind::Normal:
            for (size_t i = 0; i < n; ++i) {
                float w = layer[i * 4 + 3];
                if (w <= 0) continue;
                for (int c = 0; c < 3; ++c) {
                    float x = layer[i * 4 + c] / w;
                    v[i * 3 + c] = isFloat ? x : x * 0.5f + 0.5f;
                }
            }
            break;
        case AovKind::Samples:
            for (size_t i = 0; i < n; ++i) v[i] = band.sampleCounts[i] / (isFloat ? 1.0f : float(maxSamples));
            break;
        case AovKind::Id:
            // Float files: the id's bits as they are (a UINT channel); 8-bit:
            // its hash colour, black for the background.
            for (size_t i = 0; i < n; ++i) {
                float bits = layer[i * 4 + spec.channel];
                if (isFloat) {
                    v[i] = bits;
                    continue;
                }
                uint32_t rgb = gpu::idColorRgb8(std::bit_cast<uint32_t>(bits));
                for (int c = 0; c < 3; ++c) v[i * 3 + c] = float((rgb >> (8 * c)) & 0xffu) / 255.0f;
            }
            break;
    }
}

}  // namespace

// The depth of a pixel that hit nothing in a float file: infinitely far where an environment is seen there,
// else 0, so that the files of scenes without an environment keep their values.
static float noHitDepth(bool environment) {
    return environment ? std::numeric_limits<float>::infinity() : 0.0f;
}

// The coverage is the share of each pixel's samples whose camera ray hit something (w of the coefficient
// layer kAovCoefs1). The colour of a transparent background is black, so v is premultiplied already.
void addCoverage(const BandView& band, bool premultiplied, std::vector<float>& v) {
    std::span<const float> hits = band.layer(gpu::kAovCoefs1);
    size_t n = v.size() / 3;
    std::vector<float> rgba(n * 4);
    for (size_t i = 0; i < n; ++i) {
        float a = std::clamp(hits[i * 4 + 3], 0.0f, 1.0f);
        float scale = premultiplied || a <= 0.0f ? 1.0f : 1.0f / a;
        for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = v[i * 3 + c] * scale;
        rgba[i * 4 + 3] = a;
    }
    v = std::move(rgba);
}

namespace {

// Calls work(i) for each i in [0, count) on up to one thread a core, this one
// included: each file is encoded on its own, and PNG's deflate is most of
// the time after a render (17 PNG files of 640x480: 0.35 s on one core).
// The first exception is rethrown once every thread has stopped.
template <class Work>
void forEachFileInParallel(size_t count, const Work& work) {
    std::atomic<size_t> next{0};
    auto run = [&] {
        for (size_t i; (i = next++) < count;) work(i);
    };
    size_t threads = std::min<size_t>(count, std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::future<void>> helpers;
    for (size_t t = 1; t < threads; ++t) helpers.push_back(std::async(std::launch::async, run));
    std::exception_ptr failure;
    try {
        run();
    } catch (...) {
        failure = std::current_exception();
        next = count;  // the helpers take no further file
    }
    for (auto& helper : helpers) {
        try {
            helper.get();
        } catch (...) {
            if (!failure) failure = std::current_exception();
        }
    }
    if (failure) std::rethrow_exception(failure);
}

}  // namespace

void ImageFileSink::writeBand(const BandView& band) {
    int row = band.y0 - layout_.region.y0;
    forEachFileInParallel(files_.size(), [&](size_t f) {
        File& file = *files_[f];
        std::vector<float> v;
        // Depth: -1 in the spool where nothing was hit, to tell it from a distance.
        float noHit = file.spooled() ? -1.0f : noHitDepth(layout_.environment);
        bandValues(file.spec, band, file.channels, file.isFloat, noHit, maxSamples_, colourScale_, v);
        if (file.alpha) addCoverage(band, file.isFloat, v);
        if (!file.histogram.empty())
            for (size_t i = 0; i < v.size(); ++i)
                if (band.layer(gpu::kAovCoefs1)[i * 4 + 3] > 0) {
                    ++file.histogram[std::bit_cast<uint32_t>(v[i]) >> 16];
                    ++file.hits;
                }
        if (file.seedTonemap)
            for (float x : v) file.lo = std::min(file.lo, x), file.hi = std::max(file.hi, x);
        if (file.spooled())
            file.spool->write(v);
        else
            file.writer->writeRows(row, band.rows, v);
    });
}

std::vector<std::filesystem::path> ImageFileSink::finish() {
    const PixelRegion& r = layout_.region;
    size_t rowValues = size_t(r.width());
    forEachFileInParallel(files_.size(), [&](size_t f) {
        File* file = files_[f].get();
        if (!file->spooled()) return;
        // The median distance, exactly: the upper 16 bits of the float
        // (distances are positive, so their bits sort like their values)
        // from the histogram gathered while streaming, then the lower 16
        // bits from a pass over the spool.
        float median = 0.0f;
        std::vector<float> v(rowValues * file->channels);
        if (!file->histogram.empty() && file->hits > 0) {
            uint64_t rank = file->hits / 2, below = 0;
            uint32_t upper = 0;
            while (below + file->histogram[upper] <= rank) below += file->histogram[upper++];
            std::vector<uint64_t> lower(1u << 16, 0);
            file->spool->rewind();
            for (int y = 0; y < r.height(); ++y) {
                file->spool->read(v);
                for (float d : v)
                    if (d >= 0 && std::bit_cast<uint32_t>(d) >> 16 == upper) ++lower[std::bit_cast<uint32_t>(d) & 0xffffu];
            }
            uint32_t bits = 0;
            while (below + lower[bits] <= rank) below += lower[bits++];
            median = std::bit_cast<float>(upper << 16 | bits);
        }
        // Second pass: encode and write row by row.
        file->spool->rewind();
        float range = file->hi - file->lo;
        for (int y = 0; y < r.height(); ++y) {
            file->spool->read(v);
            for (float& x : v) {
                if (file->seedTonemap)  // the seed's min-max normalisation, then a gamma of 0.667
                    x = range > 0 ? std::pow((x - file->lo) / range, 0.667f) : 0.0f;
                else  // 8-bit depth: m / (m + d), near is bright, 0 where nothing was hit
                    x = x >= 0 ? median / (median + x) : 0.0f;
            }
            file->writer->writeRows(y, 1, v);
        }
    });
    forEachFileInParallel(files_.size(), [&](size_t f) { files_[f]->writer->commit(); });
    std::vector<std::filesystem::path> written;
    for (auto& file : files_) written.push_back(file->writer->path());
    return written;
}

namespace {
}  // namespace

const std::vector<AovInfo>& allAovs() {
    static const std::vector<AovInfo> infos = [] {
        std::vector<AovInfo> v;
        for (const AovSpec& s : aovSpecs()) v.push_back(s.info);
        return v;
    }();
    return infos;
}

std::vector<std::string> parseAovList(const std::string& list, int bounces) {
    std::vector<std::string> names;
    if (list == "none" || list.empty()) return names;
    if (list == "all") {
        for (const AovInfo& a : allAovs()) {
            names.push_back(a.name);
            if (std::string(a.name) == "transmission")  // the split images follow the colour components
                for (const char* part : {"reflection.", "transmission."})
                    for (int k = 1; k <= bounces; ++k) names.push_back(part + std::to_string(k));
        }
        return names;
    }
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) {
        findSpec(item, uint32_t(bounces));  // throws for an unknown name
        if (std::find(names.begin(), names.end(), item) == names.end()) names.push_back(item);
    }
    return names;
}

bool hasIdAov(const std::vector<std::string>& aovs) {
    return std::find(aovs.begin(), aovs.end(), "object_id") != aovs.end() ||
           std::find(aovs.begin(), aovs.end(), "material_id") != aovs.end();
}

bool hasSplitAov(const std::vector<std::string>& aovs) {
    for (const std::string& name : aovs)
        if (name.rfind("reflection.", 0) == 0 || name.rfind("transmission.", 0) == 0) return true;
    return false;
}

std::filesystem::path aovPath(const std::filesystem::path& mainImage, const std::string& aov) {
    return mainImage.parent_path() / (mainImage.stem().string() + "." + aov + mainImage.extension().string());
}

std::vector<std::filesystem::path> writeRenderImages(const RenderResult& result, const std::filesystem::path& mainImage,
                                                     const std::vector<std::string>& aovs, Tonemap tonemap,
                                                     double exposure) {
    // The whole result as one band.
    ImageLayout layout = result.layout;
    if (layout.fullWidth == 0) layout = {result.width, result.height, {0, 0, result.width, result.height}, 1};
    layout.layerCount = 1;
    if (result.hasAuxiliary)  // the rendered layers: kAovCount, and the split ones if any
        while (layout.layerCount < result.layers.size() && !result.layers[layout.layerCount].empty())
            ++layout.layerCount;
    size_t pixels = size_t(result.width) * result.height;
    std::vector<float> layers(layout.layerCount * pixels * 4);
    for (uint32_t l = 0; l < layout.layerCount; ++l)
        std::copy(result.layers[l].begin(), result.layers[l].end(), layers.begin() + l * pixels * 4);
    std::vector<float> counts = result.sampleCounts;
    counts.resize(pixels, float(result.samplesPerPixel));
    ImageFileSink sink(mainImage, aovs, tonemap, layout, std::max(result.samplesPerPixel, 1), exposure);
    sink.writeBand({.y0 = layout.region.y0, .rows = result.height, .width = result.width, .layers = layers,
                    .sampleCounts = counts});
    return sink.finish();
}

}  // namespace whitted

namespace whitted {

std::vector<float> floatImageValues(const BandView& band, const std::string& name, int bounces, int maxSamples,
                                    int& channels, bool environment) {
    AovSpec spec = name == "image" ? AovSpec{{"image", "the image"}, AovKind::Color, gpu::kAovColor, 0, 1}
                                   : findSpec(name, uint32_t(bounces));
    // The id layer follows the split layers (ImageLayout::idLayer).
    if (spec.kind == AovKind::Id) spec.layer = gpu::kAovCount + 2 * uint32_t(bounces);
    channels = channelCount(spec, true);
    std::vector<float> v;
    bandValues(spec, band, channels, true, noHitDepth(environment), maxSamples, 1.0f, v);
    return v;
}

}  // namespace whitted

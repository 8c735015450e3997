// Turns a RenderResult into files: the main image and the auxiliary images
// (AOVs) beside it, tone-mapped for 8-bit formats, linear for EXR.
#pragma once

#include "render/band_sink.h"
#include "render/render_result.h"

#include <memory>

#include <filesystem>
#include <string>
#include <vector>

namespace whitted {

enum class Tonemap {
    Clamp,  // clamp to [0,1], then the sRGB curve for 8-bit files
    Seed,   // the seed's min-max normalisation followed by x^0.667
};

// One auxiliary image: its name on the command line and in file names.
struct AovInfo {
    const char* name;
    const char* description;
};

// Every auxiliary image, in the order `--aov all` writes them.
const std::vector<AovInfo>& allAovs();

// Parses "all", "none" or a comma-separated list of names; throws
// std::invalid_argument naming an unknown entry. With bounces B > 0, the
// split images reflection.1 .. reflection.B and transmission.1 ..
// transmission.B exist too ("all" includes them after "transmission"); a
// split name beyond B is refused.
std::vector<std::string> parseAovList(const std::string& list, int bounces = 0);

// Whether the list holds a mask (object_id, material_id): the render needs
// RenderSettings::ids.
bool hasIdAov(const std::vector<std::string>& aovs);

// Whether the list holds one of the split images (reflection.K, transmission.K).
bool hasSplitAov(const std::vector<std::string>& aovs);

// Path of auxiliary image `aov` for the main image `mainImage`:
// out/room.png -> out/room.diffuse.png
std::filesystem::path aovPath(const std::filesystem::path& mainImage, const std::string& aov);

// Streams a render's bands into the main image and the requested auxiliary
// images, each written under a temporary name: finish() completes and renames
// them all; destroyed unfinished (a failed render), it leaves nothing behind.
// 8-bit depth (scaled by the median distance) and --tonemap seed (min-max
// over the image) need the whole image first: their values are spooled to
// an unlinked temporary file and written by finish(), so host memory stays
// bounded by one band whatever the image size.
class ImageFileSink final : public BandSink {
public:
    // exposure (EV, --exposure): the colour images (the image, ambient ...
    // transmission and their split parts) are scaled by 2^exposure, in EXR
    // files as in 8-bit ones, so that the components still add up to the
    // image in every file; coefficients, ior, depth, normal and samples are not.
    // alpha (--background transparent): the main image gets a fourth channel, the coverage (the share of
    // its samples whose camera ray hit something: the layout's auxiliary layers must be there); EXR keeps
    // the colour premultiplied by it (associated alpha), 8-bit files divide it out (PNG's straight alpha).
    ImageFileSink(const std::filesystem::path& mainImage, const std::vector<std::string>& aovs, Tonemap tonemap,
                  const ImageLayout& layout, int maxSamples, double exposure = 0.0, bool alpha = false);
    ~ImageFileSink() override;
    void writeBand(const BandView& band) override;
    // Completes every file; returns the paths written, main image first.
    std::vector<std::filesystem::path> finish();

private:
    struct File;
    std::vector<std::unique_ptr<File>> files_;
    ImageLayout layout_;
    int maxSamples_;
    float colourScale_;  // 2^exposure
};

// The values the float (EXR) file of "image" or of auxiliary image `name`
// holds for `band`, row-major, `channels` (3 or 1) per pixel: what the
// Python module hands out as arrays (host/python/). environment: the
// scene has one (ImageLayout::environment: depth infinity where nothing was hit).
std::vector<float> floatImageValues(const BandView& band, const std::string& name, int bounces, int maxSamples,
                                    int& channels, bool environment = false);

// Colour values `v` (3 a pixel, as floatImageValues gives "image") with the band's coverage as a fourth
// channel, the alpha of --background transparent; premultiplied: the colour stays as it is (EXR's
// associated alpha), else it is divided by the alpha (PNG's straight alpha).
void addCoverage(const BandView& band, bool premultiplied, std::vector<float>& v);

// Writes the main image and the requested auxiliary images; returns the
// paths written, main image first.
std::vector<std::filesystem::path> writeRenderImages(const RenderResult& result, const std::filesystem::path& mainImage,
                                                     const std::vector<std::string>& aovs, Tonemap tonemap,
                                                     double exposure = 0.0);

}  // namespace whitted

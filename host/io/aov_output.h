// Turns a RenderResult into files: the main image and the auxiliary images
// (AOVs) beside it, tone-mapped for 8-bit formats, linear for EXR.
#pragma once

#include "render/renderer.h"

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
// std::invalid_argument naming an unknown entry.
std::vector<std::string> parseAovList(const std::string& list);

// Path of auxiliary image `aov` for the main image `mainImage`:
// out/room.png -> out/room.diffuse.png
std::filesystem::path aovPath(const std::filesystem::path& mainImage, const std::string& aov);

// Writes the main image and the requested auxiliary images; returns the
// paths written, main image first.
std::vector<std::filesystem::path> writeRenderImages(const RenderResult& result, const std::filesystem::path& mainImage,
                                                     const std::vector<std::string>& aovs, Tonemap tonemap);

}  // namespace whitted

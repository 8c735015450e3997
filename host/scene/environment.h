// The world around the scene (scenes/README.md "Environment"): what a ray that
// leaves the scene sees, at every depth, and the light it gives (sampled as
// distribution ray tracing samples area lights). One per scene, with no
// position: a constant colour, a vertical gradient or an equirectangular
// image, turned about the up axis (+y) and scaled by an intensity.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <memory>
#include <string>

namespace whitted {

struct TextureData;  // io/texture.h

struct Environment {
    enum class Kind { Color, Gradient, Image };
    Kind kind = Kind::Color;
    glm::dvec3 color{0, 0, 0};    // Color: the radiance in every direction
    glm::dvec3 zenith{0, 0, 0};   // Gradient: at +y, at the horizon and at -y; linear in y between
    glm::dvec3 horizon{0, 0, 0};
    glm::dvec3 ground{0, 0, 0};
    // Image: equirectangular, linear RGB (8- and 16-bit files sRGB-decoded);
    // the path as the scene file wrote it, and its texels.
    std::string imageWritten;
    std::shared_ptr<const TextureData> image;
    double rotationDegrees = 0.0;  // about +y, counter-clockwise seen from above
    double intensity = 1.0;        // multiplies every kind's radiance
    bool visible = true;           // false: camera rays see black (mirrors, glass and lighting still see it)
    int shadowSamples = 1;         // its light's shadow rays per camera sample; 0: it lights nothing
    int sourceLine = 0;
};

// The mapping of an image environment (scenes/README.md "Environment"): the
// direction d (world space, before the rotation is undone) that texel
// coordinates (u, t) look along, u across the image from its left edge, t
// down from its top row, both in [0, 1]: the image's centre (0.5, 0.5) looks
// along -z, u = 0.75 along +x, the top row along +y. rotationDegrees turns
// the whole image about +y.
glm::dvec3 environmentDirection(double u, double t, double rotationDegrees);
// Its inverse: the (u, t) a world direction looks up.
glm::dvec2 environmentUv(const glm::dvec3& direction, double rotationDegrees);
// The radiance the environment gives along a world direction (the image
// read with the nearest texel; the device filters bilinearly).
glm::dvec3 environmentRadiance(const Environment& environment, const glm::dvec3& direction);

// An image environment from a file (`whitted render --environment FILE`),
// everything else at its default; throws SceneError(FILE, 0, ...) for a
// file that cannot be read.
Environment environmentFromImageFile(const std::filesystem::path& path);

// The element as the scene writer writes it, each line indented by `indent`
// spaces; `imageText` is the image's path as the written file names it
// (XML-escaped).
std::string environmentXml(const Environment& environment, const std::string& imageText, int indent);

}  // namespace whitted

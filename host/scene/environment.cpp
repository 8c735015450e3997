#include "scene/environment.h"
#include "scene/environment_reader.h"

#include "io/texture.h"
#include "io/texture_file.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace whitted {

namespace {


// d turned by `degrees` about +y, counter-clockwise seen from above (+z towards +x).
glm::dvec3 turnedAboutUp(const glm::dvec3& d, double degrees) {
    double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
    return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}

std::string colourXml(const char* tag, const glm::dvec3& c) {
    return std::string("<") + tag + " r=\"" + xmlNumber(c.r) + "\" g=\"" + xmlNumber(c.g) + "\" b=\"" +
           xmlNumber(c.b) + "\"/>";
}

}  // namespace

glm::dvec3 environmentDirection(double u, double t, double rotationDegrees) {
    double theta = t * std::numbers::pi, phi = (u - 0.5) * 2.0 * std::numbers::pi;
    glm::dvec3 d{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
    return turnedAboutUp(d, rotationDegrees);
}

glm::dvec2 environmentUv(const glm::dvec3& direction, double rotationDegrees) {
    glm::dvec3 d = turnedAboutUp(glm::normalize(direction), -rotationDegrees);
    double u = 0.5 + std::atan2(d.x, -d.z) / (2.0 * std::numbers::pi);
    double t = std::acos(std::clamp(d.y, -1.0, 1.0)) / std::numbers::pi;
    return {u - std::floor(u), t};
}

glm::dvec3 environmentRadiance(const Environment& environment, const glm::dvec3& direction) {
    switch (environment.kind) {
        case Environment::Kind::Color: return environment.color * environment.intensity;
        case Environment::Kind::Gradient: {
            double y = glm::normalize(direction).y;
            glm::dvec3 c = y >= 0 ? glm::mix(environment.horizon, environment.zenith, y)
                                  : glm::mix(environment.horizon, environment.ground, -y);
            return c * environment.intensity;
        }
        case Environment::Kind::Image: break;
    }
    if (!environment.image || environment.image->levels.empty()) return glm::dvec3(0.0);
    const TextureLevel& level = environment.image->levels[0];
    glm::dvec2 uv = environmentUv(direction, environment.rotationDegrees);
    int x = std::clamp(int(uv.x * level.width), 0, level.width - 1);
    int y = std::clamp(int(uv.y * level.height), 0, level.height - 1);
    const uint16_t* texel = &level.rgba[(size_t(y) * level.width + x) * 4];
    glm::dvec3 c{glm::unpackHalf1x16(texel[0]), glm::unpackHalf1x16(texel[1]), glm::unpackHalf1x16(texel[2])};
    return c * environment.intensity;
}

// One of <color>, <gradient> (with <zenith>, <horizon>, <ground>) or
// <image>; <rotation> (degrees) and <intensity> [1]; <visible> [true];
// <shadow_samples> [1], 0 for an environment that lights nothing.
Environment readEnvironment(const xml::Diagnostics& diag, const xml::XMLElement* e,
                            const std::filesystem::path& folder) {
    using namespace xml;
    ElementReader r(diag, e,
                    {{"color"}, {"gradient"}, {"image"}, {"rotation"}, {"intensity"}, {"visible"}, {"shadow_samples"}});
    Environment env;
    env.sourceLine = e->GetLineNum();
    const XMLElement* color = r.optional("color");
    const XMLElement* gradient = r.optional("gradient");
    const XMLElement* image = r.optional("image");
    int kinds = (color ? 1 : 0) + (gradient ? 1 : 0) + (image ? 1 : 0);
    if (kinds == 0) diag.fail(e, "<environment> needs one of <color>, <gradient> or <image>");
    if (kinds > 1)
        diag.fail(laterOf(color ? color : gradient, image ? image : gradient),
                  "<environment> takes one of <color>, <gradient> or <image>, not two");
    if (color) {
        env.kind = Environment::Kind::Color;
        env.color = colour(diag, color, kNonNegative);
    } else if (gradient) {
        env.kind = Environment::Kind::Gradient;
        ElementReader g(diag, gradient, {{"zenith"}, {"horizon"}, {"ground"}});
        env.zenith = colour(diag, g.required("zenith"), kNonNegative);
        env.horizon = colour(diag, g.required("horizon"), kNonNegative);
        env.ground = colour(diag, g.required("ground"), kNonNegative);
    } else {
        env.kind = Environment::Kind::Image;
        env.imageWritten = valueText(diag, image);
        if (env.imageWritten.empty()) diag.fail(image, "<image> is empty; expected the path of an image file");
        std::filesystem::path path(env.imageWritten);
        if (path.is_relative()) path = folder / path;
        try {
            env.image = std::make_shared<const TextureData>(readTextureFile(path, TextureEncoding::Colour));
        } catch (const TextureFileError& error) {
            diag.fail(image, "environment image \"" + env.imageWritten + "\" " + error.what());
        }
    }
    if (const XMLElement* rotation = r.optional("rotation"))
        env.rotationDegrees = number(diag, rotation, Range{-360, 360, false, false});
    if (const XMLElement* intensity = r.optional("intensity")) env.intensity = number(diag, intensity, kNonNegative);
    if (const XMLElement* visible = r.optional("visible")) env.visible = boolean(diag, visible);
    if (const XMLElement* samples = r.optional("shadow_samples"))
        env.shadowSamples = integer(diag, samples, 0, kMaxShadowSamples);
    return env;
}

Environment environmentFromImageFile(const std::filesystem::path& path) {
    Environment env;
    env.kind = Environment::Kind::Image;
    env.imageWritten = std::filesystem::absolute(path).string();
    try {
        env.image = std::make_shared<const TextureData>(readTextureFile(path, TextureEncoding::Colour));
    } catch (const TextureFileError& error) {
        throw SceneError(path.string(), 0, std::string("environment image ") + error.what());
    }
    return env;
}

std::string environmentXml(const Environment& environment, const std::string& imageText, int indent) {
    std::string pad(size_t(indent), ' ');
    std::ostringstream x;
    x << pad << "<environment>\n";
    switch (environment.kind) {
        case Environment::Kind::Color: x << pad << "  " << colourXml("color", environment.color) << "\n"; break;
        case Environment::Kind::Gradient:
            x << pad << "  <gradient>\n";
            x << pad << "    " << colourXml("zenith", environment.zenith) << "\n";
            x << pad << "    " << colourXml("horizon", environment.horizon) << "\n";
            x << pad << "    " << colourXml("ground", environment.ground) << "\n";
            x << pad << "  </gradient>\n";
            break;
        case Environment::Kind::Image: x << pad << "  <image>" << imageText << "</image>\n"; break;
    }
    if (environment.rotationDegrees != 0)
        x << pad << "  <rotation>" << xmlNumber(environment.rotationDegrees) << "</rotation>\n";
    if (environment.intensity != 1)
        x << pad << "  <intensity>" << xmlNumber(environment.intensity) << "</intensity>\n";
    if (!environment.visible) x << pad << "  <visible>false</visible>\n";
    if (environment.shadowSamples != 1)
        x << pad << "  <shadow_samples>" << environment.shadowSamples << "</shadow_samples>\n";
    x << pad << "</environment>\n";
    return x.str();
}

}  // namespace whitted

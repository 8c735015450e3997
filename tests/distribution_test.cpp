// Distribution ray tracing (Cook, Porter and Carpenter 1984): depth of field
// through a thin lens and glossy reflection and refraction (scenes/README.md
// "Depth of field", "Shading model"). Each test knows its answer without a
// reference image: the thin lens's circle of confusion, a blur that grows
// with roughness, and light that a glossy lobe must neither lose nor gain.
#include "io/image_io.h"
#include "scene/scene_loader.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr double kFovDegrees = 40.0;

void writeColour(const RenderResult& r, const std::string& name) {
    std::vector<float> rgb(size_t(r.width) * r.height * 3);
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            for (int c = 0; c < 3; ++c) rgb[(size_t(y) * r.width + x) * 3 + c] = pixel(r, gpu::kAovColor, x, y)[c];
    fs::path dir = outputDir() / "distribution";
    fs::create_directories(dir);
    writeImage(dir / (name + ".png"), r.width, r.height, 3, rgb, PixelEncoding::Srgb8);
}

// ---- Defaults ------------------------------------------------------------------------------------------

// <aperture_radius>0</aperture_radius> and <roughness>0</roughness> written into every shipped scene render
// bit for bit as the scene without them: a pinhole and a mirror take no new draw.
TEST(DistributionDefaults, ZeroApertureAndRoughnessAreBitIdentical) {
    int scenes = 0;
    for (const auto& entry : fs::directory_iterator(sourceDir() / "scenes")) {
        if (entry.path().extension() != ".xml") continue;
        std::ifstream in(entry.path());
        std::stringstream text;
        text << in.rdbuf();
        std::string plain = text.str();
        // A scene that has a lens or gloss already (scenes/soft.xml) is not one without the new elements.
        if (plain.find("<aperture_radius>") != std::string::npos || plain.find("<roughness>") != std::string::npos)
            continue;
        ++scenes;
        std::string zero = std::regex_replace(plain, std::regex("</camera>"), "<aperture_radius>0</aperture_radius></camera>");
        // Every top-level object's material (a csg child given a material element would stop taking its csg
        // object's).
        auto count = [](const std::string& text, const std::string& what) {
            size_t n = 0;
            for (size_t i = text.find(what); i != std::string::npos; i = text.find(what, i + 1)) ++n;
            return n;
        };
        for (size_t at = zero.find("<properties>"); at != std::string::npos; at = zero.find("<properties>", at + 1)) {
            std::string before = zero.substr(0, at);
            if (count(before, "<objects>") - count(before, "</objects>") == 1)
                zero.insert(at + std::string("<properties>").size(), "<roughness>0</roughness>");
        }
        ASSERT_NE(zero.find("<roughness>"), std::string::npos) << entry.path();
        Scene a = loadSceneFromString(plain, entry.path());
        Scene b = loadSceneFromString(zero, entry.path());
        RenderSettings settings{.width = 80, .height = 60, .samplesPerPixel = 4, .maxDepth = 6, .auxiliary = false};
        RenderResult ra = renderScene(a, settings), rb = renderScene(b, settings);
        ASSERT_EQ(ra.layers[gpu::kAovColor].size(), rb.layers[gpu::kAovColor].size());
        EXPECT_EQ(ra.layers[gpu::kAovColor], rb.layers[gpu::kAovColor]) << entry.path().filename();
    }
    EXPECT_GE(scenes, 8);
}

// ---- Depth of field ------------------------------------------------------------------------------------

// A camera at the origin looking down -z, a small emissive sphere (radius 0.05 unless given) at depth `depth` on the
// view axis, nothing else: its light lands where the lens sends it.
Scene pointScene(double depth, double aperture, double focus, double radius = 0.05) {
    std::ostringstream xml;
    xml << R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/><fov>)" << kFovDegrees
        << "</fov><width>" << kWidth << "</width><height>" << kHeight << "</height>"
        << "<aperture_radius>" << aperture << "</aperture_radius><focus_distance>" << focus
        << "</focus_distance></camera><lights/><objects>"
        << R"(<object><position x="0" y="0" z=")" << -depth
        << R"("/><diffuse_color r="1" g="1" b="1"/><properties><type>sphere</type><radius>)" << radius << "</radius>"
        << R"(<diffuse_coef>0</diffuse_coef><emission r="100" g="100" b="100"/></properties></object>)"
        << "</objects></scene>";
    return loadSceneFromString(xml.str(), "point.xml");
}

// The light of a render: total, centroid and mean squared distance from it (pixel units, pixel centres at
// x + 0.5), and the share within 1.5 pixels of the brightest pixel's centre.
struct Spot {
    double total = 0, cx = 0, cy = 0, meanSquaredRadius = 0, nearBrightest = 0;
};

Spot measureSpot(const RenderResult& r) {
    Spot s;
    int bx = 0, by = 0;
    float brightest = -1;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            float v = pixel(r, gpu::kAovColor, x, y).g;
            s.total += v;
            s.cx += v * (x + 0.5);
            s.cy += v * (y + 0.5);
            if (v > brightest) brightest = v, bx = x, by = y;
        }
    s.cx /= s.total;
    s.cy /= s.total;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            float v = pixel(r, gpu::kAovColor, x, y).g;
            s.meanSquaredRadius += v * ((x + 0.5 - s.cx) * (x + 0.5 - s.cx) + (y + 0.5 - s.cy) * (y + 0.5 - s.cy));
            if (std::abs(x - bx) <= 1 && std::abs(y - by) <= 1) s.nearBrightest += v;
        }
    s.meanSquaredRadius /= s.total;
    s.nearBrightest /= s.total;
    return s;
}

constexpr RenderSettings kLensSettings{
    .width = kWidth, .height = kHeight, .samplesPerPixel = 256, .maxDepth = 0, .auxiliary = false};

// A point on the plane of focus stays a point: all its light within the 3x3 pixels about the brightest
// one, as through a pinhole, and none of it lost.
TEST(DepthOfField, PointAtFocusDistanceStaysWithinOnePixel) {
    RenderResult lens = renderScene(pointScene(5.0, 0.2, 5.0, 0.01), kLensSettings);  // a third of a pixel
    RenderResult pinhole = renderScene(pointScene(5.0, 0.0, 5.0, 0.01), kLensSettings);
    writeColour(lens, "point_in_focus");
    Spot a = measureSpot(lens), b = measureSpot(pinhole);
    EXPECT_GT(a.nearBrightest, 0.99);
    EXPECT_NEAR(a.total, b.total, 0.02 * b.total);
    EXPECT_NEAR(a.cx, b.cx, 0.1);
    EXPECT_NEAR(a.cy, b.cy, 0.1);
}

// A point off the plane of focus spreads into the thin lens's circle of confusion: a lens of radius R
// focused at D images a point at depth z as a disc of diameter 2 R |z - D| / z on the plane of focus, which
// is D * 2 tan(fov / 2) / height per pixel there. A uniform disc of radius rho has mean squared radius
// rho^2 / 2; the sphere's own image (a disc of its angular radius) adds its own rho^2 / 2.
TEST(DepthOfField, OutOfFocusPointSpreadsIntoTheCircleOfConfusion) {
    const double aperture = 0.2, focus = 5.0, pixelAtUnitDepth = 2.0 * std::tan(glm::radians(kFovDegrees) / 2) / kHeight;
    for (double depth : {2.5, 10.0}) {
        RenderResult r = renderScene(pointScene(depth, aperture, focus), kLensSettings);
        writeColour(r, "point_at_" + std::to_string(int(depth * 10)));
        Spot s = measureSpot(r);
        double expectedDiameter = 2.0 * aperture * std::abs(depth - focus) / depth / (focus * pixelAtUnitDepth);
        double sphereRadius = 0.05 / depth / pixelAtUnitDepth;
        double measuredDiameter = 2.0 * std::sqrt(2.0 * s.meanSquaredRadius - sphereRadius * sphereRadius);
        std::printf("[ lens     ] depth %.1f: circle of confusion %.2f px, thin lens %.2f px\n", depth,
                    measuredDiameter, expectedDiameter);
        EXPECT_NEAR(measuredDiameter, expectedDiameter, 1.0) << "depth " << depth;
        // Centred where the pinhole images the point (the view axis: the image centre).
        EXPECT_NEAR(s.cx, kWidth / 2.0, 0.25);
        EXPECT_NEAR(s.cy, kHeight / 2.0, 0.25);
    }
}

// An orthographic camera's lens (pbrt's OrthographicCamera): rays from the lens point through the pinhole
// ray's point on the plane of focus, so a point at depth z spreads into a disc 2 R |z - D| / D across, in
// window units (the window is window_height high over `height` pixels).
TEST(DepthOfField, OrthographicLensBlursByItsCircleOfConfusion) {
    const double aperture = 0.1, focus = 5.0, windowHeight = 2.0, depth = 2.5;
    std::ostringstream xml;
    xml << R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
        << "<projection>orthographic</projection><window_height>" << windowHeight << "</window_height><width>"
        << kWidth << "</width><height>" << kHeight << "</height><aperture_radius>" << aperture
        << "</aperture_radius><focus_distance>" << focus << "</focus_distance></camera><lights/><objects>"
        << R"(<object><position x="0" y="0" z=")" << -depth
        << R"("/><diffuse_color r="1" g="1" b="1"/><properties><type>sphere</type><radius>0.005</radius>)"
        << R"(<diffuse_coef>0</diffuse_coef><emission r="100" g="100" b="100"/></properties></object>)"
        << "</objects></scene>";
    RenderResult r = renderScene(loadSceneFromString(xml.str(), "ortho.xml"), kLensSettings);
    Spot s = measureSpot(r);
    double perPixel = windowHeight / kHeight;
    double expectedDiameter = 2.0 * aperture * std::abs(depth - focus) / focus / perPixel;
    double sphereRadius = 0.005 / perPixel;
    double measuredDiameter = 2.0 * std::sqrt(2.0 * s.meanSquaredRadius - sphereRadius * sphereRadius);
    std::printf("[ lens     ] orthographic: circle of confusion %.2f px, thin lens %.2f px\n", measuredDiameter,
                expectedDiameter);
    EXPECT_NEAR(measuredDiameter, expectedDiameter, 1.0);
}

// With a lens, the auxiliary layers (normal, depth, coefficients) come from each sample's pinhole ray: the
// same values, bit for bit, as the render without the lens.
TEST(DepthOfField, AuxiliaryLayersComeFromThePinholeRay) {
    Scene scene = loadScene(sourceDir() / "scenes" / "three_diffuse_spheres.xml");
    RenderSettings settings{.width = 64, .height = 48, .samplesPerPixel = 4, .maxDepth = 2, .auxiliary = true};
    RenderResult pinhole = renderScene(scene, settings);
    scene.camera.apertureRadius = 0.3;
    RenderResult lens = renderScene(scene, settings);
    for (uint32_t layer : {gpu::kAovNormal, gpu::kAovCoefs0, gpu::kAovCoefs1})
        EXPECT_EQ(lens.layers[layer], pinhole.layers[layer]) << "layer " << layer;
    EXPECT_NE(lens.layers[gpu::kAovColor], pinhole.layers[gpu::kAovColor]);  // the lens does blur the colour
}

// ---- Glossy reflection and refraction ------------------------------------------------------------------

// A mirror (the plane z = 0, kr 1) seen head-on from (0, 0, 5) reflects a thin emissive rod lying along x
// behind the camera (z = 8, radius 0.02): a horizontal line across the image centre. The mean squared
// distance of its light from its centre row, over the middle columns.
double reflectedLineSpread(double roughness, double* total) {
    std::ostringstream xml;
    xml << R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/><fov>)" << kFovDegrees
        << "</fov></camera><lights/><objects>"
        << R"(<object><position x="0" y="0" z="0"/><diffuse_color r="1" g="1" b="1"/><properties><type>plane</type>)"
        << R"(<normal x="0" y="0" z="1"/><diffuse_coef>0</diffuse_coef><reflection_coef>1</reflection_coef>)"
        << "<roughness>" << roughness << "</roughness></properties></object>"
        << R"(<object><position x="-50" y="0" z="8"/><diffuse_color r="1" g="1" b="1"/><properties>)"
        << R"(<type>cylinder</type><radius>0.02</radius><height>100</height><axis x="1" y="0" z="0"/>)"
        << R"(<diffuse_coef>0</diffuse_coef><emission r="10" g="10" b="10"/></properties></object>)"
        << "</objects></scene>";
    RenderSettings settings{.width = kWidth, .height = kHeight, .samplesPerPixel = 64, .maxDepth = 1,
                            .auxiliary = false};
    RenderResult r = renderScene(loadSceneFromString(xml.str(), "glossy_line.xml"), settings);
    writeColour(r, "glossy_line_" + std::to_string(int(roughness * 100)));
    std::vector<double> rows(r.height, 0.0);
    for (int y = 0; y < r.height; ++y)
        for (int x = kWidth / 2 - 20; x < kWidth / 2 + 20; ++x) rows[y] += pixel(r, gpu::kAovColor, x, y).g;
    double sum = 0, centre = 0, spread = 0;
    for (int y = 0; y < r.height; ++y) sum += rows[y], centre += rows[y] * (y + 0.5);
    centre /= sum;
    for (int y = 0; y < r.height; ++y) spread += rows[y] * (y + 0.5 - centre) * (y + 0.5 - centre);
    *total = sum;
    return spread / sum;
}

// The reflected line blurs more the rougher the mirror; the light it reflects stays the same (the lobe
// only moves it). For a Phong lobe of exponent e about the mirror direction, the reflected rays leave at
// small angles with a variance of about 1 / (e + 2) per axis; the rod, 8 away from the mirror and 13 from
// the eye, is seen blurred by 8/13 of that angle.
TEST(GlossyReflection, ReflectedLineBlursMoreWithRoughness) {
    const double pixelAngle = 2.0 * std::tan(glm::radians(kFovDegrees) / 2) / kHeight;
    double previous = -1, firstTotal = 0;
    for (double roughness : {0.0, 0.1, 0.2, 0.4}) {
        double total = 0;
        double spread = std::sqrt(reflectedLineSpread(roughness, &total));
        double e = glossyLobeExponent(roughness);
        double predicted = std::isinf(e) ? 0.0 : 8.0 / 13.0 / std::sqrt(e + 2.0) / pixelAngle;
        std::printf("[ glossy   ] roughness %.1f: line spread %.2f px (lobe alone %.2f px), light %.1f\n", roughness,
                    spread, predicted, total);
        EXPECT_GT(spread, previous) << "roughness " << roughness;
        previous = spread;
        if (roughness == 0.0) firstTotal = total;
        EXPECT_NEAR(total, firstTotal, 0.03 * firstTotal) << "roughness " << roughness;
        if (roughness >= 0.2) {
            EXPECT_NEAR(spread, predicted, 0.2 * predicted) << "roughness " << roughness;
        }
    }
}

// <roughness_texture> (glTF's metallicRoughnessTexture): the roughness where a ray hits is <roughness> times
// the texture's green channel. The mirror of ReflectedLineBlursMoreWithRoughness, with `mirror` as its extra
// material elements, a texture 64 texels wide (float EXR, its green channel green(u)) repeating every 10 world
// units from x = -5: the visible mirror, x in about [-2.4, 2.4], reads u in [0.26, 0.74].
RenderResult mirrorLine(const std::string& mirror, const std::function<float(int)>& green = {}) {
    std::string texture;
    if (green) {
        const int w = 64, h = 4;
        std::vector<float> texels;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) texels.insert(texels.end(), {1.0f, green(x), 1.0f});
        fs::path dir = outputDir() / "distribution";
        fs::create_directories(dir);
        fs::path file = dir / ("roughness_" + std::to_string(std::hash<std::string>{}(mirror)) + ".exr");
        writeImage(file, w, h, 3, texels, PixelEncoding::Float);
        texture = "<roughness_texture>" + fs::absolute(file).string() + "</roughness_texture>" +
                  "<texture_scale>10</texture_scale>";
    }
    std::ostringstream xml;
    xml << R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/><fov>)" << kFovDegrees
        << "</fov></camera><lights/><objects>"
        << R"(<object><position x="-5" y="0" z="0"/><diffuse_color r="1" g="1" b="1"/><properties><type>plane</type>)"
        << R"(<normal x="0" y="0" z="1"/><diffuse_coef>0</diffuse_coef><reflection_coef>1</reflection_coef>)"
        << mirror << texture << "</properties></object>"
        << R"(<object><position x="-50" y="0" z="8"/><diffuse_color r="1" g="1" b="1"/><properties>)"
        << R"(<type>cylinder</type><radius>0.02</radius><height>100</height><axis x="1" y="0" z="0"/>)"
        << R"(<diffuse_coef>0</diffuse_coef><emission r="10" g="10" b="10"/></properties></object>)"
        << "</objects></scene>";
    RenderSettings settings{.width = kWidth, .height = kHeight, .samplesPerPixel = 64, .maxDepth = 1,
                            .auxiliary = false};
    return renderScene(loadSceneFromString(xml.str(), "roughness_texture.xml"), settings);
}

float columnDifference(const RenderResult& a, const RenderResult& b, int x) {
    float worst = 0;
    for (int y = 0; y < a.height; ++y)
        worst = std::max(worst, glm::length(pixel(a, gpu::kAovColor, x, y) - pixel(b, gpu::kAovColor, x, y)));
    return worst;
}

// A texture whose green is 0.5 everywhere (red and blue 1, unread) on roughness 0.3 renders as roughness
// 0.15 without one: the same draws through the same lobe, its exponent computed in float on the device
// instead of double on the host.
TEST(GlossyReflection, RoughnessTextureScalesRoughnessByItsGreenChannel) {
    RenderResult textured = mirrorLine("<roughness>0.3</roughness>", [](int) { return 0.5f; });
    RenderResult plain = mirrorLine("<roughness>0.15</roughness>");
    RenderResult rougher = mirrorLine("<roughness>0.3</roughness>");
    writeColour(textured, "roughness_texture_uniform");
    float worst = 0, apart = 0;
    for (int x = 0; x < kWidth; ++x) {
        worst = std::max(worst, columnDifference(textured, plain, x));
        apart = std::max(apart, columnDifference(textured, rougher, x));
    }
    std::printf("[ glossy   ] green 0.5 x roughness 0.3 against roughness 0.15: worst pixel %.3g (against 0.3: %.3g)\n",
                worst, apart);
    EXPECT_LT(worst, 1e-3f);
    EXPECT_GT(apart, 0.1f);  // the texture does change the image
}

// A texture green 0 on its left half and 1 on its right (roughness 0.3): the mirror's left is a perfect
// mirror, its right roughness 0.3, each column equal to the untextured render of one or the other, but for
// the few the texture's filtering blends at the edge (x = 0, the image's centre).
TEST(GlossyReflection, RoughnessTextureVariesAcrossTheSurface) {
    RenderResult split = mirrorLine("<roughness>0.3</roughness>", [](int x) { return x < 32 ? 0.0f : 1.0f; });
    RenderResult mirror = mirrorLine("");
    RenderResult rough = mirrorLine("<roughness>0.3</roughness>");
    writeColour(split, "roughness_texture_split");
    int lastMirror = -1, firstRough = kWidth, mirrors = 0, roughs = 0;
    for (int x = 0; x < kWidth; ++x) {
        if (columnDifference(split, mirror, x) == 0.0f) {
            ++mirrors;
            lastMirror = x;
        } else if (columnDifference(split, rough, x) < 1e-3f) {
            ++roughs;
            firstRough = std::min(firstRough, x);
        }
    }
    std::printf("[ glossy   ] split texture: %d mirror columns up to %d, %d rough columns from %d\n", mirrors,
                lastMirror, roughs, firstRough);
    EXPECT_EQ(mirrors, lastMirror + 1);        // the mirror columns are the left ones
    EXPECT_EQ(roughs, kWidth - firstRough);    // the rough ones the right ones
    // A texel is 10/64 world units, about 5 columns of the mirror: bilinear filtering blends the two halves
    // over one texel, so about 5 columns are neither.
    EXPECT_LE(firstRough - lastMirror - 1, 8);
    EXPECT_NEAR(lastMirror + 1, kWidth / 2, 8);
}

// A white furnace: the camera inside a closed sphere whose inside is a perfect glossy reflector (kr 1,
// Cs white, nothing else) emitting 0.05. Every ray, of any depth, sees 0.05 and passes weight 1 on, so a
// pixel is 0.05 (D + 1) for max depth D, whatever the roughness: a lobe that dropped its draws below the
// surface would lose light, one that renormalised wrongly would gain it.
TEST(GlossyReflection, WhiteFurnaceConservesEnergy) {
    const int maxDepth = 10;
    for (double roughness : {0.3, 1.0}) {
        std::ostringstream xml;
        xml << R"(<scene><camera><position x="0.3" y="0.2" z="0.1"/><window_position x="0.3" y="0.1" z="-0.9"/>)"
            << R"(</camera><lights/><objects><object><position x="0" y="0" z="0"/><diffuse_color r="1" g="1" b="1"/>)"
            << R"(<properties><type>sphere</type><radius>1</radius><diffuse_coef>0</diffuse_coef>)"
            << R"(<reflection_coef>1</reflection_coef><emission r="0.05" g="0.05" b="0.05"/><roughness>)"
            << roughness << "</roughness></properties></object></objects></scene>";
        RenderSettings settings{.width = 40, .height = 30, .samplesPerPixel = 16, .maxDepth = maxDepth,
                                .auxiliary = false};
        RenderResult r = renderScene(loadSceneFromString(xml.str(), "furnace.xml"), settings);
        const double expected = 0.05 * (maxDepth + 1);
        double sum = 0, worst = 0;
        for (int y = 0; y < r.height; ++y)
            for (int x = 0; x < r.width; ++x) {
                double v = pixel(r, gpu::kAovColor, x, y).g;
                sum += v;
                worst = std::max(worst, std::abs(v - expected));
            }
        double mean = sum / (r.width * r.height);
        EXPECT_NEAR(mean, expected, 0.01 * expected) << "roughness " << roughness;
        EXPECT_LT(worst, 0.01 * expected) << "roughness " << roughness;
    }
}

// Glossy refraction: a glass slab of index 1 (kt 1, no reflection) with a rough surface in front of an
// emissive wall. Every refracted draw still crosses the slab (draws folded back through the surface) and
// reaches the wall, so every pixel is the wall's emission; a blurred checker behind it would be the look,
// the light stays.
TEST(GlossyRefraction, RoughSlabPassesAllLight) {
    std::ostringstream xml;
    xml << R"(<scene><camera><position x="0" y="0" z="3"/><window_position x="0" y="0" z="2"/></camera>)"
        << R"(<lights/><objects>)"
        << R"(<object><position x="-2000" y="-2000" z="-0.1"/><diffuse_color r="1" g="1" b="1"/><properties>)"
        << R"(<type>box</type><size x="4000" y="4000" z="0.2"/><diffuse_coef>0</diffuse_coef>)"
        << R"(<transmission_coef>1</transmission_coef><refraction_coef>1</refraction_coef>)"
        << R"(<roughness>0.8</roughness></properties></object>)"
        << R"(<object><position x="0" y="0" z="-2"/><diffuse_color r="1" g="1" b="1"/><properties><type>plane</type>)"
        << R"(<normal x="0" y="0" z="1"/><diffuse_coef>0</diffuse_coef><emission r="0.5" g="0.5" b="0.5"/>)"
        << R"(</properties></object></objects></scene>)";
    RenderSettings settings{.width = 40, .height = 30, .samplesPerPixel = 16, .maxDepth = 4, .auxiliary = false};
    RenderResult r = renderScene(loadSceneFromString(xml.str(), "slab.xml"), settings);
    double worst = 0;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) worst = std::max(worst, std::abs(double(pixel(r, gpu::kAovColor, x, y).g) - 0.5));
    EXPECT_LT(worst, 0.005);
}

}  // namespace
}  // namespace whitted::test

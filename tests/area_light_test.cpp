// Area lights (scenes/README.md "Area lights"; Cook, Porter and Carpenter
// 1984): a sphere light's penumbra against the closed-form visible fraction
// of its disc of directions behind a spherical occluder; small area lights
// against point lights; a rect light's faces; radius 0 changing no pixel of
// any shipped scene; the writer's round trip.
#include "render/ray_tree.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace whitted::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The solid angle where two spherical caps of angular radii a and b, their
// centres gamma apart, overlap (Tovchigrechko and Vakser 2001, "How common is
// the funnel-like energy landscape in protein-protein interactions?", eq. 2;
// also Mazonka 2012, "Solid angle of conical surfaces, polyhedral cones, and
// intersecting spherical caps").
double capOverlap(double a, double b, double gamma) {
    if (gamma >= a + b) return 0.0;
    if (gamma <= std::abs(a - b)) return 2.0 * kPi * (1.0 - std::cos(std::min(a, b)));
    double ca = std::cos(a), cb = std::cos(b), cg = std::cos(gamma);
    double sa = std::sin(a), sb = std::sin(b), sg = std::sin(gamma);
    return 2.0 * (kPi - std::acos((cg - ca * cb) / (sa * sb)) - std::acos((cb - cg * ca) / (sg * sa)) * ca -
                  std::acos((ca - cg * cb) / (sg * sb)) * cb);
}

// The fraction of a sphere light (centre c, radius r) that p sees past an
// opaque sphere (centre o, radius s): one minus the overlap of their caps
// over the light's cap.
double visibleFraction(const glm::dvec3& p, const glm::dvec3& c, double r, const glm::dvec3& o, double s) {
    glm::dvec3 toLight = c - p, toOccluder = o - p;
    double a = std::asin(r / glm::length(toLight)), b = std::asin(s / glm::length(toOccluder));
    double gamma = std::acos(std::clamp(glm::dot(glm::normalize(toLight), glm::normalize(toOccluder)), -1.0, 1.0));
    return 1.0 - capOverlap(a, b, gamma) / (2.0 * kPi * (1.0 - std::cos(a)));
}

TEST(AreaLight, CapOverlapAgreesWithCountedDirections) {
    // The formula against directions counted on a fine grid of the first cap.
    const double a = 0.05, b = 0.06;
    for (double gamma : {0.02, 0.05, 0.08, 0.105}) {
        const int n = 2000;
        long inside = 0, total = 0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                // Uniform in solid angle over cap a about +z: cos theta uniform.
                double cosTheta = 1.0 - (1.0 - std::cos(a)) * (i + 0.5) / n, phi = 2.0 * kPi * (j + 0.5) / n;
                double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
                glm::dvec3 d(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
                glm::dvec3 other(std::sin(gamma), 0.0, std::cos(gamma));
                inside += glm::dot(d, other) >= std::cos(b);
                ++total;
            }
        double counted = double(inside) / double(total) * 2.0 * kPi * (1.0 - std::cos(a));
        EXPECT_NEAR(capOverlap(a, b, gamma), counted, 1e-3 * 2.0 * kPi * (1.0 - std::cos(a))) << gamma;
    }
}

// The penumbra scene: a floor y = 0 (white, kd 1), a sphere light of radius
// 0.5 at height 10 above the origin, an opaque ball of radius 0.3 at height 5
// between them, seen from (0, 3, 6) with a 20 degree field of view, so that
// the centre row crosses the whole penumbra (|x| from about 0.1 to 1.1).
constexpr int kWidth = 64, kHeight = 48;
const glm::dvec3 kEye(0, 3, 6), kLight(0, 10, 0), kBall(0, 5, 0);
constexpr double kLightRadius = 0.5, kBallRadius = 0.3, kFovDegrees = 20.0;

std::string penumbraXml(bool ball, const std::string& lightExtra) {
    std::string xml = R"(<scene><camera><position x="0" y="3" z="6"/><window_position x="0" y="2.552786" z="5.105573"/>)"
                      R"(<fov>20</fov><width>64</width><height>48</height></camera><lights><light>)"
                      R"(<position x="0" y="10" z="0"/><color r="1" g="1" b="1"/>)" +
                      lightExtra +
                      R"(</light></lights><objects><object><position x="0" y="0" z="0"/><properties><type>plane</type>)"
                      R"(<normal x="0" y="1" z="0"/></properties></object>)";
    if (ball)
        xml += R"(<object><position x="0" y="5" z="0"/><properties><type>sphere</type><radius>0.3</radius>)"
               R"(</properties></object>)";
    return xml + "</objects></scene>";
}

// Where the ray through image point (x, y) (pixels, from the top left)
// meets the floor.
glm::dvec3 floorPoint(double x, double y) {
    glm::dvec3 forward = glm::normalize(-kEye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
    glm::dvec3 up = glm::cross(right, forward);
    double tanHalf = std::tan(glm::radians(kFovDegrees) / 2.0), aspect = double(kWidth) / kHeight;
    glm::dvec3 d = forward + (2.0 * x / kWidth - 1.0) * tanHalf * aspect * right + (1.0 - 2.0 * y / kHeight) * tanHalf * up;
    return kEye + d * (-kEye.y / d.y);
}

// The centre row, rendered with and without the ball: each pixel's ratio is
// the light's visible fraction weighted by N.L over its cap, against the
// closed-form fraction averaged over the pixel (the box filter of the
// samples). N.L changes by at most tan(6.3 deg) * 0.05 = 0.6% across the
// cap here (the light is never more than 6.3 degrees off the normal), the
// ratio removing its mean, so 0.01 holds what it leaves and the noise of
// 64 x 64 stratified shadow rays per pixel.
TEST(AreaLight, SphereLightPenumbraMatchesVisibleFraction) {
    RenderSettings s{.width = kWidth, .height = kHeight, .samplesPerPixel = 64, .maxDepth = 0, .auxiliary = false,
                     .antiAliasing = AntiAliasing::Uniform, .region = PixelRegion{0, kHeight / 2, kWidth, kHeight / 2 + 1}};
    const std::string light = "<radius>0.5</radius><shadow_samples>64</shadow_samples>";
    RenderResult shadowed = renderXml(penumbraXml(true, light), s);
    RenderResult open = renderXml(penumbraXml(false, light), s);
    ASSERT_EQ(shadowed.width, kWidth);
    int penumbra = 0, umbra = 0;
    double worst = 0.0;
    for (int x = 0; x < kWidth; ++x) {
        double expected = 0.0;
        const int sub = 8;
        for (int i = 0; i < sub; ++i)
            for (int j = 0; j < sub; ++j)
                expected += visibleFraction(floorPoint(x + (i + 0.5) / sub, kHeight / 2 + (j + 0.5) / sub), kLight,
                                            kLightRadius, kBall, kBallRadius);
        expected /= sub * sub;
        double lit = pixel(open, gpu::kAovColor, x, 0).g, got = pixel(shadowed, gpu::kAovColor, x, 0).g / lit;
        ASSERT_GT(lit, 0.9);
        EXPECT_NEAR(got, expected, 0.01) << "pixel " << x << ", floor point x " << floorPoint(x + 0.5, kHeight / 2 + 0.5).x;
        worst = std::max(worst, std::abs(got - expected));
        penumbra += expected > 0.05 && expected < 0.95;
        umbra += expected < 0.01;
    }
    EXPECT_GE(penumbra, 20) << "the row crosses the penumbra";
    EXPECT_GE(umbra, 2) << "and the umbra";
    std::cout << "[          ] penumbra pixels " << penumbra << ", worst |rendered - closed form| " << worst << "\n";
}

// The shadow samples follow the camera samples (sampleDimension), so
// adaptive anti-aliasing sees a noisy penumbra and refines it: with one
// shadow ray per camera sample, the centre row's penumbra pixels take more
// samples on average than its fully lit ones, which stop at the first pass.
TEST(AreaLight, AdaptiveRefinementRefinesThePenumbra) {
    RenderSettings s{.width = kWidth, .height = kHeight, .samplesPerPixel = 64, .maxDepth = 0, .auxiliary = false,
                     .antiAliasing = AntiAliasing::Adaptive};
    RenderResult r = renderXml(penumbraXml(true, "<radius>0.5</radius>"), s);
    ASSERT_EQ(r.sampleCounts.size(), size_t(kWidth * kHeight));
    double penumbraSum = 0.0, litSum = 0.0;
    int penumbra = 0, lit = 0;
    const int y = kHeight / 2;
    for (int x = 0; x < kWidth; ++x) {
        double f = visibleFraction(floorPoint(x + 0.5, y + 0.5), kLight, kLightRadius, kBall, kBallRadius);
        double count = r.sampleCounts[size_t(y) * kWidth + x];
        if (f > 0.2 && f < 0.8) penumbraSum += count, ++penumbra;
        if (f == 1.0) litSum += count, ++lit;
    }
    ASSERT_GT(penumbra, 5);
    ASSERT_GT(lit, 5);
    EXPECT_GT(penumbraSum / penumbra, 2.0 * litSum / lit)
        << "penumbra " << penumbraSum / penumbra << " samples a pixel, lit " << litSum / lit;
    std::cout << "[          ] samples a pixel: penumbra " << penumbraSum / penumbra << ", lit " << litSum / lit << "\n";
}

// The ray tree records each sampled shadow ray: at a penumbra pixel the
// camera ray has its light's 8 shadow rays, to different points, some
// blocked by the ball and some lit; their shares add up to the ray's diffuse
// term, and the tree's colour is the pixel of a one-sample render.
TEST(AreaLight, RayTreeRecordsEachShadowSample) {
    const std::string xml = penumbraXml(true, "<radius>0.5</radius><shadow_samples>8</shadow_samples>");
    RenderSettings s{.width = kWidth, .height = kHeight, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = false,
                     .antiAliasing = AntiAliasing::Uniform, .bandBytes = 0};
    const int x = 42, y = kHeight / 2;
    const double fraction = visibleFraction(floorPoint(x + 0.5, y + 0.5), kLight, kLightRadius, kBall, kBallRadius);
    ASSERT_GT(fraction, 0.2);
    ASSERT_LT(fraction, 0.8);
    Scene scene = loadSceneFromString(xml, "penumbra.xml");
    Renderer renderer(testContext(), scene, s);
    RayTree tree = RayTreeRecorder(testContext()).trace(renderer, x, y);
    ASSERT_EQ(tree.rays.size(), 1u);
    ASSERT_EQ(tree.rays[0].shadowRayCount, 8u);
    int blocked = 0, lit = 0;
    glm::vec3 diffuse(0.0f);
    for (uint32_t i = 0; i < 8; ++i) {
        const gpu::RayTreeShadowRay& r = tree.shadowRays[tree.rays[0].firstShadowRay + i];
        blocked += r.outcome == gpu::kShadowBlocked;
        lit += r.outcome == gpu::kShadowLit;
        diffuse += r.diffuse;
        if (i > 0) {
            EXPECT_NE(r.direction, tree.shadowRays[tree.rays[0].firstShadowRay].direction) << i;
        }
    }
    EXPECT_GT(blocked, 0);
    EXPECT_GT(lit, 0);
    EXPECT_LT(glm::length(diffuse - tree.rays[0].diffuse), 1e-5f);
    RenderSettings whole = s;
    whole.bandBytes = RenderSettings{}.bandBytes;
    RenderResult image = renderScene(scene, whole);
    EXPECT_LT(glm::length(tree.color() - glm::vec3(pixel(image, gpu::kAovColor, x, y))), 1e-5f);
}

// A white Lambert wall z = -5 lit from (0.6, -0.4, -3), seen from the origin.
std::string wallXml(const std::string& light) {
    return R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
           R"(<width>32</width><height>24</height></camera><lights>)" +
           light +
           R"(</lights><objects><object><position x="0" y="0" z="-5"/><properties><type>plane</type>)"
           R"(<normal x="0" y="0" z="1"/></properties></object></objects></scene>)";
}

double maxDifference(const RenderResult& a, const RenderResult& b) {
    double worst = 0.0;
    for (size_t i = 0; i < a.layers[gpu::kAovColor].size(); ++i)
        if (i % 4 != 3) worst = std::max(worst, double(std::abs(a.layers[gpu::kAovColor][i] - b.layers[gpu::kAovColor][i])));
    return worst;
}

// A small sphere or rect light gives what a point light at its centre does
// (the colour is the total), to within its size's effect on N.L and 1/d^2
// (here < 1e-3 of the light); the pixels are about 0.5 of full light.
TEST(AreaLight, SmallAreaLightsMatchAPointLight) {
    RenderSettings s{.width = 32, .height = 24, .samplesPerPixel = 4, .maxDepth = 0, .auxiliary = false};
    const std::string at = R"(<position x="0.6" y="-0.4" z="-3"/><color r="1" g="0.5" b="0.25"/>)"
                           R"(<falloff>inverse_square</falloff><intensity>4</intensity>)";
    RenderResult point = renderXml(wallXml("<light>" + at + "</light>"), s);
    RenderResult sphere =
        renderXml(wallXml("<light>" + at + "<radius>0.002</radius><shadow_samples>4</shadow_samples></light>"), s);
    RenderResult rect = renderXml(wallXml("<light><type>rect</type>" + at +
                                          R"(<u x="0.003" y="0" z="0"/><v x="0" y="-0.002" z="0"/></light>)"),
                                  s);
    EXPECT_GT(pixel(point, gpu::kAovColor, 16, 12).r, 0.4f);
    EXPECT_LT(maxDifference(point, sphere), 1e-3);
    EXPECT_LT(maxDifference(point, rect), 1e-3);
}

// A rect light shines from the face u x v only: facing the wall it gives
// each pixel (its centre: 1 sample) the mean of N.L over the rectangle
// (no falloff; computed here on a 64 x 64 grid), turned away (v reversed)
// nothing, and two-sided as much as facing it. 64 stratified shadow rays
// of a smooth integrand leave well under 0.2% of full light.
TEST(AreaLight, RectLightShinesFromItsFrontFace) {
    RenderSettings s{.width = 32, .height = 24, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = false};
    const glm::dvec3 centre(0, 0, -3), u(1, 0, 0);
    auto rect = [&](const std::string& v, bool twoSided) {
        return renderXml(wallXml(R"(<light><type>rect</type><position x="0" y="0" z="-3"/><color r="1" g="1" b="1"/>)"
                                 R"(<u x="1" y="0" z="0"/>)" +
                                 v + (twoSided ? "<two_sided>true</two_sided>" : "") +
                                 "<shadow_samples>64</shadow_samples></light>"),
                         s);
    };
    RenderResult facing = rect(R"(<v x="0" y="-1" z="0"/>)", false);  // u x v = -z: towards the wall
    RenderResult away = rect(R"(<v x="0" y="1" z="0"/>)", false);
    RenderResult both = rect(R"(<v x="0" y="1" z="0"/>)", true);
    const glm::dvec3 v(0, 1, 0);
    double worst = 0.0, brightest = 0.0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            const double tanHalf = std::tan(glm::radians(30.0)), aspect = 32.0 / 24.0;
            glm::dvec3 d((2.0 * (x + 0.5) / 32 - 1.0) * tanHalf * aspect, (1.0 - 2.0 * (y + 0.5) / 24) * tanHalf, -1.0);
            glm::dvec3 p = d * (-5.0 / d.z);
            double expected = 0.0;
            for (int i = 0; i < 64; ++i)
                for (int j = 0; j < 64; ++j) {
                    glm::dvec3 point = centre + ((i + 0.5) / 64 - 0.5) * u + ((j + 0.5) / 64 - 0.5) * v;
                    expected += std::max(0.0, glm::normalize(point - p).z) / (64.0 * 64.0);
                }
            worst = std::max({worst, std::abs(pixel(facing, gpu::kAovColor, x, y).g - expected),
                              std::abs(pixel(both, gpu::kAovColor, x, y).g - expected)});
            brightest = std::max(brightest, double(glm::length(glm::vec3(pixel(away, gpu::kAovColor, x, y)))));
        }
    EXPECT_LT(worst, 2e-3);
    EXPECT_EQ(brightest, 0.0) << "a rect light gives nothing behind its face";
}

// <radius>0</radius> written into every light of every shipped scene changes
// no bit of its image (the point-light branch draws no sample).
TEST(AreaLight, RadiusZeroChangesNoPixelOfAnyScene) {
    RenderSettings s{.width = 80, .height = 60, .samplesPerPixel = 2, .maxDepth = 6, .auxiliary = false};
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(sourceDir() / "scenes")) {
        if (entry.path().extension() != ".xml") continue;
        std::ifstream in(entry.path());
        std::stringstream text;
        text << in.rdbuf();
        std::string xml = text.str(), withRadius;
        size_t from = 0, at;
        int lights = 0;
        while ((at = xml.find("</light>", from)) != std::string::npos) {
            size_t open = xml.rfind("<light>", at);
            // Directional lights take no radius; an area light (scenes/soft.xml) has its own already.
            std::string light = xml.substr(open, at - open);
            bool point = light.find("directional") == std::string::npos && light.find("<radius>") == std::string::npos &&
                         light.find("rect") == std::string::npos;
            withRadius += xml.substr(from, at - from) + (point ? "<radius>0</radius>" : "");
            lights += point;
            from = at;
            withRadius += "</light>";
            from += std::strlen("</light>");
        }
        withRadius += xml.substr(from);
        if (lights == 0) continue;  // only area lights
        Scene plain = loadSceneFromString(xml, entry.path());
        Scene explicitZero = loadSceneFromString(withRadius, entry.path());
        RenderResult a = renderScene(plain, s), b = renderScene(explicitZero, s);
        ASSERT_EQ(a.layers[gpu::kAovColor].size(), b.layers[gpu::kAovColor].size());
        EXPECT_EQ(std::memcmp(a.layers[gpu::kAovColor].data(), b.layers[gpu::kAovColor].data(),
                              a.layers[gpu::kAovColor].size() * sizeof(float)),
                  0)
            << entry.path();
        ++scenes;
    }
    EXPECT_GE(scenes, 8);
}

TEST(AreaLight, WriterRoundTrip) {
    const std::string xml = R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
      </camera><lights>
      <light><type>spot</type><position x="1" y="2" z="3"/><color r="1" g="1" b="1"/>
        <direction x="0" y="-1" z="0"/><radius>0.25</radius><shadow_samples>9</shadow_samples></light>
      <light><type>rect</type><position x="0" y="4" z="0"/><color r="1" g="0.5" b="1"/>
        <u x="2" y="0" z="0"/><v x="0" y="0" z="-1.5"/><two_sided>true</two_sided>
        <shadow_samples>16</shadow_samples></light>
      <light><type>rect</type><position x="0" y="4" z="0"/><color r="1" g="1" b="1"/>
        <u x="1" y="0" z="0"/><v x="0" y="1" z="1"/></light>
      <light><position x="0" y="1" z="0"/><color r="1" g="1" b="1"/></light>
    </lights><objects><object><position x="0" y="0" z="0"/><properties><type>sphere</type>
      <radius>1</radius></properties></object></objects></scene>)";
    Scene scene = loadSceneFromString(xml, "t.xml");
    ASSERT_EQ(scene.lights.size(), 4u);
    EXPECT_EQ(scene.lights[0].radius, 0.25);
    EXPECT_EQ(scene.lights[0].shadowSamples, 9);
    EXPECT_EQ(scene.lights[1].type, Light::Type::Rect);
    EXPECT_EQ(scene.lights[1].u, glm::dvec3(2, 0, 0));
    EXPECT_EQ(scene.lights[1].v, glm::dvec3(0, 0, -1.5));
    EXPECT_TRUE(scene.lights[1].twoSided);
    EXPECT_FALSE(scene.lights[2].twoSided);
    EXPECT_EQ(scene.lights[2].shadowSamples, 1);
    EXPECT_FALSE(scene.lights[3].area());
    std::string written = sceneXml(scene);
    Scene again = loadSceneFromString(written, "again.xml");
    ASSERT_EQ(again.lights.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        const Light &l = scene.lights[i], &m = again.lights[i];
        EXPECT_EQ(l.type, m.type) << i;
        EXPECT_EQ(l.position, m.position) << i;
        EXPECT_EQ(l.radius, m.radius) << i;
        EXPECT_EQ(l.shadowSamples, m.shadowSamples) << i;
        EXPECT_EQ(l.u, m.u) << i;
        EXPECT_EQ(l.v, m.v) << i;
        EXPECT_EQ(l.twoSided, m.twoSided) << i;
    }
    // A point light is written without any area element.
    EXPECT_EQ(written.find("<radius>0</radius>"), std::string::npos);
}

}  // namespace
}  // namespace whitted::test

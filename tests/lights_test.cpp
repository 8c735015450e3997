// Light types and the material additions (scenes/README.md "Lights",
// "Materials"), against formulas computed here in double precision from the
// same camera model: inverse-square falloff, the spot's cone, a directional
// light's shadow outline, shadows through tinted glass, Fresnel (Schlick)
// weights. Every render test runs on both trace paths (our BVH and, where
// the device has them, ray queries). Also: the loader and the writer of the
// new elements, and that their defaults change no pixel.
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace whitted::test {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;
constexpr double kTolerance = 2e-4;

// A camera at the origin looking down -z, 60 degrees vertical field of view.
std::string sceneXml(const std::string& lights, const std::string& objects, const std::string& extra = "") {
    return R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
           R"(<width>64</width><height>48</height></camera>)" +
           extra + "<lights>" + lights + "</lights><objects>" + objects + "</objects></scene>";
}

// The ray through pixel (x, y)'s centre (the first sample of a pixel).
glm::dvec3 pixelRay(int x, int y) {
    const double tanHalf = std::tan(glm::radians(60.0) / 2.0), aspect = double(kWidth) / kHeight;
    return glm::normalize(glm::dvec3((2.0 * (x + 0.5) / kWidth - 1.0) * tanHalf * aspect,
                                     (1.0 - 2.0 * (y + 0.5) / kHeight) * tanHalf, -1.0));
}

// A white Lambert wall z = -5 facing the camera, kd 1, no ambient term.
const std::string kWall = R"(<object><position x="0" y="0" z="-5"/><properties><type>plane</type>)"
                          R"(<normal x="0" y="0" z="1"/></properties></object>)";
constexpr double kWallZ = -5.0;

glm::dvec3 wallPoint(int x, int y) {
    glm::dvec3 d = pixelRay(x, y);
    return d * (kWallZ / d.z);
}

class LightsTest : public ::testing::TestWithParam<TracePath> {
protected:
    RenderResult render(const std::string& xml, int maxDepth = 6) {
        if (GetParam() == TracePath::RayQuery && !testContext().deviceInfo().rayQuery) return {};
        RenderSettings s{.width = kWidth, .height = kHeight, .samplesPerPixel = 1, .maxDepth = maxDepth,
                         .auxiliary = true, .trace = GetParam(), .antiAliasing = AntiAliasing::Uniform};
        RenderResult r = renderXml(xml, s);
        EXPECT_EQ(r.trace, GetParam());
        return r;
    }
    void SetUp() override {
        if (GetParam() == TracePath::RayQuery && !testContext().deviceInfo().rayQuery)
            GTEST_SKIP() << "device '" << testContext().deviceInfo().name << "' lacks VK_KHR_ray_query";
    }
};

// Inverse-square falloff: a point light of colour c and intensity I at
// distance d from a Lambert wall gives c I cos(theta) / d^2; without
// falloff, c I cos(theta).
TEST_P(LightsTest, InverseSquareFalloffOnAWall) {
    const glm::dvec3 light(0.6, -0.4, -3.0);
    const glm::dvec3 colour(1.0, 0.5, 0.25);
    const double intensity = 2.5;
    for (bool inverseSquare : {true, false}) {
        std::string xml = sceneXml(R"(<light><position x="0.6" y="-0.4" z="-3"/><color r="1" g="0.5" b="0.25"/>)"
                                   R"(<intensity>2.5</intensity>)" +
                                       std::string(inverseSquare ? "<falloff>inverse_square</falloff>" : "") +
                                       "</light>",
                                   kWall);
        RenderResult r = render(xml);
        double lo = 1e9, hi = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                glm::dvec3 toLight = light - wallPoint(x, y);
                double d = glm::length(toLight);
                double e = intensity * (toLight.z / d) / (inverseSquare ? d * d : 1.0);
                glm::vec4 got = pixel(r, gpu::kAovColor, x, y);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(got[c], colour[c] * e, kTolerance * std::max(1.0, e)) << x << "," << y;
                lo = std::min(lo, e), hi = std::max(hi, e);
            }
        if (inverseSquare) {
            EXPECT_GT(hi / lo, 3.0) << "the falloff shows across the wall";
        }
    }
}

// The spot's cone across the wall: saturate((cos theta - cos outer) /
// (cos inner - cos outer))^2 (KHR_lights_punctual), theta from the spot's
// direction; full inside the inner cone, zero outside the outer one.
TEST_P(LightsTest, SpotConeProfileAcrossAWall) {
    const glm::dvec3 light(0.3, 0.2, -1.0);
    const glm::dvec3 direction = glm::normalize(glm::dvec3(-0.1, -0.05, -1.0));
    const double cosInner = std::cos(glm::radians(15.0)), cosOuter = std::cos(glm::radians(35.0));
    std::string xml = sceneXml(R"(<light><type>spot</type><position x="0.3" y="0.2" z="-1"/>)"
                               R"(<color r="1" g="1" b="1"/><direction x="-0.1" y="-0.05" z="-1"/>)"
                               R"(<inner_angle>15</inner_angle><outer_angle>35</outer_angle></light>)",
                               kWall);
    RenderResult r = render(xml);
    int inside = 0, ramp = 0, outside = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            glm::dvec3 toLight = light - wallPoint(x, y);
            double d = glm::length(toLight);
            double cosTheta = glm::dot(-toLight / d, direction);
            double s = std::clamp((cosTheta - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
            double expected = s * s * (toLight.z / d);
            EXPECT_NEAR(pixel(r, gpu::kAovColor, x, y).g, expected, kTolerance) << x << "," << y;
            (s >= 1.0 ? inside : s <= 0.0 ? outside : ramp) += 1;
        }
    EXPECT_GT(inside, 50);
    EXPECT_GT(ramp, 200);
    EXPECT_GT(outside, 200);
}

// Whether the ray p + t dir, t > 0, meets the sphere (centre, radius), and
// how far from its outline: the ray's distance from the centre minus the
// radius (negative: through the sphere).
double sphereMargin(const glm::dvec3& p, const glm::dvec3& dir, const glm::dvec3& centre, double radius) {
    glm::dvec3 v = centre - p;
    double along = glm::dot(v, dir);
    if (along <= 0) return glm::length(v) - radius;
    return glm::length(v - along * dir) - radius;
}

// A directional light's shadow is the occluder's parallel projection: on
// the wall, exactly the points whose ray towards the light meets the
// sphere are dark. Pixels whose ray passes within 1e-3 of the outline are
// too close to call; pixels that see the sphere itself are left out.
TEST_P(LightsTest, DirectionalShadowHasTheProjectedOutline) {
    const glm::dvec3 travel = glm::normalize(glm::dvec3(0.5, -0.3, -1.0));
    const glm::dvec3 centre(-0.6, 0.4, -3.0);
    const double radius = 0.6;
    std::string sphere = R"(<object><position x="-0.6" y="0.4" z="-3"/><properties><type>sphere</type>)"
                         R"(<radius>0.6</radius></properties></object>)";
    std::string xml = sceneXml(R"(<light><type>directional</type><color r="1" g="1" b="1"/>)"
                               R"(<direction x="0.5" y="-0.3" z="-1"/></light>)",
                               kWall + sphere);
    RenderResult r = render(xml);
    int shadowed = 0, lit = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            if (sphereMargin(glm::dvec3(0), pixelRay(x, y), centre, radius) < 1e-3) continue;  // sees the sphere
            glm::dvec3 p = wallPoint(x, y);
            double margin = sphereMargin(p, -travel, centre, radius);
            if (std::abs(margin) < 1e-3) continue;
            double expected = margin < 0 ? 0.0 : -travel.z;  // cos theta on the wall, normal +z
            EXPECT_NEAR(pixel(r, gpu::kAovColor, x, y).r, expected, kTolerance) << x << "," << y;
            (margin < 0 ? shadowed : lit) += 1;
        }
    EXPECT_GT(shadowed, 50);
    EXPECT_GT(lit, 1000);
}

// Whether the ray p + t dir, t > 0, meets the box [lo, hi] (slab test).
bool meetsBox(const glm::dvec3& p, const glm::dvec3& dir, const glm::dvec3& lo, const glm::dvec3& hi) {
    double tIn = 0, tOut = 1e30;
    for (int a = 0; a < 3; ++a) {
        double t0 = (lo[a] - p[a]) / dir[a], t1 = (hi[a] - p[a]) / dir[a];
        tIn = std::max(tIn, std::min(t0, t1));
        tOut = std::min(tOut, std::max(t0, t1));
    }
    return tOut > tIn;
}

// Shadows through glass are filtered: a clear box (kt 0.8, kd 0) tinted
// by a transmission colour, out of view, between the wall and a spot or a
// directional light. Each of the two crossings filters by kt Ct, so the
// shadow is the lit value times (0.8 Ct)^2 per channel.
TEST_P(LightsTest, SpotAndDirectionalShadowsThroughGlassAreFiltered) {
    const glm::dvec3 tint(1.0, 0.5, 0.25);
    const glm::dvec3 lo(-4.0, -1.0, -3.0), hi(-3.0, 1.0, -2.0);
    std::string glass = R"(<object><position x="-4" y="-1" z="-3"/><properties><type>box</type>)"
                        R"(<size x="1" y="2" z="1"/><diffuse_coef>0</diffuse_coef>)"
                        R"(<transmission_coef>0.8</transmission_coef><refraction_coef>1.5</refraction_coef>)"
                        R"(<transmission_color r="1" g="0.5" b="0.25"/></properties></object>)";
    const glm::dvec3 travel = glm::normalize(glm::dvec3(1.0, 0.0, -1.0));
    const glm::dvec3 spot(-6.0, 0.0, 1.0);
    const glm::dvec3 spotDirection = glm::normalize(glm::dvec3(1.0, 0.0, -1.0));
    const double cosInner = std::cos(glm::radians(40.0)), cosOuter = std::cos(glm::radians(70.0));
    for (bool directional : {true, false}) {
        std::string light = directional ? R"(<light><type>directional</type><color r="1" g="1" b="1"/>)"
                                          R"(<direction x="1" y="0" z="-1"/></light>)"
                                        : R"(<light><type>spot</type><position x="-6" y="0" z="1"/>)"
                                          R"(<color r="1" g="1" b="1"/><direction x="1" y="0" z="-1"/>)"
                                          R"(<inner_angle>40</inner_angle><outer_angle>70</outer_angle></light>)";
        RenderResult r = render(sceneXml(light, kWall + glass));
        int filtered = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                glm::dvec3 p = wallPoint(x, y);
                glm::dvec3 toLight = directional ? -travel : glm::normalize(spot - p);
                double e = toLight.z;
                if (!directional) {
                    double cosTheta = glm::dot(-toLight, spotDirection);
                    double s = std::clamp((cosTheta - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
                    e *= s * s;
                }
                // Too close to the box's outline to call: it would differ
                // for a box 1e-3 larger or smaller.
                const glm::dvec3 margin(1e-3);
                bool crosses = meetsBox(p, toLight, lo, hi);
                if (crosses != meetsBox(p, toLight, lo - margin, hi + margin) ||
                    crosses != meetsBox(p, toLight, lo + margin, hi - margin))
                    continue;
                glm::vec4 got = pixel(r, gpu::kAovColor, x, y);
                for (int c = 0; c < 3; ++c) {
                    double filter = crosses ? (0.8 * tint[c]) * (0.8 * tint[c]) : 1.0;
                    EXPECT_NEAR(got[c], e * filter, kTolerance)
                        << (directional ? "directional" : "spot") << " " << x << "," << y << " channel " << c;
                }
                if (crosses && e > 0.1) ++filtered;
            }
        EXPECT_GT(filtered, 100) << (directional ? "directional" : "spot");
    }
}

// Fresnel on a glass sphere (ior 1.5, kr = F0 = 0.04, kt 1) inside an
// emissive shell of radiance 1 that lights nothing: the reflection image is
// Cs F with F = F0 + (1 - F0)(1 - cos theta)^5 (Schlick), F0 at normal
// incidence and more towards the rim. At depth 2 the light through the
// sphere is kt (1 - F) in and kt (1 - F) out (a sphere's exit angle equals
// its entry angle): the transmission image is (1 - F)^2.
TEST_P(LightsTest, FresnelGlassSphereReflectsSchlicksWeight) {
    const glm::dvec3 centre(0.2, -0.1, -4.0);
    const double radius = 1.6, f0 = 0.04;
    std::string shell = R"(<object><position x="0" y="0" z="0"/><properties><type>sphere</type>)"
                        R"(<radius>50</radius><diffuse_coef>0</diffuse_coef>)"
                        R"(<emission r="1" g="1" b="1"/></properties></object>)";
    std::string glass = R"(<object><position x="0.2" y="-0.1" z="-4"/><specular_color r="1" g="1" b="1"/>)"
                        R"(<properties><type>sphere</type><radius>1.6</radius><diffuse_coef>0</diffuse_coef>)"
                        R"(<reflection_coef>0.04</reflection_coef><transmission_coef>1</transmission_coef>)"
                        R"(<refraction_coef>1.5</refraction_coef><fresnel>true</fresnel></properties></object>)";
    RenderResult r = render(sceneXml("", shell + glass, R"(<ambient_light r="0" g="0" b="0"/>)"), 2);
    double centreF = 1, rimF = 0;
    int hits = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            glm::dvec3 d = pixelRay(x, y);
            double b = glm::dot(-centre, d), c = glm::dot(centre, centre) - radius * radius;
            double disc = b * b - c;
            if (disc < 0.05) continue;  // misses, or grazes too steeply to call
            double t = -b - std::sqrt(disc);
            double cosTheta = glm::dot(glm::normalize(t * d - centre), -d);
            double f = f0 + (1.0 - f0) * std::pow(1.0 - cosTheta, 5.0);
            EXPECT_NEAR(pixel(r, gpu::kAovReflection, x, y).g, f, kTolerance) << x << "," << y;
            EXPECT_NEAR(pixel(r, gpu::kAovTransmission, x, y).g, (1.0 - f) * (1.0 - f), 1e-3) << x << "," << y;
            centreF = std::min(centreF, double(pixel(r, gpu::kAovReflection, x, y).g));
            rimF = std::max(rimF, double(pixel(r, gpu::kAovReflection, x, y).g));
            ++hits;
        }
    EXPECT_GT(hits, 500);
    EXPECT_NEAR(centreF, f0, 1e-3) << "F0 at normal incidence";
    EXPECT_GT(rimF, 0.15) << "more towards the rim";
}

INSTANTIATE_TEST_SUITE_P(TracePaths, LightsTest, ::testing::Values(TracePath::Bvh, TracePath::RayQuery),
                         [](const auto& info) { return info.param == TracePath::Bvh ? "Bvh" : "RayQuery"; });

// Emission is added where a ray hits and lights nothing else; the ambient
// term takes the ambient colour instead of Cd.
TEST(LightsMaterial, EmissionAndAmbientColour) {
    std::string lamp = R"(<object><position x="-1" y="0" z="-4"/><diffuse_color r="0.5" g="0.5" b="0.5"/>)"
                       R"(<properties><type>sphere</type><radius>0.5</radius><diffuse_coef>0</diffuse_coef>)"
                       R"(<emission r="2" g="1" b="0.5"/></properties></object>)";
    std::string ambient = R"(<object><position x="1.2" y="0" z="-4"/><diffuse_color r="0.9" g="0.9" b="0.9"/>)"
                          R"(<properties><type>sphere</type><radius>0.5</radius><diffuse_coef>0</diffuse_coef>)"
                          R"(<ambiente_coef>0.5</ambiente_coef><ambient_color r="0.2" g="0.4" b="0.6"/>)"
                          R"(</properties></object>)";
    std::string wall = R"(<object><position x="0" y="0" z="-5"/><properties><type>plane</type>)"
                       R"(<normal x="0" y="0" z="1"/></properties></object>)";
    RenderSettings s{.width = kWidth, .height = kHeight, .samplesPerPixel = 1, .maxDepth = 6, .auxiliary = true,
                     .antiAliasing = AntiAliasing::Uniform};
    RenderResult r = renderXml(sceneXml("", lamp + ambient + wall, R"(<ambient_light r="1" g="1" b="1"/>)"), s);
    // The spheres' centres project to x = 32 -+ 0.25 / tan(30) / (4/3) * 32 pixels.
    const double half = 32.0, scale = half / (std::tan(glm::radians(30.0)) * 4.0 / 3.0);
    int lampX = int(half - 0.25 * scale), ambientX = int(half + 0.3 * scale);
    glm::vec4 e = pixel(r, gpu::kAovColor, lampX, 24);
    EXPECT_EQ(glm::vec3(e), glm::vec3(2, 1, 0.5)) << "emission alone (kd 0, ka 0)";
    glm::vec4 a = pixel(r, gpu::kAovAmbient, ambientX, 24);
    EXPECT_NEAR(a.r, 0.5 * 0.2, 1e-6);
    EXPECT_NEAR(a.g, 0.5 * 0.4, 1e-6);
    EXPECT_NEAR(a.b, 0.5 * 0.6, 1e-6);
    // The wall (kd 1, no ambient term) stays black: emission lights nothing.
    for (int y = 0; y < kHeight; ++y) EXPECT_EQ(pixel(r, gpu::kAovColor, 2, y), glm::vec4(0, 0, 0, 1)) << y;
}

// The new elements' defaults change nothing: the room (glass, a mirror,
// Phong, two lights) with every default written out renders bit for bit as
// without them, every output layer included.
TEST(LightsMaterial, DefaultsAreBitIdentical) {
    std::ifstream in(sourceDir() / "scenes" / "room.xml");
    std::string xml((std::istreambuf_iterator<char>(in)), {});
    std::string withDefaults = xml;
    const std::string materialDefaults = R"(<fresnel>false</fresnel><transmission_color r="1" g="1" b="1"/>)"
                                         R"(<emission r="0" g="0" b="0"/>)";
    for (size_t at = 0; (at = withDefaults.find("<type>", at)) != std::string::npos;
         at += materialDefaults.size() + 6)
        withDefaults.insert(at, materialDefaults);
    for (size_t at = 0; (at = withDefaults.find("<light>", at)) != std::string::npos; at += 7)
        withDefaults.insert(at + 7, "<type>point</type><intensity>1</intensity><falloff>none</falloff>");
    ASSERT_NE(withDefaults, xml);
    Scene a = loadSceneFromString(xml, "room.xml"), b = loadSceneFromString(withDefaults, "room.xml");
    RenderSettings s{.width = 80, .height = 60, .samplesPerPixel = 1, .maxDepth = 6, .auxiliary = true,
                     .antiAliasing = AntiAliasing::Uniform};
    RenderResult ra = renderScene(a, s), rb = renderScene(b, s);
    ASSERT_EQ(ra.layers.size(), rb.layers.size());
    for (size_t l = 0; l < ra.layers.size(); ++l) EXPECT_TRUE(ra.layers[l] == rb.layers[l]) << "layer " << l;
    EXPECT_EQ(whitted::sceneXml(a), whitted::sceneXml(b)) << "and they are written as before";
}

// The loader reads every new element, and the writer writes them back
// (only where they are not the default).
TEST(LightsLoader, ReadsAndWritesLightTypesAndMaterialAdditions) {
    const std::string xml = R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>
  </camera><lights>
    <light><name>key</name><type>spot</type><position x="1" y="2" z="3"/><color r="1" g="0.5" b="0.25"/>
      <intensity>4</intensity><falloff>inverse_square</falloff><direction x="0" y="-2" z="0"/>
      <inner_angle>10</inner_angle><outer_angle>30</outer_angle></light>
    <light><type>directional</type><color r="1" g="1" b="1"/><direction x="1" y="-1" z="0"/></light>
    <light><position x="0" y="1" z="0"/><color r="1" g="1" b="1"/></light>
  </lights><objects>
    <object><name>glass &amp; co</name><position x="0" y="0" z="0"/><properties><type>sphere</type>
      <radius>1</radius><fresnel>true</fresnel><transmission_color r="0.9" g="0.8" b="0.7"/>
      <emission r="2" g="0" b="0"/><ambient_color r="0.1" g="0.2" b="0.3"/></properties></object>
  </objects></scene>)";
    Scene scene = loadSceneFromString(xml, "t.xml");
    ASSERT_EQ(scene.lights.size(), 3u);
    const Light& spot = scene.lights[0];
    EXPECT_EQ(spot.type, Light::Type::Spot);
    EXPECT_EQ(spot.name, "key");
    EXPECT_EQ(spot.position, glm::dvec3(1, 2, 3));
    EXPECT_EQ(spot.intensity, 4.0);
    EXPECT_EQ(spot.falloff, Light::Falloff::InverseSquare);
    EXPECT_EQ(spot.direction, glm::dvec3(0, -1, 0)) << "made unit length";
    EXPECT_EQ(spot.innerAngleDegrees, 10.0);
    EXPECT_EQ(spot.outerAngleDegrees, 30.0);
    EXPECT_EQ(scene.lights[1].type, Light::Type::Directional);
    EXPECT_EQ(scene.lights[2].type, Light::Type::Point);
    EXPECT_EQ(scene.lights[2].intensity, 1.0);
    EXPECT_EQ(scene.lights[2].falloff, Light::Falloff::None);
    const Object& o = scene.objects[0];
    EXPECT_EQ(o.name, "glass & co");
    EXPECT_TRUE(o.material.fresnel);
    EXPECT_EQ(o.material.transmissionColor, glm::dvec3(0.9, 0.8, 0.7));
    EXPECT_EQ(o.material.emission, glm::dvec3(2, 0, 0));
    ASSERT_TRUE(o.material.ambientColor);
    EXPECT_EQ(*o.material.ambientColor, glm::dvec3(0.1, 0.2, 0.3));

    std::string written = whitted::sceneXml(scene);
    Scene again = loadSceneFromString(written, "again.xml");
    ASSERT_EQ(again.lights.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        const Light &l = scene.lights[i], &m = again.lights[i];
        EXPECT_EQ(l.type, m.type);
        EXPECT_EQ(l.name, m.name);
        EXPECT_EQ(l.position, m.position);
        EXPECT_EQ(l.color, m.color);
        EXPECT_EQ(l.intensity, m.intensity);
        EXPECT_EQ(l.falloff, m.falloff);
        // Read back, a unit vector is made unit length again: the same to rounding.
        EXPECT_NEAR(glm::length(l.direction - m.direction), 0.0, 1e-15);
        EXPECT_EQ(l.innerAngleDegrees, m.innerAngleDegrees);
        EXPECT_EQ(l.outerAngleDegrees, m.outerAngleDegrees);
    }
    EXPECT_EQ(again.objects[0].name, "glass & co");
    EXPECT_TRUE(again.objects[0].material.fresnel);
    EXPECT_EQ(again.objects[0].material.transmissionColor, o.material.transmissionColor);
    EXPECT_EQ(again.objects[0].material.emission, o.material.emission);
    EXPECT_EQ(again.objects[0].material.ambientColor, o.material.ambientColor);
    // The point light of the seed is written as the seed wrote it.
    EXPECT_NE(written.find("<light>\n      <position x=\"0\" y=\"1\" z=\"0\"/>\n      <color r=\"1\" g=\"1\" "
                           "b=\"1\"/>\n    </light>"),
              std::string::npos)
        << written;
}

// What a light type does not use is refused, word for word.
TEST(LightsLoader, RefusesWhatATypeDoesNotUse) {
    auto errorOf = [](const std::string& light) {
        try {
            loadSceneFromString(R"(<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/>)"
                                "</camera><lights>\n<light>" +
                                    light + "</light></lights><objects/></scene>",
                                "t.xml");
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string white = R"(<color r="1" g="1" b="1"/>)";
    EXPECT_EQ(errorOf(R"(<position x="0" y="0" z="0"/>)" + white + R"(<direction x="0" y="-1" z="0"/>)"),
              "t.xml:2: <direction> does not apply to a point light; only spot and directional lights have one");
    EXPECT_EQ(errorOf(R"(<position x="0" y="0" z="0"/>)" + white + "<inner_angle>5</inner_angle>"),
              "t.xml:2: <inner_angle> does not apply to a point light; only a spot light has a cone");
    EXPECT_EQ(errorOf("<type>directional</type>" + white + R"(<direction x="0" y="-1" z="0"/>)" +
                      "<falloff>inverse_square</falloff>"),
              "t.xml:2: <falloff> does not apply to a directional light; its light does not weaken with distance");
    EXPECT_EQ(errorOf("<type>spot</type>" + white + R"(<position x="0" y="0" z="0"/>)"),
              "t.xml:2: <light> is missing <direction> (required for a spot light)");
    EXPECT_EQ(errorOf("<type>spot</type>" + white + R"(<position x="0" y="0" z="0"/>)" +
                      R"(<direction x="0" y="-1" z="0"/><inner_angle>50</inner_angle>)"),
              "t.xml:2: <outer_angle> (45) must be greater than <inner_angle> (50); a spot has 0 <= inner < outer "
              "<= 90 degrees");
}

}  // namespace
}  // namespace whitted::test

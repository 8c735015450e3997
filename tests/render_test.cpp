// Render tests that know the right answer without a reference image
// (pbrt-v4 integrators_test style), plus the invariants of the output layers.
#include "scene/scene_loader.h"
#include "test_support.h"

#include <cmath>

namespace whitted::test {
namespace {

constexpr float kTolerance = 1e-4f;

// A camera at the origin looking down -z with the given light list and
// objects (XML fragments), rendered small.
std::string sceneXml(const std::string& lights, const std::string& objects, const std::string& extra = "") {
    return R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
           R"(<width>32</width><height>24</height></camera>)" +
           extra + "<lights>" + lights + "</lights><objects>" + objects + "</objects></scene>";
}

std::string sphereXml(const std::string& center, double radius, const std::string& properties,
                      const std::string& diffuse = R"(r="1" g="1" b="1")") {
    return "<object><position " + center + "/><diffuse_color " + diffuse + "/><properties><type>sphere</type><radius>" +
           std::to_string(radius) + "</radius>" + properties + "</properties></object>";
}

RenderSettings small(int spp = 1, int maxDepth = 6) {
    return {.width = 32, .height = 24, .samplesPerPixel = spp, .maxDepth = maxDepth, .auxiliary = true};
}

// The five colour components add up to the main image (each ray's light is
// tagged with the primary-hit component that spawned it).
TEST(RenderLayers, ColourComponentsSumToMainImage) {
    Scene scene = loadScene(sourceDir() / "scenes" / "room.xml");
    RenderResult r = renderScene(scene, {.width = 64, .height = 48, .samplesPerPixel = 2, .maxDepth = 6, .auxiliary = true});
    double maxError = 0, totalReflection = 0, totalTransmission = 0;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            glm::vec4 sum(0);
            for (uint32_t l = gpu::kAovAmbient; l <= gpu::kAovTransmission; ++l) sum += pixel(r, l, x, y);
            glm::vec4 color = pixel(r, gpu::kAovColor, x, y);
            for (int c = 0; c < 3; ++c) maxError = std::max(maxError, double(std::abs(sum[c] - color[c])));
            totalReflection += pixel(r, gpu::kAovReflection, x, y).g;
            totalTransmission += pixel(r, gpu::kAovTransmission, x, y).g;
        }
    EXPECT_LT(maxError, 1e-5);
    // The room has a mirror and a glass sphere: both components carry light.
    EXPECT_GT(totalReflection, 1.0);
    EXPECT_GT(totalTransmission, 1.0);
}

// The ambient layer is exactly ka Cd A where a surface is visible.
TEST(RenderLayers, AmbientLayerIsKaCdA) {
    std::string xml = sceneXml("", sphereXml(R"(x="0" y="0" z="-5")", 2.0, "<ambiente_coef>0.3</ambiente_coef>",
                                             R"(r="0.2" g="0.4" b="0.6")"),
                               R"(<ambient_light r="0.5" g="1" b="0.25"/>)");
    RenderResult r = renderXml(xml, small());
    glm::vec4 a = pixel(r, gpu::kAovAmbient, 16, 12);
    EXPECT_NEAR(a.r, 0.3f * 0.2f * 0.5f, 1e-6f);
    EXPECT_NEAR(a.g, 0.3f * 0.4f * 1.0f, 1e-6f);
    EXPECT_NEAR(a.b, 0.3f * 0.6f * 0.25f, 1e-6f);
    EXPECT_EQ(pixel(r, gpu::kAovColor, 0, 0), glm::vec4(0, 0, 0, 1)) << "background is black";
}

// A Lambert sphere lit from the eye: every pixel is kd cos(theta), theta the
// angle between the surface normal and the direction back to the eye,
// computed here in double precision from the same camera model.
TEST(RenderAnalytic, LambertSphereLitFromTheEye) {
    const glm::dvec3 center(0.3, -0.2, -4.0);
    const double radius = 1.5, kd = 0.8;
    std::string xml = sceneXml(R"(<light><position x="0" y="0" z="0"/><color r="1" g="1" b="1"/></light>)",
                               sphereXml(R"(x="0.3" y="-0.2" z="-4")", radius, "<diffuse_coef>0.8</diffuse_coef>"));
    RenderResult r = renderXml(xml, small());
    const double tanHalf = std::tan(glm::radians(60.0) / 2.0), aspect = 32.0 / 24.0;
    int hits = 0;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / 32.0 - 1.0) * tanHalf * aspect,
                                                     (1.0 - 2.0 * (y + 0.5) / 24.0) * tanHalf, -1.0));
            double b = glm::dot(-center, d), c = glm::dot(center, center) - radius * radius;
            double disc = b * b - c;
            float got = pixel(r, gpu::kAovColor, x, y).r;
            if (disc < 1e-3) {  // misses, and grazing pixels too close to call
                if (disc < -1e-3) {
                    EXPECT_EQ(got, 0.0f) << x << "," << y;
                }
                continue;
            }
            double t = -b - std::sqrt(disc);
            glm::dvec3 n = glm::normalize(t * d - center);
            double expected = kd * glm::dot(n, -d);
            EXPECT_NEAR(got, expected, kTolerance) << "pixel " << x << "," << y;
            ++hits;
        }
    EXPECT_GT(hits, 100);
}

// A sphere with IOR 1, kt 1 and no other term is invisible: the image with
// it equals the image without it, its shadow included.
TEST(RenderAnalytic, IndexOneClearSphereIsInvisible) {
    std::string light = R"(<light><position x="2" y="3" z="0"/><color r="1" g="1" b="1"/></light>)";
    std::string floor = R"(<object><position x="0" y="-1" z="0"/><properties><type>plane</type>)"
                        R"(<normal x="0" y="1" z="0"/><ambiente_coef>0.1</ambiente_coef></properties></object>)"
                        R"(<object><position x="0" y="0" z="-8"/><diffuse_color r="0.5" g="0.7" b="0.9"/><properties>)"
                        R"(<type>plane</type><normal x="0" y="0" z="1"/></properties></object>)";
    std::string clear = sphereXml(R"(x="0.2" y="0" z="-4")", 0.8,
                                  "<diffuse_coef>0</diffuse_coef><transmission_coef>1</transmission_coef>"
                                  "<refraction_coef>1</refraction_coef>");
    RenderResult with = renderXml(sceneXml(light, floor + clear), small(1, 6));
    RenderResult without = renderXml(sceneXml(light, floor), small(1, 6));
    for (int y = 0; y < with.height; ++y)
        for (int x = 0; x < with.width; ++x) {
            glm::vec4 a = pixel(with, gpu::kAovColor, x, y), b = pixel(without, gpu::kAovColor, x, y);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], kTolerance) << "pixel " << x << "," << y;
        }
}

// Total internal reflection: from inside a glass sphere (IOR 1.5) a ray
// whose impact parameter is 0.95 radius meets the surface at 71.8 degrees,
// past the critical angle of 41.8 degrees, and every later chord meets it at
// the same angle. With kt 1, ka a and nothing else, the first hit gives a to
// the ambient layer and each of the maxDepth reflections adds a to the
// reflection layer; nothing is transmitted. A ray through the centre leaves.
TEST(RenderAnalytic, TotalInternalReflectionPastTheCriticalAngle) {
    const float a = 0.1f;
    std::string glass = sphereXml(R"(x="0.95" y="0" z="0")", 1.0,
                                  "<ambiente_coef>0.1</ambiente_coef><diffuse_coef>0</diffuse_coef>"
                                  "<transmission_coef>1</transmission_coef><refraction_coef>1.5</refraction_coef>");
    std::string backdrop = R"(<object><position x="0" y="0" z="-20"/><properties><type>plane</type>)"
                           R"(<normal x="0" y="0" z="1"/><ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>)";
    RenderResult r = renderXml(sceneXml("", glass + backdrop), small(1, 3));
    glm::vec4 ambient = pixel(r, gpu::kAovAmbient, 16, 12);
    glm::vec4 reflection = pixel(r, gpu::kAovReflection, 16, 12);
    glm::vec4 transmission = pixel(r, gpu::kAovTransmission, 16, 12);
    EXPECT_NEAR(ambient.r, a, 1e-6f);
    EXPECT_NEAR(reflection.r, 3 * a, 1e-5f);
    EXPECT_EQ(transmission.r, 0.0f);

    // Control: with the eye 0.3 radius off the centre (sin 0.3 < 1/1.5) the
    // ray refracts out twice and reaches the white backdrop.
    std::string nearCentre = glass;
    nearCentre.replace(nearCentre.find("0.95"), 4, "0.3");
    RenderResult control = renderXml(sceneXml("", nearCentre + backdrop), small(1, 3));
    EXPECT_NEAR(pixel(control, gpu::kAovTransmission, 16, 12).r, 1.0f, 1e-5f);
    EXPECT_EQ(pixel(control, gpu::kAovReflection, 16, 12).r, 0.0f);
}

// --max-depth 0 shows local shading only: no secondary ray is traced.
TEST(RenderAnalytic, MaxDepthZeroTracesNoSecondaryRays) {
    Scene scene = loadScene(sourceDir() / "scenes" / "room.xml");
    RenderResult r = renderScene(scene, {.width = 32, .height = 24, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true});
    EXPECT_EQ(r.rays.secondary, 0u);
    EXPECT_EQ(r.rays.primary, 32u * 24u);
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            EXPECT_EQ(pixel(r, gpu::kAovReflection, x, y), glm::vec4(0, 0, 0, 1));
            EXPECT_EQ(pixel(r, gpu::kAovTransmission, x, y), glm::vec4(0, 0, 0, 1));
        }
}

// The shader counts every camera sample.
TEST(RenderAnalytic, CountsOnePrimaryRayPerSample) {
    Scene scene = loadScene(sourceDir() / "scenes" / "three_diffuse_spheres.xml");
    RenderResult r = renderScene(scene, {.width = 40, .height = 30, .samplesPerPixel = 3, .maxDepth = 6, .auxiliary = false});
    EXPECT_EQ(r.rays.primary, 40u * 30u * 3u);
    EXPECT_GT(r.rays.shadow, 0u);
}

// The same scene, settings and device give a bit-identical image, however
// the samples are split into dispatches.
TEST(RenderAnalytic, RenderingIsDeterministic) {
    Scene scene = loadScene(sourceDir() / "scenes" / "room.xml");
    RenderSettings s{.width = 136, .height = 40, .samplesPerPixel = 5, .maxDepth = 6, .auxiliary = false};
    RenderResult a = renderScene(scene, s);
    RenderResult b = renderScene(scene, s);
    EXPECT_TRUE(a.layers[gpu::kAovColor] == b.layers[gpu::kAovColor]);
    // Two 128-pixel tiles, and at most 700 camera samples per dispatch: one
    // sample per dispatch, ten dispatches instead of two. The same samples
    // are traced; only the order of the floating-point sums changes.
    s.samplesPerDispatch = 700;
    RenderResult split = renderScene(scene, s);
    ASSERT_EQ(a.layers[gpu::kAovColor].size(), split.layers[gpu::kAovColor].size());
    for (size_t i = 0; i < a.layers[gpu::kAovColor].size(); ++i)
        ASSERT_NEAR(a.layers[gpu::kAovColor][i], split.layers[gpu::kAovColor][i], 1e-6f) << i;
    EXPECT_EQ(a.rays.total(), split.rays.total());
}

// A perfect mirror facing the camera shows the sphere behind the camera
// with the mirror's specular colour as the weight.
TEST(RenderAnalytic, MirrorReflectsWithSpecularColourWeight) {
    std::string light = R"(<light><position x="0" y="0" z="3"/><color r="1" g="1" b="1"/></light>)";
    std::string mirror = R"(<object><position x="0" y="0" z="-3"/><specular_color r="0.5" g="1" b="1"/><properties>)"
                         R"(<type>plane</type><normal x="0" y="0" z="1"/><diffuse_coef>0</diffuse_coef>)"
                         R"(<specular_coef>1</specular_coef><shininess>1e5</shininess><reflective>true</reflective></properties></object>)";
    // Behind the eye, seen only in the mirror; lit by its ambient term alone.
    std::string sphere = sphereXml(R"(x="0" y="0" z="6")", 2.0, "<ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef>");
    RenderResult r = renderXml(sceneXml(light, mirror + sphere), small(1, 1));
    glm::vec4 c = pixel(r, gpu::kAovReflection, 16, 12);
    EXPECT_NEAR(c.r, 0.5f, kTolerance);  // ka Cd A = 1, times Cs = (0.5, 1, 1)
    EXPECT_NEAR(c.g, 1.0f, kTolerance);
    EXPECT_NEAR(pixel(r, gpu::kAovReflection, 0, 0).g, 0.0f, kTolerance) << "the reflected ray misses near the corner";
}

// The primary ray through pixel (x, y) of a w x h image from the camera of
// sceneXml (eye at the origin, looking down -z, 60 degree vertical fov), in
// double precision. Pixel centres: with 1 spp the sample is the centre.
glm::dvec3 cameraRay(int x, int y, int w, int h) {
    const double tanHalf = std::tan(glm::radians(60.0) / 2.0), aspect = double(w) / h;
    return glm::normalize(glm::dvec3((2.0 * (x + 0.5) / w - 1.0) * tanHalf * aspect,
                                     (1.0 - 2.0 * (y + 0.5) / h) * tanHalf, -1.0));
}

// Snell's law in double precision: d refracted at a surface with normal n
// (facing the incoming ray) from index 1 into index eta2/eta1 = 1/eta.
glm::dvec3 snell(glm::dvec3 d, glm::dvec3 n, double eta) {
    double cosi = -glm::dot(n, d);
    double k = 1.0 - eta * eta * (1.0 - cosi * cosi);
    return glm::normalize(eta * d + (eta * cosi - std::sqrt(k)) * n);
}

// A glass slab (a wide box from z = -2 to z = -8, IOR 1.5, kt 1, no other
// term) in front of a lit half-space (an ambient-only box for x > 8,
// z = -10 .. -11). Each ray leaves the slab parallel to itself, shifted sideways by
// thickness * sin(i - r) / cos(r) (Snell: sin i = 1.5 sin r), so the edge of
// the lit box appears moved towards the centre of the image. Every pixel's
// transmission is predicted by refracting its ray in double precision.
TEST(RenderAnalytic, GlassSlabShiftsRaysAsSnellSays) {
    const int w = 96, h = 24;
    const double edge = 8.0, ior = 1.5;
    std::string slab = R"(<object><position x="-100" y="-100" z="-8"/><properties><type>box</type>)"
                       R"(<size x="200" y="200" z="6"/><diffuse_coef>0</diffuse_coef><transmission_coef>1</transmission_coef>)"
                       R"(<refraction_coef>1.5</refraction_coef></properties></object>)";
    std::string lit = R"(<object><position x="8" y="-100" z="-11"/><properties><type>box</type>)"
                      R"(<size x="100" y="200" z="1"/><ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>)";
    RenderResult r = renderXml(sceneXml("", slab + lit), {.width = w, .height = h, .samplesPerPixel = 1, .maxDepth = 6, .auxiliary = true});
    int litPixels = 0, shifted = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = cameraRay(x, y, w, h);
            glm::dvec3 p1 = d * (2.0 / -d.z);                      // enters at z = -2
            glm::dvec3 inside = snell(d, {0, 0, 1}, 1.0 / ior);
            glm::dvec3 p2 = p1 + inside * (6.0 / -inside.z);       // leaves at z = -8
            glm::dvec3 out = snell(inside, {0, 0, 1}, ior);        // parallel to d again
            // The lit box spans z = -10 .. -11: the ray meets it on its front
            // face or, passing just beside it, on its side face x = 8.
            double hitX = std::max((p2 + out * (2.0 / -out.z)).x, (p2 + out * (3.0 / -out.z)).x);
            double straightX = std::max((d * (10.0 / -d.z)).x, (d * (11.0 / -d.z)).x);
            EXPECT_NEAR(glm::length(out - d), 0.0, 1e-12);
            if (std::abs(hitX - edge) < 0.02) continue;  // too close to the edge to call
            float expected = hitX > edge ? 1.0f : 0.0f;
            EXPECT_NEAR(pixel(r, gpu::kAovTransmission, x, y).r, expected, kTolerance) << "pixel " << x << "," << y;
            litPixels += expected > 0;
            shifted += (straightX > edge) != (hitX > edge);
        }
    EXPECT_GT(litPixels, 100);
    EXPECT_GE(shifted, 2 * h) << "the shift must move the edge by whole pixels, or this test proves nothing";
}

// Shadows take the colour of glass: a floor lit from above through a glass
// sphere (kt 0.8, kd 0.5, Cd reddish) receives light filtered by
// kt * mix(white, Cd, kd) at each of the two crossings of the sphere, and
// the full light elsewhere. Every floor pixel's diffuse term is predicted in
// double precision, shadow rays included.
TEST(RenderAnalytic, ShadowThroughGlassTakesItsColour) {
    const int w = 64, h = 48;
    const glm::dvec3 light(0, 4, -4), center(0, 0, -4);
    const double radius = 0.9;
    const glm::dvec3 cd(1.0, 0.2, 0.4), filter = 0.8 * glm::mix(glm::dvec3(1.0), cd, 0.5);
    std::string lights = R"(<light><position x="0" y="4" z="-4"/><color r="1" g="1" b="1"/></light>)";
    std::string floor = R"(<object><position x="0" y="-1" z="0"/><properties><type>plane</type>)"
                        R"(<normal x="0" y="1" z="0"/></properties></object>)";
    std::string glass = sphereXml(R"(x="0" y="0" z="-4")", radius,
                                  "<diffuse_coef>0.5</diffuse_coef><transmission_coef>0.8</transmission_coef>"
                                  "<refraction_coef>1.5</refraction_coef>",
                                  R"(r="1" g="0.2" b="0.4")");
    RenderResult r = renderXml(sceneXml(lights, floor + glass), {.width = w, .height = h, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true});
    // Crossings of the segment from p to the light with the sphere: 0 or 2,
    // or -1 when the segment grazes it too closely to call.
    auto crossings = [&](glm::dvec3 p) {
        glm::dvec3 toLight = light - p;
        double dist = glm::length(toLight);
        glm::dvec3 l = toLight / dist;
        double b = glm::dot(p - center, l), c = glm::dot(p - center, p - center) - radius * radius;
        double disc = b * b - c;
        if (std::abs(disc) < 1e-3) return -1;
        return disc > 0 && -b - std::sqrt(disc) > 0 ? 2 : 0;
    };
    int tinted = 0, open = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = cameraRay(x, y, w, h);
            if (d.y >= -1e-3) continue;  // above the horizon
            double bs = glm::dot(-center, d), cs = glm::dot(center, center) - radius * radius;
            if (bs * bs - cs > -1e-3) continue;  // sees the sphere, or nearly
            glm::dvec3 p = d * (-1.0 / d.y);
            int n = crossings(p);
            if (n < 0) continue;
            double nDotL = glm::normalize(light - p).y;
            glm::dvec3 expected = nDotL * (n == 2 ? filter * filter : glm::dvec3(1.0));
            glm::vec4 got = pixel(r, gpu::kAovDiffuse, x, y);
            for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expected[ch], kTolerance) << "pixel " << x << "," << y;
            (n == 2 ? tinted : open) += 1;
        }
    EXPECT_GT(tinted, 20);
    EXPECT_GT(open, 200);
}

// Absorption (Beer-Lambert). A wide slab of clear glass (IOR 1: no bending,
// kt 1, no other term) from z = -3 to z = -2 with sigma = (0.2, 0.7, 1.5)
// in front of an ambient-only backdrop: each pixel shows the backdrop times
// exp(-sigma d), d = 1 / |dir.z| the length of its ray inside the slab.
// With sigma = 0 the image is bit for bit that of a slab without the element.
std::string absorbingSlab(const std::string& absorption) {
    std::string backdrop = R"(<object><position x="0" y="0" z="-8"/><diffuse_color r="0.5" g="0.7" b="0.9"/>)"
                           R"(<properties><type>plane</type><normal x="0" y="0" z="1"/>)"
                           R"(<ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>)";
    std::string slab = R"(<object><position x="-20" y="-20" z="-3"/><properties><type>box</type>)"
                       R"(<size x="40" y="40" z="1"/><diffuse_coef>0</diffuse_coef>)"
                       R"(<transmission_coef>1</transmission_coef><refraction_coef>1</refraction_coef>)" +
                       absorption + "</properties></object>";
    return sceneXml("", backdrop + slab);
}

TEST(RenderAnalytic, AbsorptionAttenuatesTransmittedLight) {
    const glm::dvec3 sigma(0.2, 0.7, 1.5), backdrop(0.5, 0.7, 0.9);
    RenderResult r = renderXml(absorbingSlab(R"(<absorption r="0.2" g="0.7" b="1.5"/>)"), small());
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            double d = 1.0 / std::abs(cameraRay(x, y, r.width, r.height).z);
            glm::vec4 got = pixel(r, gpu::kAovColor, x, y);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], std::exp(-sigma[c] * d) * backdrop[c], kTolerance) << "pixel " << x << "," << y;
        }
}

TEST(RenderAnalytic, ZeroAbsorptionChangesNothing) {
    RenderResult with = renderXml(absorbingSlab(R"(<absorption r="0" g="0" b="0"/>)"), small());
    RenderResult without = renderXml(absorbingSlab(""), small());
    for (uint32_t l = 0; l < gpu::kAovCount; ++l) EXPECT_EQ(with.layers[l], without.layers[l]) << "layer " << l;
    // And through the slab at all: exactly the backdrop.
    EXPECT_NEAR(pixel(with, gpu::kAovColor, 16, 12).b, 0.9f, kTolerance);
}

// The shadow of an absorbing slab: a floor lit from above through a clear
// slab (kt 1, kd 0: no filter) 0.5 thick with sigma = (0.3, 1, 2) takes
// exp(-sigma * 0.5 / l.y) of the light, l the unit direction to the light;
// the same slab with sigma = 0 casts no shadow at all, bit for bit.
TEST(RenderAnalytic, AbsorptionAttenuatesShadowRays) {
    const int w = 64, h = 48;
    const glm::dvec3 light(0, 4, -4), sigma(0.3, 1.0, 2.0);
    auto scene = [](const std::string& absorption) {
        std::string lights = R"(<light><position x="0" y="4" z="-4"/><color r="1" g="1" b="1"/></light>)";
        std::string floor = R"(<object><position x="0" y="-1" z="0"/><properties><type>plane</type>)"
                            R"(<normal x="0" y="1" z="0"/></properties></object>)";
        std::string slab = R"(<object><position x="-50" y="0.5" z="-50"/><properties><type>box</type>)"
                           R"(<size x="100" y="0.5" z="60"/><diffuse_coef>0</diffuse_coef>)"
                           R"(<transmission_coef>1</transmission_coef><refraction_coef>1</refraction_coef>)" +
                           absorption + "</properties></object>";
        return sceneXml(lights, floor + slab);
    };
    RenderSettings settings{.width = w, .height = h, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true};
    RenderResult r = renderXml(scene(R"(<absorption r="0.3" g="1" b="2"/>)"), settings);
    int checked = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = cameraRay(x, y, w, h);
            if (d.y >= -1e-3) continue;  // above the horizon
            glm::dvec3 p = d * (-1.0 / d.y);
            if (p.z < -20.0 || std::abs(p.x) > 20.0) continue;  // the path to the light leaves by the slab's sides
            glm::dvec3 l = glm::normalize(light - p);
            glm::vec4 got = pixel(r, gpu::kAovDiffuse, x, y);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], l.y * std::exp(-sigma[c] * 0.5 / l.y), kTolerance) << "pixel " << x << "," << y;
            ++checked;
        }
    EXPECT_GT(checked, 500);
    RenderResult zero = renderXml(scene(R"(<absorption r="0" g="0" b="0"/>)"), settings);
    RenderResult none = renderXml(scene(""), settings);
    for (uint32_t l = 0; l < gpu::kAovCount; ++l) EXPECT_EQ(zero.layers[l], none.layers[l]) << "layer " << l;
}

// The solid checker on a plane y = -1 anchored at x = 0.3, z = 0.1 with
// cells of 0.5: the ambient layer is ka Cd A in cells of even coordinate sum
// and ka Cc A in odd ones; the plane itself lies on a cell boundary
// (y - (-1) = 0), which the 0.001 tolerance puts in cell 0 everywhere.
TEST(RenderAnalytic, CheckerPicksTheColourByCell) {
    const int w = 64, h = 48;
    std::string floor = R"(<object><position x="0.3" y="-1" z="0.1"/><diffuse_color r="0.9" g="0.5" b="0.1"/>)"
                        R"(<properties><type>plane</type><normal x="0" y="1" z="0"/><ambiente_coef>1</ambiente_coef>)"
                        R"(<checker_color r="0.1" g="0.2" b="0.8"/><checker_size>0.5</checker_size>)"
                        R"(</properties></object>)";
    RenderResult r = renderXml(sceneXml("", floor),
                               {.width = w, .height = h, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true});
    int even = 0, odd = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = cameraRay(x, y, w, h);
            if (d.y >= -1e-3) continue;
            glm::dvec3 q = (d * (-1.0 / d.y) - glm::dvec3(0.3, -1, 0.1)) / 0.5 + 0.001;
            glm::dvec3 f = q - glm::floor(q);
            if (std::min(f.x, f.z) < 0.02 || std::max(f.x, f.z) > 0.98) continue;  // too close to a cell edge to call
            bool isOdd = (long(std::floor(q.x)) + long(std::floor(q.z))) % 2 != 0;
            glm::dvec3 expected = isOdd ? glm::dvec3(0.1, 0.2, 0.8) : glm::dvec3(0.9, 0.5, 0.1);
            glm::vec4 got = pixel(r, gpu::kAovAmbient, x, y);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-6) << "pixel " << x << "," << y;
            (isOdd ? odd : even) += 1;
        }
    EXPECT_GT(even, 100);
    EXPECT_GT(odd, 100);
}

// The scene's arrays are read through buffer device addresses, not storage
// buffer descriptors, so a scene beyond maxStorageBufferRange renders (it
// used to be refused). On lavapipe (128 MiB) 2^21 + 1 spheres overrun it in
// the primitives and in the materials (one per object). The last
// object, in front of the lattice, has the material at index 2^21, past the
// old range: the image must show it red, the lattice green, gaps black.
TEST(RenderLimits, SceneBeyondTheStorageBufferRangeRenders) {
    vk::DeviceSize range = testContext().physicalDevice.getProperties().limits.maxStorageBufferRange;
    if (range > (vk::DeviceSize(256) << 20))
        GTEST_SKIP() << "this device's storage buffer range (" << (range >> 20)
                     << " MiB) needs a scene too large to build";
    Scene scene = loadSceneFromString(sceneXml("", ""), "inline.xml");
    size_t count = size_t(range / sizeof(gpu::Primitive)) + 1;
    Material lattice{.diffuseColor = {0, 1, 0}, .ambient = 1.0};
    scene.objects.reserve(count);
    for (size_t i = 0; i + 1 < count; ++i)
        scene.objects.push_back(
            {.shape = Sphere{{double(i % 2048), double(i / 2048), -10.0}, 0.4}, .material = lattice});
    const glm::dvec3 nearCenter{-1.5, -1.0, -5.0};
    const double nearRadius = 0.8;
    scene.objects.push_back(
        {.shape = Sphere{nearCenter, nearRadius}, .material = {.diffuseColor = {1, 0, 0}, .ambient = 1.0}});

    const int w = 32, h = 24;
    RenderResult r =
        renderScene(scene, {.width = w, .height = h, .samplesPerPixel = 1, .maxDepth = 0, .auxiliary = false});
    // Distance along unit ray d from the eye to a sphere, or a negative
    // number; sets nearRim where the ray passes too close to the rim to call.
    auto hitSphere = [](glm::dvec3 d, glm::dvec3 c, double radius, bool& nearRim) {
        double b = glm::dot(c, d), disc = b * b - (glm::dot(c, c) - radius * radius);
        nearRim = nearRim || std::abs(disc) < 0.02;
        return disc > 0 ? b - std::sqrt(disc) : -1.0;
    };
    int red = 0, green = 0, black = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 d = cameraRay(x, y, w, h), expected(0.0);
            bool nearRim = false;
            if (hitSphere(d, nearCenter, nearRadius, nearRim) > 0) {
                expected = {1, 0, 0};
            } else {
                // The lattice spheres the ray can meet lie next to where it crosses z = -10.
                glm::dvec3 p = d * (10.0 / -d.z);
                for (double gy = std::floor(p.y) - 1; gy <= std::floor(p.y) + 2; ++gy)
                    for (double gx = std::floor(p.x) - 1; gx <= std::floor(p.x) + 2; ++gx)
                        if (gx >= 0 && gx < 2048 && gy >= 0 && hitSphere(d, {gx, gy, -10.0}, 0.4, nearRim) > 0)
                            expected = {0, 1, 0};
            }
            if (nearRim) continue;
            glm::vec4 got = pixel(r, gpu::kAovColor, x, y);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], kTolerance) << "pixel " << x << "," << y;
            (expected.r > 0 ? red : expected.g > 0 ? green : black) += 1;
        }
    EXPECT_GT(red, 10);
    EXPECT_GT(green, 20);
    EXPECT_GT(black, 20);
    EXPECT_GT(r.deviceBytes, 2 * range);  // primitives and materials each past the old range
}

// A scene array larger than one buffer may be is refused with its count,
// its bytes and the limit, before anything is packed or allocated. The limits
// here are made up (a real scene over them takes gigabytes).
TEST(RenderLimits, SceneBeyondTheBufferLimitIsAClearError) {
    BufferLimits limits{.maxBufferSize = (uint64_t(4) << 30) - 1, .maxAllocationSize = uint64_t(2) << 30};
    uint64_t fit = limits.maxAllocationSize / sizeof(gpu::Primitive);
    uint64_t nodesFit = limits.maxAllocationSize / sizeof(gpu::BvhNode);
    EXPECT_EQ(sceneArraysTooLarge({.primitives = fit, .bvhNodes = nodesFit, .materials = 1, .lights = 1}, limits),
              std::nullopt);
    EXPECT_EQ(sceneArraysTooLarge({.primitives = fit + 1, .bvhNodes = 2 * fit + 1, .materials = 1, .lights = 1},
                                  limits),
              "the scene's 33554433 primitives (triangles count one each) need 2147483712 bytes (2048 MiB) in one "
              "buffer, more than this device's maxMemoryAllocationSize of 2147483648 bytes (2048 MiB, 33554432 of "
              "them)");
    // The smaller of the two limits is named.
    BufferLimits smallBuffer{.maxBufferSize = uint64_t(1) << 20, .maxAllocationSize = uint64_t(2) << 30};
    EXPECT_EQ(sceneArraysTooLarge({.primitives = 1, .bvhNodes = 1, .materials = 1, .lights = 40000}, smallBuffer),
              "the scene's 40000 lights need 3840000 bytes (3 MiB) in one buffer, more than this device's "
              "maxBufferSize of 1048576 bytes (1 MiB, 10922 of them)");
    // Beyond the shader's 32-bit indices even where the device allows more.
    BufferLimits huge{.maxBufferSize = UINT64_MAX, .maxAllocationSize = UINT64_MAX};
    EXPECT_EQ(sceneArraysTooLarge({.primitives = uint64_t(1) << 31, .bvhNodes = 1, .materials = 1, .lights = 1}, huge),
              "the scene's 2147483648 primitives (triangles count one each) are more than the shader's 32-bit "
              "indices address (2147483647)");

    // The counts come from the scene before packing; the BVH's is its bound.
    std::string light = R"(<light><position x="0" y="0" z="0"/><color r="1" g="1" b="1"/></light>)";
    std::string spheres = sphereXml(R"(x="0" y="0" z="-5")", 1.0, "") + sphereXml(R"(x="1" y="0" z="-5")", 1.0, "");
    Scene scene = loadSceneFromString(sceneXml(light, spheres), "inline.xml");
    SceneArrayCounts counts = countSceneArrays(scene);
    EXPECT_EQ(counts.primitives, 2u);
    EXPECT_EQ(counts.bvhNodes, 1u);  // collapseToWide: at most max(leaves - 1, 1)
    EXPECT_EQ(counts.materials, 2u);
    EXPECT_EQ(counts.lights, 1u);

    // The device's own limits are read (lavapipe: 2 GiB allocations, buffers of 4 GiB - 1).
    BufferLimits device = sceneBufferLimits(testContext());
    EXPECT_GT(device.maxAllocationSize, 0u);
    EXPECT_GE(device.maxAllocationSize, testContext().physicalDevice.getProperties().limits.maxStorageBufferRange);
}

}  // namespace
}  // namespace whitted::test

namespace whitted::test {
namespace {

// The descriptor set's needs against a device's limits: lavapipe has
// enough; Vulkan's guaranteed minimums do not, and the shortfall is named.
TEST(DescriptorLimits, LavapipeHasEnoughAndTheMinimumsAreNamedShort) {
    EXPECT_EQ(descriptorLimitShortfall(testContext().physicalDevice.getProperties().limits), "");
    vk::PhysicalDeviceLimits minimum = testContext().physicalDevice.getProperties().limits;
    minimum.maxPerStageDescriptorStorageBuffers = 4;  // the spec's minimum
    EXPECT_EQ(descriptorLimitShortfall(minimum), "offers 4 storage buffers per shader stage; whitted needs 9");
    minimum = testContext().physicalDevice.getProperties().limits;
    minimum.maxPerStageDescriptorSamplers = 16;
    EXPECT_EQ(descriptorLimitShortfall(minimum), "offers 16 samplers per shader stage; whitted needs 32");
    minimum = testContext().physicalDevice.getProperties().limits;
    minimum.maxPerStageResources = 41;
    EXPECT_EQ(descriptorLimitShortfall(minimum), "offers 41 resources per shader stage; whitted needs 42");
}

}  // namespace
}  // namespace whitted::test

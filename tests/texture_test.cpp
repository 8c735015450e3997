// Image textures (scenes/README.md "Textures"): reading and decoding the files, where
// each mapping puts the image, the ray-cone filter against supersampling,
// and bad input. The POV-Ray cross-checks of the spherical map and of mesh
// UVs are in tests/povray_test.cpp (PovrayCrossCheck.Textured*).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/gtc/packing.hpp>
#include <iterator>
#include <regex>

#include "io/image_io.h"
#include "io/mesh_file.h"
#include "io/srgb.h"
#include "io/texture_file.h"
#include "scene/scene_loader.h"
#include "scene/scene_writer.h"
#include "test_support.h"

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

std::string readFileText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

fs::path textureDir() {
    fs::path dir = outputDir() / "textures";
    fs::create_directories(dir);
    return dir;
}

glm::vec4 texel(const TextureLevel& level, int x, int y) {
    const uint16_t* t = &level.rgba[(size_t(y) * level.width + x) * 4];
    return {glm::unpackHalf1x16(t[0]), glm::unpackHalf1x16(t[1]), glm::unpackHalf1x16(t[2]), glm::unpackHalf1x16(t[3])};
}

// An 8-bit file is sRGB-decoded; a float file is taken as it is; data
// (normal maps) never decoded. Each mip level is the 2x2 mean of the one
// above, down to 1x1.
TEST(TextureFile, DecodesSrgbAndBuildsTheMipChain) {
    fs::path png = textureDir() / "levels.png", exr = textureDir() / "levels.exr";
    std::vector<float> stored(8 * 2 * 3);
    for (size_t i = 0; i < stored.size(); ++i) stored[i] = float((i * 37) % 256) / 255.0f;
    writeImage(png, 8, 2, 3, stored, PixelEncoding::Linear8);  // these bytes as they are
    writeImage(exr, 8, 2, 3, stored, PixelEncoding::Float);

    TextureData colour = readTextureFile(png, TextureEncoding::Colour);
    EXPECT_TRUE(colour.srgbDecoded);
    ASSERT_EQ(colour.levels.size(), 4u);  // 8x2, 4x1, 2x1, 1x1
    EXPECT_EQ(colour.levels[1].width, 4);
    EXPECT_EQ(colour.levels[1].height, 1);
    EXPECT_EQ(colour.levels[3].width, 1);
    for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(texel(colour.levels[0], x, 1)[c], srgbToLinear(stored[(8 + x) * 3 + c]), 1e-3f);
    EXPECT_FLOAT_EQ(texel(colour.levels[0], 0, 0).a, 1.0f);
    for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 8; ++x) mean += srgbToLinear(stored[(y * 8 + x) * 3 + c]) / 16.0;
        EXPECT_NEAR(texel(colour.levels[3], 0, 0)[c], mean, 2e-3) << "the 1x1 level is the mean of the file";
    }

    TextureData data = readTextureFile(png, TextureEncoding::Data);
    EXPECT_FALSE(data.srgbDecoded);
    EXPECT_NEAR(texel(data.levels[0], 3, 1).g, stored[(8 + 3) * 3 + 1], 1e-3f);
    TextureData linear = readTextureFile(exr, TextureEncoding::Colour);
    EXPECT_FALSE(linear.srgbDecoded);
    EXPECT_NEAR(texel(linear.levels[0], 3, 1).g, stored[(8 + 3) * 3 + 1], 1e-3f);
}

// A wall facing the camera, in front of a 64x64 image: a plane facing +z
// at z = 0 whose texture the planar mapping puts once onto the square the
// camera sees (u along +x, v along +y, one repeat per <texture_scale>).
// `ambient` is the ambient light's grey, `surface` the plane's material
// and texture elements.
std::string quadrantWallXml(const std::string& ambient, const std::string& surface) {
    return R"(<scene>
  <camera><position x="0" y="0" z="2"/><window_position x="0" y="0" z="1"/><window_height>0.5</window_height>
    <width>64</width><height>64</height></camera>
  <ambient_light r=")" + ambient + R"(" g=")" + ambient + R"(" b=")" + ambient + R"("/>
  <lights/>
  <objects>
    <object><position x="-0.5" y="-0.5" z="0"/><diffuse_color r="1" g="1" b="1"/>
      <properties><type>plane</type><normal x="0" y="0" z="1"/><texture_scale>1</texture_scale>)" + surface +
           R"(</properties></object>
  </objects>
</scene>)";
}

// Each quadrant of the image of quadrantWallXml is the quadrant image's
// colour times `scale`, in its place (upright, unmirrored).
void expectQuadrants(const RenderResult& r, const glm::vec3& scale) {
    struct Expected {
        int x, y;
        glm::vec3 colour;
    };
    for (const Expected& e : {Expected{16, 16, kQuadrantTopLeft}, Expected{48, 16, kQuadrantTopRight},
                              Expected{16, 48, kQuadrantBottomLeft}, Expected{48, 48, kQuadrantBottomRight}})
        for (int c = 0; c < 3; ++c)
            // 8-bit sRGB quantisation of the file: half a level is at most
            // 0.0025 in linear terms at these values.
            EXPECT_NEAR(pixel(r, gpu::kAovColor, e.x, e.y)[c], scale[c] * e.colour[c], 0.004f)
                << "pixel " << e.x << "," << e.y << " channel " << c;
}

// Lit by ambient light only (ka = 1, white Cd), the wall shows the
// texture's own linear colours.
TEST(TextureRender, PlanarMappingPutsTheImageUpright) {
    fs::path dir = textureDir();
    writeQuadrantTexture(dir / "quadrants.png");
    const std::string xml = quadrantWallXml("1", "<diffuse_texture>quadrants.png</diffuse_texture>"
                                                 "<ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef>");
    Scene scene = loadSceneFromString(xml, dir / "quadrants_wall.xml");
    expectQuadrants(renderScene(scene, {.samplesPerPixel = 1, .maxDepth = 0, .auxiliary = false}), glm::vec3(1));
}

// <emission_texture> multiplies <emission> (glTF's emissiveFactor times
// emissiveTexture): the unlit wall (no ambient light, no lights, kd = 0)
// shows emission times each quadrant's colour; the scene writer keeps the
// element.
TEST(TextureRender, EmissionTextureMultipliesEmission) {
    fs::path dir = textureDir();
    writeQuadrantTexture(dir / "quadrants.png");
    const std::string xml = quadrantWallXml("0", R"(<emission r="0.5" g="1" b="0.75"/>)"
                                                 "<emission_texture>quadrants.png</emission_texture>"
                                                 "<ambiente_coef>0</ambiente_coef><diffuse_coef>0</diffuse_coef>"
                                                 "<specular_coef>0</specular_coef>");
    Scene scene = loadSceneFromString(xml, dir / "emission_wall.xml");
    for (const Scene& s : {scene, loadSceneFromString(sceneXml(scene), dir / "emission_wall_written.xml")}) {
        ASSERT_TRUE(s.objects[0].material.emissionTexture);
        EXPECT_EQ(s.objects[0].material.emissionTexture.written, "quadrants.png");
        expectQuadrants(renderScene(s, {.samplesPerPixel = 1, .maxDepth = 0, .auxiliary = false}),
                        glm::vec3(0.5f, 1.0f, 0.75f));
    }
}

// A texture multiplies Cd everywhere Cd is used: a white object with a
// constant texture of colour c renders exactly as the same object with
// diffuse_color c: ambient and diffuse terms, and the coloured shadow of a
// transparent textured box (shadow rays filter by the texture too), on the
// BVH path and, where the device has them, on the ray-query path. (c is
// exact in the half floats textures are stored in.)
TEST(TextureRender, ConstantTextureEqualsDiffuseColour) {
    fs::path dir = textureDir();
    const glm::vec3 c(0.75f, 0.5f, 0.25f);
    std::vector<float> texels;
    for (int i = 0; i < 16; ++i) texels.insert(texels.end(), {c.r, c.g, c.b});
    writeImage(dir / "constant.exr", 4, 4, 3, texels, PixelEncoding::Float);
    const std::string xml = R"(<scene>
  <camera><position x="0" y="2" z="4"/><window_position x="0" y="1.6" z="3"/><fov>45</fov>
    <width>64</width><height>48</height></camera>
  <ambient_light r="0.5" g="0.5" b="0.5"/>
  <lights><light><position x="0.5" y="6" z="0.5"/><color r="1" g="1" b="1"/></light></lights>
  <objects>
    <object><position x="0" y="0" z="0"/><diffuse_color r="0.9" g="0.9" b="0.9"/>
      <properties><type>plane</type><normal x="0" y="1" z="0"/><diffuse_coef>0.8</diffuse_coef></properties></object>
    <object><position x="-0.5" y="1.5" z="-0.5"/>COLOUR
      <properties><type>box</type><size x="1" y="0.2" z="1"/>TEXTURE<transmission_coef>0.7</transmission_coef>
        <refraction_coef>1</refraction_coef><diffuse_coef>0.6</diffuse_coef><ambiente_coef>0.3</ambiente_coef>
      </properties></object>
    <object><position x="1.2" y="0.5" z="0"/>COLOUR
      <properties><type>sphere</type><radius>0.5</radius>TEXTURE<diffuse_coef>0.7</diffuse_coef>
        <ambiente_coef>0.3</ambiente_coef></properties></object>
  </objects>
</scene>)";
    auto variant = [&](const std::string& colour, const std::string& texture) {
        std::string text = xml;
        for (size_t at; (at = text.find("COLOUR")) != std::string::npos;) text.replace(at, 6, colour);
        for (size_t at; (at = text.find("TEXTURE")) != std::string::npos;) text.replace(at, 7, texture);
        return loadSceneFromString(text, dir / "constant.xml");
    };
    Scene coloured = variant(R"(<diffuse_color r="0.75" g="0.5" b="0.25"/>)", "");
    Scene textured = variant("", "<diffuse_texture>constant.exr</diffuse_texture>");
    std::vector<TracePath> paths = {TracePath::Bvh};
    if (testContext().deviceInfo().rayQuery) paths.push_back(TracePath::RayQuery);
    for (TracePath path : paths) {
        RenderSettings settings{.samplesPerPixel = 1, .maxDepth = 3, .auxiliary = false, .trace = path};
        RenderResult a = renderScene(coloured, settings), b = renderScene(textured, settings);
        double worst = 0;
        for (size_t i = 0; i < a.layers[gpu::kAovColor].size(); ++i)
            worst = std::max(worst, double(std::abs(a.layers[gpu::kAovColor][i] - b.layers[gpu::kAovColor][i])));
        EXPECT_LT(worst, 1e-6) << (path == TracePath::Bvh ? "bvh" : "ray queries");
    }
}

// ---- Filtering ----------------------------------------------------------

// A floor and a ceiling with a one-texel checker (the hardest case: it
// averages to grey at mip level 1) receding to the horizon, ambient light
// only, and a mirror sphere standing on the floor that reflects both
// (curved reflection: the cone spreads). With a textured ceiling instead of
// a black sky, the mirror shows no edge of its own. The reference is 64 stratified samples per pixel at mip level 0
// (supersampling, no texture filter); the ray-cone render takes 1 sample.
const std::string kFloorXml = R"(<scene>
  <camera><position x="0" y="1" z="3"/><window_position x="0" y="0.75" z="2"/><fov>50</fov>
    <width>160</width><height>120</height></camera>
  <ambient_light r="1" g="1" b="1"/>
  <lights/>
  <objects>
    <object><position x="0" y="0" z="0"/><diffuse_color r="1" g="1" b="1"/>
      <properties><type>plane</type><normal x="0" y="1" z="0"/><diffuse_texture>checker1.png</diffuse_texture>
        <texture_scale>2</texture_scale><ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>
    <object><position x="0" y="3" z="0"/><diffuse_color r="1" g="1" b="1"/>
      <properties><type>plane</type><normal x="0" y="-1" z="0"/><diffuse_texture>checker1.png</diffuse_texture>
        <texture_scale>2</texture_scale><ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>
    <object><position x="0.4" y="0.5" z="0"/><diffuse_color r="0" g="0" b="0"/><specular_color r="1" g="1" b="1"/>
      <properties><type>sphere</type><radius>0.5</radius><reflection_coef>1</reflection_coef>
        <ambiente_coef>0</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>
  </objects>
</scene>)";

// PSNR (dB) of the sRGB-encoded colours, over the pixels that see only the
// floor and over those that see only the mirror in the reference (its
// means of kr and of the hit mask are exactly 0 and 1, or 1 and 1): the
// silhouettes, which 1 sample per pixel aliases whatever the texture
// filter, are left out.
struct Psnr {
    double floor, mirror;
};
Psnr psnr(const RenderResult& a, const RenderResult& reference) {
    double squared[2] = {0, 0};
    int count[2] = {0, 0};
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            glm::vec4 coefs = pixel(reference, gpu::kAovCoefs1, x, y);
            float kr = coefs.x, hit = coefs.w;  // means over the pixel's samples
            if (hit != 1.0f || (kr != 0.0f && kr != 1.0f)) continue;
            int mirror = kr == 1.0f ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                double d = linearToSrgb(pixel(a, gpu::kAovColor, x, y)[c]) -
                           linearToSrgb(pixel(reference, gpu::kAovColor, x, y)[c]);
                squared[mirror] += d * d;
                ++count[mirror];
            }
        }
    return {10 * std::log10(count[0] / squared[0]), 10 * std::log10(count[1] / squared[1])};
}

TEST(TextureRender, RayConesFilterLikeSupersampling) {
    fs::path dir = textureDir();
    writeTestTexture(dir / "checker1.png", 64, 64, [](float u, float v) {
        bool odd = (int(u * 64) + int(v * 64)) % 2 == 1;
        return odd ? glm::vec3(0.9f) : glm::vec3(0.05f);
    });
    Scene scene = loadSceneFromString(kFloorXml, dir / "checker_floor.xml");
    RenderSettings reference{.samplesPerPixel = 64, .maxDepth = 2, .auxiliary = true, .textureLodZero = true};
    RenderSettings cones{.samplesPerPixel = 1, .maxDepth = 2, .auxiliary = true};
    RenderSettings unfiltered = cones;
    unfiltered.textureLodZero = true;
    RenderResult want = renderScene(scene, reference);
    RenderResult got = renderScene(scene, cones);
    RenderResult aliased = renderScene(scene, unfiltered);
    Psnr filtered = psnr(got, want), plain = psnr(aliased, want);
    std::printf(
        "[ texture  ] 1 spp against 64 spp at level 0: ray cones %.2f dB floor, %.2f dB in the mirror; "
        "level 0 %.2f dB floor, %.2f dB in the mirror\n",
        filtered.floor, filtered.mirror, plain.floor, plain.mirror);
    if (std::getenv("WHITTED_TEXTURE_KEEP")) {
        for (auto [name, r] :
             {std::pair{"reference", &want}, std::pair{"cones", &got}, std::pair{"level0", &aliased}}) {
            std::vector<float> rgb;
            for (int y = 0; y < r->height; ++y)
                for (int x = 0; x < r->width; ++x)
                    for (int c = 0; c < 3; ++c) rgb.push_back(pixel(*r, gpu::kAovColor, x, y)[c]);
            writeImage(dir / (std::string("floor.") + name + ".png"), r->width, r->height, 3, rgb,
                       PixelEncoding::Srgb8);
        }
    }
    // Measured (lavapipe, Mesa 25.0.7): ray cones 33.3 dB on the floor and
    // ceiling, 35.6 dB in the mirror; level 0 21.2 and 19.9 dB. Rendering is
    // deterministic; the bounds sit about 1 dB below the measurement.
    EXPECT_GE(filtered.floor, 32.0);
    EXPECT_GE(filtered.mirror, 34.0);
    EXPECT_GE(filtered.floor, plain.floor + 10.0);
    EXPECT_GE(filtered.mirror, plain.mirror + 12.0);
}

// The window's Save (scene/scene_writer.h) keeps the texture elements: the
// path as written, the plane's texture scale and each polygon's <uv>.
TEST(TextureLoader, SceneWriterKeepsTextures) {
    fs::path dir = textureDir();
    writeQuadrantTexture(dir / "quadrants.png");
    const std::string xml = R"(<scene>
  <camera><position x="0" y="1" z="5"/><window_position x="0" y="1" z="4"/></camera>
  <lights/>
  <objects>
    <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="0" y="1" z="0"/>
      <diffuse_texture>quadrants.png</diffuse_texture><texture_scale>0.25</texture_scale></properties></object>
    <object><properties><type>mesh</type><diffuse_texture>quadrants.png</diffuse_texture><polygons>
      <polygon><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/>
        <uv u="0.125" v="0"/><uv u="1" v="0.5"/><uv u="0" v="1.75"/></polygon>
    </polygons></properties></object>
  </objects>
</scene>)";
    Scene a = loadSceneFromString(xml, dir / "writer_a.xml");
    Scene b = loadSceneFromString(sceneXml(a), dir / "writer_b.xml");
    ASSERT_EQ(b.objects.size(), 2u);
    EXPECT_EQ(b.objects[0].material.diffuseTexture.written, "quadrants.png");
    EXPECT_EQ(b.objects[0].material.textureScale, 0.25);
    EXPECT_EQ(b.objects[1].material.diffuseTexture.written, "quadrants.png");
    const Mesh& mesh = std::get<Mesh>(b.objects[1].shape);
    ASSERT_EQ(mesh.uvs.size(), 1u);
    EXPECT_EQ(mesh.uvs[0][0], glm::dvec2(0.125, 0));
    EXPECT_EQ(mesh.uvs[0][1], glm::dvec2(1, 0.5));
    EXPECT_EQ(mesh.uvs[0][2], glm::dvec2(0, 1.75));
}

// ---- Normal maps ----------------------------------------------------------

// A constant normal map of normal m (tangent space), as a float EXR: the
// texel (m + 1) / 2 exactly, no 8-bit rounding.
void writeConstantNormalMap(const fs::path& path, const glm::dvec3& m) {
    std::vector<float> texels;
    for (int i = 0; i < 16; ++i)
        for (int c = 0; c < 3; ++c) texels.push_back(float((m[c] + 1.0) / 2.0));
    writeImage(path, 4, 4, 3, texels, PixelEncoding::Float);
}

// A flat map (0.5, 0.5, 1: the unperturbed normal) leaves every pixel as it
// was without a map, on the mappings of a sphere, a plane, a box and a mesh
// with UVs, in colour and in the normal layer.
TEST(NormalMap, FlatMapChangesNothing) {
    fs::path dir = textureDir();
    writeConstantNormalMap(dir / "flat_normals.exr", {0, 0, 1});
    std::string xml = R"(<scene>
  <camera><position x="0" y="1.5" z="5"/><window_position x="0" y="1.2" z="4"/><fov>45</fov>
    <width>64</width><height>48</height></camera>
  <ambient_light r="0.3" g="0.3" b="0.3"/>
  <lights><light><position x="3" y="6" z="5"/><color r="1" g="1" b="1"/></light></lights>
  <objects>
    <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="0" y="1" z="0"/>MAP
      <ambiente_coef>0.2</ambiente_coef><diffuse_coef>0.6</diffuse_coef><specular_coef>0.3</specular_coef></properties></object>
    <object><position x="-1" y="1" z="0"/><properties><type>sphere</type><radius>0.8</radius>MAP
      <diffuse_coef>0.6</diffuse_coef><specular_coef>0.5</specular_coef><reflection_coef>0.3</reflection_coef></properties></object>
    <object><position x="0.6" y="0" z="-0.5"/><properties><type>box</type><size x="0.8" y="0.8" z="0.8"/>MAP
      <diffuse_coef>0.7</diffuse_coef><specular_coef>0.3</specular_coef></properties></object>
    <object><position x="1.2" y="0" z="0.5"/><properties><type>mesh</type>MAP
      <diffuse_coef>0.7</diffuse_coef><specular_coef>0.3</specular_coef><polygons>
      <polygon><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0.3"/><vertex x="0" y="1" z="0"/>
        <uv u="0" v="0"/><uv u="1" v="0"/><uv u="0" v="1"/></polygon>
    </polygons></properties></object>
  </objects>
</scene>)";
    auto withMap = [&](const std::string& map) {
        std::string text = xml;
        for (size_t at = text.find("MAP"); at != std::string::npos; at = text.find("MAP")) text.replace(at, 3, map);
        return text;
    };
    RenderSettings settings{.samplesPerPixel = 1, .maxDepth = 2, .auxiliary = true};
    RenderResult plain = renderScene(loadSceneFromString(withMap(""), dir / "flat_a.xml"), settings);
    RenderResult mapped = renderScene(
        loadSceneFromString(withMap("<normal_map>flat_normals.exr</normal_map>"), dir / "flat_b.xml"), settings);
    double worst = 0;
    for (uint32_t layer : {gpu::kAovColor, gpu::kAovNormal})
        for (size_t i = 0; i < plain.layers[layer].size(); ++i)
            worst = std::max(worst, double(std::abs(plain.layers[layer][i] - mapped.layers[layer][i])));
    // The mapped normal is ns renormalised (at most an ulp or two off per
    // component), which Phong's power of 32 and the reflected rays carry
    // into the colour: measured 1.3e-5 at most; a one-degree tilt is ~1e-2.
    EXPECT_LT(worst, 5e-5) << "largest difference in colour or normal";
}

// A constant tilted map on a wall facing the camera: the centre pixel sees
// the point (0, 0, 0) and must show Phong shading (scenes/README.md "Shading model")
// computed here with the tilted normal: tilted towards +u = +x (red) or
// towards +v = +y (green up), at full and at half strength (x and y of the
// map scaled by 0.5).
TEST(NormalMap, ConstantTiltEqualsAnalyticPhong) {
    fs::path dir = textureDir();
    const double tilt = glm::radians(25.0);
    struct Case {
        const char* name;
        glm::dvec3 map;  // tangent space
        double strength;
    };
    for (const Case& c :
         {Case{"x", {std::sin(tilt), 0, std::cos(tilt)}, 1.0}, Case{"y", {0, std::sin(tilt), std::cos(tilt)}, 1.0},
          Case{"x_half", {std::sin(tilt), 0, std::cos(tilt)}, 0.5}}) {
        SCOPED_TRACE(c.name);
        std::string file = std::string("tilt_") + c.name + ".exr";
        writeConstantNormalMap(dir / file, c.map);
        std::string xml = R"(<scene>
  <camera><position x="0" y="0" z="3"/><window_position x="0" y="0" z="2"/><fov>20</fov><width>33</width><height>33</height></camera>
  <ambient_light r="1" g="1" b="1"/>
  <lights><light><position x="2" y="1.5" z="4"/><color r="1" g="1" b="1"/></light></lights>
  <objects>
    <object><position x="0" y="0" z="0"/><properties><type>plane</type><normal x="0" y="0" z="1"/>
      <normal_map>)" + file +
                          R"(</normal_map><normal_strength>)" + std::to_string(c.strength) + R"(</normal_strength>
      <ambiente_coef>0.1</ambiente_coef><diffuse_coef>0.6</diffuse_coef><specular_coef>0.3</specular_coef>
      <shininess>5</shininess></properties></object>
  </objects>
</scene>)";
        RenderResult r = renderScene(loadSceneFromString(xml, dir / (std::string("tilt_") + c.name + ".xml")),
                                     {.samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true});
        // The tilted normal in world space: the wall's u is +x, v is +y.
        glm::dvec3 n = glm::normalize(glm::dvec3(c.strength * c.map.x, c.strength * c.map.y, c.map.z));
        glm::dvec3 l = glm::normalize(glm::dvec3(2, 1.5, 4)), v(0, 0, 1);
        glm::dvec3 reflected = 2.0 * glm::dot(n, l) * n - l;
        double expected =
            0.1 + 0.6 * std::max(glm::dot(n, l), 0.0) + 0.3 * std::pow(std::max(glm::dot(reflected, v), 0.0), 5.0);
        glm::vec4 got = pixel(r, gpu::kAovColor, 16, 16);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expected, 2e-3);
        glm::vec4 normal = pixel(r, gpu::kAovNormal, 16, 16);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(normal[k], n[k], 1e-3);
        // Against the untilted wall, so the tilt is seen to matter.
        double flat = 0.1 + 0.6 * l.z + 0.3 * std::pow(std::max(2.0 * l.z * l.z - 1.0, 0.0), 5.0);
        EXPECT_GT(std::abs(expected - flat), 0.02);
    }
}

// A model file's vertex tangents (Assimp's aiProcess_CalcTangentSpace):
// an OBJ square facing +z with normals and UVs (u along +x, v along +y),
// rotated 90 degrees about z by <rotation> (so u runs along +y and v along
// -x in the world), under a constant map tilted towards +u: the centre pixel
// shows the analytic Phong shading with the normal tilted towards world +y.
// On a flat square the vertex tangents and dp/du agree, so this checks that
// the tangents are read, placed with the mesh and give the right frame, not
// that they differ from dp/du where a surface curves.
TEST(NormalMap, ModelFileTangentsCarryTheTilt) {
    fs::path dir = textureDir();
    std::ofstream(dir / "square.obj") << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                                         "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
    MeshFileData data = readMeshFile(dir / "square.obj", MeshFileMaterials::Ignore, true);
    ASSERT_EQ(data.tangents.size(), 2u);
    for (const auto& t : data.tangents)
        for (const glm::dvec3& v : t) EXPECT_NEAR(glm::distance(v, glm::dvec3(1, 0, 0)), 0.0, 1e-6);

    const double tilt = glm::radians(25.0);
    writeConstantNormalMap(dir / "tilt_u.exr", {std::sin(tilt), 0, std::cos(tilt)});
    const std::string xml = R"(<scene>
  <camera><position x="0" y="0" z="3"/><window_position x="0" y="0" z="2"/><fov>20</fov>
    <width>33</width><height>33</height></camera>
  <ambient_light r="1" g="1" b="1"/>
  <lights><light><position x="2" y="1.5" z="4"/><color r="1" g="1" b="1"/></light></lights>
  <objects>
    <object><diffuse_color r="1" g="1" b="1"/><properties><type>mesh</type><file>square.obj</file>
      <rotation x="0" y="0" z="90"/><normal_map>tilt_u.exr</normal_map>
      <ambiente_coef>0.1</ambiente_coef><diffuse_coef>0.6</diffuse_coef><specular_coef>0.3</specular_coef>
      <shininess>5</shininess></properties></object>
  </objects>
</scene>)";
    Scene scene = loadSceneFromString(xml, dir / "square.xml");
    ASSERT_EQ(std::get<Mesh>(scene.objects[0].shape).tangents.size(), 2u);
    RenderResult r = renderScene(scene, {.samplesPerPixel = 1, .maxDepth = 0, .auxiliary = true});
    glm::dvec3 n(0, std::sin(tilt), std::cos(tilt));  // +u is world +y after the rotation
    glm::dvec3 l = glm::normalize(glm::dvec3(2, 1.5, 4)), v(0, 0, 1);
    glm::dvec3 reflected = 2.0 * glm::dot(n, l) * n - l;
    double expected =
        0.1 + 0.6 * std::max(glm::dot(n, l), 0.0) + 0.3 * std::pow(std::max(glm::dot(reflected, v), 0.0), 5.0);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(pixel(r, gpu::kAovColor, 16, 16)[k], expected, 2e-3);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(pixel(r, gpu::kAovNormal, 16, 16)[k], n[k], 1e-3);
}

// ---- Materials from model files ------------------------------------------

// Khronos' BoxTextured sample in Debian's assimp-testmodels package (see
// tools/install_deps.sh --all): a cube whose glTF material has a base-colour
// texture (the Cesium logo: white, blue and green) embedded in the GLB.
const fs::path kBoxTextured = assimpTestModel("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");

std::string boxXml(const std::string& colour) {
    return R"(<scene>
  <camera><position x="1.6" y="1.3" z="2.2"/><window_position x="1.1" y="0.9" z="1.5"/><fov>40</fov>
    <width>96</width><height>72</height></camera>
  <ambient_light r="1" g="1" b="1"/>
  <lights/>
  <objects>
    <object>)" +
           colour + R"(<properties><type>mesh</type><file>)" + kBoxTextured.string() + R"(</file>
      <ambiente_coef>1</ambiente_coef><diffuse_coef>0</diffuse_coef></properties></object>
  </objects>
</scene>)";
}

TEST(ModelMaterials, GlbBaseColourTextureIsUsedWhenTheSceneSetsNoColour) {
    ASSERT_TRUE(fs::exists(kBoxTextured))
        << kBoxTextured << " is missing: install assimp-testmodels (tools/install_deps.sh --all)";
    MeshFileData data = readMeshFile(kBoxTextured, MeshFileMaterials::Read);
    ASSERT_EQ(data.triangleMaterials.size(), data.triangles.size());
    ASSERT_LT(data.triangleMaterials[0], data.materials.size());
    const MeshFileMaterial& material = data.materials[data.triangleMaterials[0]];
    ASSERT_TRUE(material.baseColourTexture) << "the embedded texture *0";
    EXPECT_EQ(material.baseColourTexture->levels[0].width, 211);  // CesiumLogoFlat.png, 211x211
    EXPECT_EQ(data.uvs.size(), data.triangles.size());

    // Ambient light only, ka = 1: every pixel of the box shows base colour
    // times texture. The logo's three colours must all appear.
    RenderResult textured = renderScene(loadSceneFromString(boxXml(""), "box.xml"),
                                        {.samplesPerPixel = 4, .maxDepth = 0, .auxiliary = true});
    int box = 0, blue = 0, green = 0, white = 0;
    for (int y = 0; y < textured.height; ++y)
        for (int x = 0; x < textured.width; ++x) {
            if (pixel(textured, gpu::kAovCoefs1, x, y).w < 1.0f) continue;
            glm::vec4 c = pixel(textured, gpu::kAovColor, x, y);
            ++box;
            blue += c.b > c.r + 0.2f && c.b > c.g;
            green += c.g > c.r + 0.1f && c.g > c.b + 0.1f;
            white += c.r > 0.7f && c.g > 0.7f && c.b > 0.7f;
        }
    std::printf("[ texture  ] BoxTextured.glb: %d box pixels, %d blue, %d green, %d white\n", box, blue, green, white);
    EXPECT_GT(box, 96 * 72 / 5);
    EXPECT_GT(blue, box / 20);
    EXPECT_GT(green, box / 20);
    EXPECT_GT(white, box / 20);

    // A colour of the scene's own wins: then the box is flat white.
    RenderResult flat = renderScene(loadSceneFromString(boxXml(R"(<diffuse_color r="1" g="1" b="1"/>)"), "box.xml"),
                                    {.samplesPerPixel = 4, .maxDepth = 0, .auxiliary = true});
    for (int y = 0; y < flat.height; ++y) {
        for (int x = 0; x < flat.width; ++x) {
            if (pixel(flat, gpu::kAovCoefs1, x, y).w != 1.0f) continue;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(pixel(flat, gpu::kAovColor, x, y)[c], 1.0f, 1e-6f) << x << "," << y;
        }
    }
}

// ---- The window ------------------------------------------------------------

// `whitted view` under its own virtual X server (as tests/view_test.cpp):
// a texture file replaced while the window is open reloads the scene with
// it, and the panel's texture-scale edit (the script's `edit`) renders and
// saves as `render` renders the saved file.
TEST(ViewTexture, TextureFileHotReloadsAndScaleEdits) {
    fs::path dir = outputDir() / "view_texture";
    fs::remove_all(dir);
    fs::create_directories(dir);
    writeQuadrantTexture(dir / "tex.png");
    writeSmoothTexture(dir / "other.png");
    std::ofstream(dir / "scene.xml") << R"(<scene>
  <camera><position x="0" y="0.5" z="3"/><window_position x="0" y="0.4" z="2"/><fov>50</fov></camera>
  <ambient_light r="1" g="1" b="1"/>
  <lights><light><position x="2" y="3" z="4"/><color r="0.6" g="0.6" b="0.6"/></light></lights>
  <objects>
    <object><position x="0" y="-0.5" z="0"/><properties><type>plane</type><normal x="0" y="1" z="0"/>
      <diffuse_texture>tex.png</diffuse_texture><texture_scale>1</texture_scale>
      <ambiente_coef>0.4</ambiente_coef><diffuse_coef>0.6</diffuse_coef></properties></object>
    <object><position x="0" y="0.3" z="0"/><properties><type>sphere</type><radius>0.7</radius>
      <diffuse_texture>tex.png</diffuse_texture><ambiente_coef>0.4</ambiente_coef><diffuse_coef>0.6</diffuse_coef>
      </properties></object>
  </objects>
</scene>)";
    std::ofstream(dir / "script.txt")
        << "spp 4\nscreenshot before.png\ncopy other.png tex.png\nreload\nspp 4\n"
           "screenshot after.png\nedit 0 texture_scale 0.5\nspp 4\nscreenshot scaled.png\n"
           "save_scene\nquit\n";
    const std::string small = " --width 160 --height 120 --spp 4";
    CommandRun view = runCommand("xvfb-run -a -s '-screen 0 1024x768x24' '" WHITTED_EXECUTABLE "' view scene.xml" +
                                     small + " --script script.txt",
                                 dir);
    ASSERT_EQ(view.status, 0) << view.output;
    EXPECT_NE(view.output.find("texture file changed"), std::string::npos) << view.output;
    EXPECT_NE(view.output.find("reloaded scene.xml"), std::string::npos) << view.output;
    Scene saved = loadScene(dir / "scene.xml");
    EXPECT_EQ(saved.objects[0].material.textureScale, 0.5);

    // tex.png now holds the other texture, scene.xml the scale 0.5.
    auto render = [&](const std::string& scene, const std::string& out) {
        CommandRun r = runCommand(
            "'" WHITTED_EXECUTABLE "' render -q --aa uniform " + scene + small + " --aov none -o " + out, dir);
        ASSERT_EQ(r.status, 0) << r.output;
    };
    render("scene.xml", "saved.png");
    std::string scale1 = readFileText(dir / "scene.xml");
    auto read = [&](const std::string& name) {
        std::vector<float> pixels;
        int w = 0, h = 0, c = 0;
        readImageInto(dir / name, w, h, c, pixels);
        return pixels;
    };
    auto maxLevels = [](const std::vector<float>& a, const std::vector<float>& b) {
        if (a.size() != b.size()) return 255.0;
        double worst = 0;
        for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(double(a[i]) - double(b[i])) * 255.0);
        return worst;
    };
    std::vector<float> before = read("before.png"), after = read("after.png"), scaled = read("scaled.png");
    EXPECT_LE(maxLevels(scaled, read("saved.png")), 1.0);
    EXPECT_GT(maxLevels(after, before), 50.0) << "the new texture file did not show";
    EXPECT_GT(maxLevels(scaled, after), 50.0) << "the scale edit changed nothing";
    // The reloaded image is the scale-1 scene with the new texture.
    std::ofstream(dir / "scale1.xml") << std::regex_replace(scale1, std::regex("<texture_scale>0.5</texture_scale>"),
                                                            "<texture_scale>1</texture_scale>");
    render("scale1.xml", "reloaded.png");
    EXPECT_LE(maxLevels(after, read("reloaded.png")), 1.0);
}

// Khronos' ClearCoatTest (assimp-testmodels) has normal textures: with no
// colour of the scene's own, the parts of the model whose material has one
// get it as their normal map, read as linear data (not sRGB-decoded).
TEST(ModelMaterials, GltfNormalTextureBecomesTheNormalMap) {
    const fs::path model = assimpTestModel("glTF2/ClearCoat-glTF/ClearCoatTest.gltf");
    ASSERT_TRUE(fs::exists(model)) << model << " is missing: install assimp-testmodels (tools/install_deps.sh --all)";
    MeshFileData data = readMeshFile(model, MeshFileMaterials::Read);
    int withNormals = 0;
    for (const MeshFileMaterial& m : data.materials)
        if (m.normalTexture) {
            ++withNormals;
            EXPECT_FALSE(m.normalTexture->srgbDecoded);
        }
    EXPECT_GT(withNormals, 0);
    Scene scene = loadSceneFromString(R"(<scene>
  <camera><position x="0" y="0" z="10"/><window_position x="0" y="0" z="9"/></camera>
  <lights/>
  <objects><object><properties><type>mesh</type><file>)" + model.string() +
                                          R"(</file></properties></object></objects>
</scene>)",
                                      "clearcoat.xml");
    int mapped = 0;
    for (const Object& o : scene.objects) mapped += o.material.normalMap ? 1 : 0;
    EXPECT_GT(mapped, 0);
    EXPECT_GT(scene.objects.size(), 1u) << "one object per material of the file";
    // Rendered under validation, normal maps and all.
    RenderResult r = renderScene(scene, {.width = 32, .height = 24, .samplesPerPixel = 1, .maxDepth = 1});
    EXPECT_EQ(r.width, 32);
}

// ---- Bad input ------------------------------------------------------------
// (Missing files, directories, <texture_scale> off a plane, meshes without
// UVs and miscounted <uv> are in the tests/bad_scenes/ catalogue, run
// through the executable.)

std::string loadError(const std::string& xml, const fs::path& name) {
    try {
        loadSceneFromString(xml, name);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "(loaded)";
}

const std::string kSphereWithTexture = R"(<scene>
  <camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/></camera>
  <lights/>
  <objects>
    <object><position x="0" y="0" z="0"/>
      <properties><type>sphere</type><radius>1</radius>
        <diffuse_texture>TEXTURE</diffuse_texture></properties></object>
  </objects>
</scene>)";

// The bytes of a PNG that claims `width` x `height` and holds one IDAT of
// garbage: enough for a reader to open it and read its size.
std::string pngClaiming(uint32_t width, uint32_t height) {
    auto crc32 = [](const std::string& bytes) {  // ISO 3309, as PNG's chunks use
        uint32_t crc = 0xFFFFFFFFu;
        for (unsigned char b : bytes) {
            crc ^= b;
            for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
        }
        return ~crc;
    };
    auto be32 = [](uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    auto chunk = [&](const std::string& type, const std::string& data) {
        return be32(uint32_t(data.size())) + type + data + be32(crc32(type + data));
    };
    std::string ihdr = be32(width) + be32(height) + std::string{8, 2, 0, 0, 0};  // 8-bit RGB
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", std::string(16, 'x')) +
           chunk("IEND", "");
}

// A file that claims more texels than a texture may hold is refused by its
// size before its pixels are allocated (before, these hundred bytes had the
// reader allocate 3 GiB of floats for 16000x16000 RGB); a float texel
// beyond the half-float range, which would be infinite on the device, is
// refused by value.
TEST(TextureFile, RefusesHugeClaimsAndTexelsBeyondHalfRange) {
    fs::path huge = textureDir() / "huge_claim.png";
    std::ofstream(huge, std::ios::binary) << pngClaiming(16000, 16000);
    try {
        readTextureFile(huge, TextureEncoding::Colour);
        ADD_FAILURE() << "a 16000x16000 claim was read";
    } catch (const TextureFileError& e) {
        EXPECT_STREQ(e.what(), "is 16000x16000; a texture holds at most 67108864 texels (8192x8192)");
    }
    const std::string bytes = pngClaiming(9000, 9000);
    try {
        readTextureMemory(std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()), "png",
                          TextureEncoding::Colour, "embedded");
        ADD_FAILURE() << "a 9000x9000 claim was read";
    } catch (const TextureFileError& e) {
        EXPECT_STREQ(e.what(), "is 9000x9000; a texture holds at most 67108864 texels (8192x8192)");
    }

    fs::path bright = textureDir() / "beyond_half.exr";
    writeImage(bright, 2, 1, 3, std::vector<float>{1, 1, 1, 1, 70000, 1}, PixelEncoding::Float);
    try {
        readTextureFile(bright, TextureEncoding::Colour);
        ADD_FAILURE() << "a texel of 70000 was read";
    } catch (const TextureFileError& e) {
        EXPECT_STREQ(e.what(), "has a texel beyond the half-float range (|value| > 65504)");
    }
    // An EXR whose channel list claims 2 GB: refused before
    // OpenEXR allocates it (texture_fuzzer's out-of-memory finding).
    fs::path claim = textureDir() / "attribute_claim.exr";
    writeImage(claim, 2, 1, 3, std::vector<float>{1, 1, 1, 1, 1, 1}, PixelEncoding::Float);
    std::string exr = readFileText(claim);
    const size_t channels = exr.find(std::string("channels\0chlist\0", 16));
    ASSERT_NE(channels, std::string::npos);
    exr.replace(channels + 16, 4, std::string("\xff\xff\xff\x7f", 4));
    std::ofstream(claim, std::ios::binary | std::ios::trunc) << exr;
    try {
        readTextureFile(claim, TextureEncoding::Colour);
        ADD_FAILURE() << "an attribute of 2 GB was read";
    } catch (const TextureFileError& e) {
        EXPECT_STREQ(e.what(), "could not be read: its EXR header attribute \"channels\" claims 2147483647 bytes, "
                               "more than the file has");
    }
    fs::path edge = textureDir() / "half_max.exr";
    writeImage(edge, 2, 1, 3, std::vector<float>{1, 1, 1, 1, 65504, 1}, PixelEncoding::Float);
    EXPECT_FLOAT_EQ(texel(readTextureFile(edge, TextureEncoding::Colour).levels[0], 1, 0).g, 65504.0f);
}

// A file that is not an image: the loader's place and OpenImageIO's reason.
TEST(TextureLoader, RefusesAFileThatIsNotAnImage) {
    fs::path dir = textureDir();
    std::ofstream(dir / "garbage.png") << "not a PNG file\n";
    std::string xml = kSphereWithTexture;
    xml.replace(xml.find("TEXTURE"), 7, "garbage.png");
    std::string error = loadError(xml, dir / "garbage.xml");
    std::string expected = (dir / "garbage.xml").string() + ":7: texture file \"garbage.png\" could not be read: ";
    EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
    EXPECT_GT(error.size(), expected.size()) << "OpenImageIO's reason follows";
}

// <uv> on every polygon of a mesh or on none; a texture on type triangle
// (which has no texture coordinates) does not apply.
TEST(TextureLoader, RefusesMixedUvsAndTexturedTriangles) {
    fs::path dir = textureDir();
    writeQuadrantTexture(dir / "quadrants.png");
    std::string mixed = R"(<scene>
  <camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/></camera>
  <lights/>
  <objects>
    <object><properties><type>mesh</type><polygons>
      <polygon><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/>
        <uv u="0" v="0"/><uv u="1" v="0"/><uv u="0" v="1"/></polygon>
      <polygon><vertex x="1" y="0" z="0"/><vertex x="1" y="1" z="0"/><vertex x="0" y="1" z="0"/></polygon>
    </polygons></properties></object>
  </objects>
</scene>)";
    EXPECT_EQ(loadError(mixed, "mixed.xml"), "mixed.xml:8: <polygon> has no <uv>, but the first <polygon> has");
    std::string triangle = R"(<scene>
  <camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/></camera>
  <lights/>
  <objects>
    <object><properties><type>triangle</type>
      <vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/>
      <diffuse_texture>quadrants.png</diffuse_texture></properties></object>
  </objects>
</scene>)";
    EXPECT_EQ(loadError(triangle, dir / "triangle.xml"),
              (dir / "triangle.xml").string() + ":7: <diffuse_texture> does not apply to type triangle");
}

}  // namespace
}  // namespace whitted::test

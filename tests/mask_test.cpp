// The object and material masks (--aov object_id,material_id): the ids of
// what the pixel-centre ray hits, never blended by anti-aliasing, the same
// whatever the sampling, trace path, banding or region, written to EXR as
// UINT channels, and named by the render record's legend.
#include "test_support.h"

#include "display_types.h"
#include "io/image_io.h"
#include "output/aov_output.h"
#include "output/render_record.h"
#include "scene/scene_loader.h"

#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

namespace whitted::test {
namespace {

namespace fs = std::filesystem;

// The id channel (0 object, 1 material) of a render with the id layer.
std::vector<uint32_t> ids(const RenderResult& r, int channel) {
    EXPECT_TRUE(r.layout.ids);
    const std::vector<float>& layer = r.layers[r.layout.idLayer()];
    std::vector<uint32_t> out(size_t(r.width) * r.height);
    for (size_t i = 0; i < out.size(); ++i) out[i] = std::bit_cast<uint32_t>(layer[i * 4 + size_t(channel)]);
    return out;
}

RenderSettings withIds(int width, int height, AntiAliasing aa, int spp) {
    RenderSettings s{.width = width, .height = height, .samplesPerPixel = spp, .auxiliary = true, .ids = true};
    s.antiAliasing = aa;
    return s;
}

Scene showcase() { return loadScene(sourceDir() / "scenes" / "showcase.xml"); }

// 4-connected regions of each id.
std::map<uint32_t, int> regionsPerId(const std::vector<uint32_t>& id, int width, int height) {
    std::vector<int> seen(id.size(), 0);
    std::map<uint32_t, int> regions;
    for (size_t start = 0; start < id.size(); ++start) {
        if (seen[start]) continue;
        ++regions[id[start]];
        std::vector<size_t> stack{start};
        seen[start] = 1;
        while (!stack.empty()) {
            size_t i = stack.back();
            stack.pop_back();
            int x = int(i % size_t(width)), y = int(i / size_t(width));
            const int dx[] = {1, -1, 0, 0}, dy[] = {0, 0, 1, -1};
            for (int k = 0; k < 4; ++k) {
                int nx = x + dx[k], ny = y + dy[k];
                if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                size_t j = size_t(ny) * width + nx;
                if (!seen[j] && id[j] == id[i]) seen[j] = 1, stack.push_back(j);
            }
        }
    }
    return regions;
}

// Each bounded object of the showcase is one region of its id; every id is an
// object's index or the background; the ids hit exactly where the hit mask
// of a one-sample render (its sample is the pixel-centre ray) says so.
TEST(Masks, EachObjectOfAShippedSceneIsOneIdRegion) {
    Scene scene = showcase();
    RenderResult r = renderScene(scene, withIds(160, 90, AntiAliasing::Uniform, 1));
    std::vector<uint32_t> object = ids(r, 0);
    std::map<uint32_t, int> regions = regionsPerId(object, r.width, r.height);
    EXPECT_EQ(regions.size(), scene.objects.size()) << "every object is seen";
    for (auto [id, count] : regions) {
        ASSERT_LT(id, scene.objects.size()) << "the showcase's background is covered by its wall and floor";
        // The floor is cut into pockets by the objects standing on it.
        if (!std::holds_alternative<Plane>(scene.objects[id].shape)) {
            EXPECT_EQ(count, 1) << "object " << id << " (line " << scene.objects[id].sourceLine << ")";
        }
    }
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            EXPECT_EQ(pixel(r, gpu::kAovCoefs1, x, y).w > 0, object[size_t(y) * r.width + x] != gpu::kNoObject);
    // Testing every primitive for every ray (the seed's way) finds the same objects.
    RenderSettings noBvh = withIds(160, 90, AntiAliasing::Uniform, 1);
    noBvh.useBvh = false;
    RenderResult reference = renderScene(scene, noBvh);
    EXPECT_EQ(ids(reference, 0), object);
    EXPECT_EQ(ids(reference, 1), ids(r, 1));
}

// Anti-aliased edges never blend ids: with 16 samples a pixel, adaptive or
// uniform, the ids are those of the centre ray alone (the one-sample
// render's), though the colours along the edges are blends.
TEST(Masks, AntiAliasingNeverBlendsIds) {
    Scene scene = showcase();
    RenderResult centre = renderScene(scene, withIds(160, 90, AntiAliasing::Uniform, 1));
    for (AntiAliasing aa : {AntiAliasing::Adaptive, AntiAliasing::Uniform}) {
        RenderResult r = renderScene(scene, withIds(160, 90, aa, 16));
        EXPECT_EQ(ids(r, 0), ids(centre, 0));
        EXPECT_EQ(ids(r, 1), ids(centre, 1));
        EXPECT_NE(r.layers[gpu::kAovColor], centre.layers[gpu::kAovColor]) << "the colours are anti-aliased";
    }
}

// The material id tells a csg child's own material from its object's: the
// drill of a block (a difference whose sphere has its own colour) is
// material 1 (the first after the one object's), object 0.
TEST(Masks, CsgChildWithItsOwnMaterialHasItsOwnMaterialId) {
    std::string xml =
        R"(<scene><camera><position x="0" y="0" z="0"/><window_position x="0" y="0" z="-1"/>)"
        R"(<width>32</width><height>24</height></camera><lights/><objects>)"
        R"(<object><position x="0" y="0" z="-5"/><properties><type>csg</type><operation>difference</operation>)"
        R"(</properties><objects><object><position x="-2" y="-2" z="-1"/><properties><type>box</type>)"
        R"(<size x="4" y="4" z="2"/></properties></object><object><position x="0" y="0" z="1"/>)"
        R"(<diffuse_color r="1" g="0" b="0"/><properties><type>sphere</type><radius>0.5</radius></properties>)"
        R"(</object></objects></object></objects></scene>)";
    RenderResult r = renderXml(xml, withIds(32, 24, AntiAliasing::Adaptive, 16));
    std::vector<uint32_t> object = ids(r, 0), material = ids(r, 1);
    size_t centre = size_t(12) * 32 + 16, edge = size_t(12) * 32 + 24, corner = 0;
    EXPECT_EQ(object[centre], 0u);
    EXPECT_EQ(material[centre], 1u);  // inside the drill: the sphere's surface
    EXPECT_EQ(object[edge], 0u);
    EXPECT_EQ(material[edge], 0u);    // the block's face
    EXPECT_EQ(object[corner], gpu::kNoObject);
    EXPECT_EQ(material[corner], gpu::kNoObject);
}

// Bands of a few rows and a region give the full render's ids, adaptive
// refinement included.
TEST(Masks, IdsAgreeAcrossBandsAndRegions) {
    Scene scene = showcase();
    RenderSettings s = withIds(160, 90, AntiAliasing::Adaptive, 16);
    RenderResult full = renderScene(scene, s);
    RenderSettings banded = s;
    banded.bandBytes = 160 * 16 * (gpu::kAovCount + 1) * 5;  // a few rows a band
    RenderResult bands = renderScene(scene, banded);
    EXPECT_GT(bands.bands, 4);
    EXPECT_EQ(ids(bands, 0), ids(full, 0));
    EXPECT_EQ(ids(bands, 1), ids(full, 1));
    RenderSettings region = s;
    region.region = PixelRegion{37, 21, 121, 70};
    RenderResult part = renderScene(scene, region);
    std::vector<uint32_t> whole = ids(full, 0), got = ids(part, 0);
    for (int y = 21; y < 70; ++y)
        for (int x = 37; x < 121; ++x) ASSERT_EQ(got[size_t(y - 21) * 84 + (x - 37)], whole[size_t(y) * 160 + x]);
}

// The command line: EXR masks hold UINT channels (read back as floats here:
// normalised), PNG masks a hash colour per id, the background
// black; the record's legend lists the objects and materials.
TEST(Masks, FilesAndLegend) {
    fs::path dir = freshOutputDir("masks", "files");
    fs::path scene = sourceDir() / "scenes" / "showcase.xml";
    for (const char* ext : {".exr", ".png"}) {
        CommandRun run = runCommand("'" WHITTED_EXECUTABLE "' render " + scene.string() + " --width 80 --height 45 -q --aov object_id,material_id -o " +
                                        (dir / (std::string("out") + ext)).string(),
                                    dir);
        ASSERT_EQ(run.status, 0) << run.output;
    }
    std::vector<float> storage;
    int w = 0, h = 0, c = 0;
    std::span<const float> exr = readImageInto(dir / "out.object_id.exr", w, h, c, storage);
    ASSERT_EQ(c, 1);
    std::vector<float> pngStorage;
    int pw = 0, ph = 0, pc = 0;
    std::span<const float> png = readImageInto(dir / "out.object_id.png", pw, ph, pc, pngStorage);
    ASSERT_EQ(pc, 3);
    std::set<float> seen;
    for (size_t i = 0; i < exr.size(); ++i) {
        // OpenImageIO reads a UINT channel as a float normalised by 2^32 - 1.
        double id = std::round(double(exr[i]) * 4294967295.0);
        seen.insert(float(id));
        ASSERT_TRUE(id >= 0 && id < 6) << id;
        uint32_t rgb = gpu::idColorRgb8(uint32_t(id));
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(std::lround(png[i * 3 + size_t(k)] * 255.0f), long((rgb >> (8 * k)) & 0xffu));
    }
    EXPECT_EQ(seen.size(), 6u);
    std::ifstream in(dir / "out.json");
    nlohmann::json record = nlohmann::json::parse(in);
    const nlohmann::json& objects = record["masks"]["objects"];
    ASSERT_EQ(objects.size(), 6u);
    EXPECT_EQ(objects[2]["shape"], "sphere");
    EXPECT_EQ(objects[3]["shape"], "csg");
    EXPECT_EQ(record["masks"]["materials"].size(), 7u) << "the drill's own material follows the objects'";
    EXPECT_EQ(record["masks"]["materials"][6]["object"], 4);
}

// The legend names each object, and each object's material after it.
TEST(Masks, LegendNamesTheObjects) {
    Scene scene = showcase();
    scene.objects[2].name = "planet";
    scene.objects[5].name = "mirror ball";
    nlohmann::ordered_json legend = maskLegend(scene);
    EXPECT_EQ(legend["objects"][2]["name"], "planet");
    EXPECT_EQ(legend["objects"][5]["name"], "mirror ball");
    EXPECT_EQ(legend["objects"][5]["id"], 5);
    EXPECT_EQ(legend["materials"][2]["name"], "planet");
    EXPECT_EQ(legend["background"], 0xffffffffu);
}

// Neighbouring ids get different colours, none of them black (the background).
TEST(Masks, HashColoursDiffer) {
    EXPECT_EQ(gpu::idColorRgb8(gpu::kNoObject), 0u);
    for (uint32_t id = 0; id < 1000; ++id) {
        EXPECT_NE(gpu::idColorRgb8(id), gpu::idColorRgb8(id + 1)) << id;
        for (int k = 0; k < 3; ++k) EXPECT_GE((gpu::idColorRgb8(id) >> (8 * k)) & 0xffu, 64u);
    }
}

}  // namespace
}  // namespace whitted::test

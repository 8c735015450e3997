#include "povray/povray_export.h"

#include "io/texture.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <variant>

namespace whitted {
namespace {

// Shortest text that reads back as the same double.
std::string num(double v) {
    if (v == 0.0) return "0";  // also turns -0 into 0
    char buffer[32];
    for (int precision = 6; precision <= 17; ++precision) {
        std::snprintf(buffer, sizeof buffer, "%.*g", precision, v);
        if (std::strtod(buffer, nullptr) == v) break;
    }
    return buffer;
}

std::string vec(const glm::dvec3& v) { return "<" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ">"; }

bool isGrey(const glm::dvec3& c) { return c.r == c.g && c.g == c.b; }

std::string where(const Scene& scene, const Object& object) {
    return scene.sourcePath.string() + ":" + std::to_string(object.sourceLine);
}

// An image texture as POV-Ray's image_map: the file by its absolute path,
// its type from the extension, 8-bit files sRGB-decoded as ours are
// (gamma srgb), bilinear lookups (interpolate 2; POV-Ray has no mip maps),
// placed as our mapping places it: spheres by the spherical map (map_type 1,
// the same longitude and latitude as sphereUv()) moved to the centre,
// meshes by their triangles' uv_vectors (uv_mapping). Other shapes are not
// exported textured (povrayInexactMappings says so).
std::string imageMap(const Material& m, const Shape& shape) {
    std::string path = m.diffuseTexture.data->name;
    std::string extension = path.substr(path.find_last_of('.') + 1);
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    std::string type = extension == "jpg" || extension == "jpeg" ? "jpeg"
                       : extension == "tif" || extension == "tiff" ? "tiff"
                                                                   : extension;
    std::string map = type + " \"" + path + "\"" + (m.diffuseTexture.data->srgbDecoded ? " gamma srgb" : "") +
                      " interpolate 2";
    if (const Sphere* sphere = std::get_if<Sphere>(&shape))
        return "image_map { " + map + " map_type 1 } translate " + vec(sphere->center);
    if (std::holds_alternative<Mesh>(shape)) return "uv_mapping image_map { " + map + " }";
    return "";
}

// The environment as what POV-Ray shows where rays leave the scene: a colour as `background`, a gradient
// as a sky_sphere whose pigment is linear in y (a function pattern from -1 to 1 with the ground, horizon and
// zenith colours at 0, 0.5 and 1), an image as a sky_sphere image_map (map_type 1: u from +x towards +z,
// v up; turned by -90 degrees about y so that its centre looks along -z, then by our rotation, which is
// POV-Ray's rotate y*degrees). None of them lights the scene (POV-Ray's sky lights nothing without
// radiosity), and an image's intensity is not exported: povrayInexactMappings says so.
std::string environmentSdl(const Scene& scene) {
    if (!scene.environment) return "background { rgb 0 }\n";
    const Environment& e = *scene.environment;
    std::string visible = e.visible ? "" : "  // <visible>false</visible>: not exported\n";
    switch (e.kind) {
        case Environment::Kind::Color: return "background { rgb " + vec(e.color * e.intensity) + " }\n";
        case Environment::Kind::Gradient:
            return "sky_sphere {\n  pigment { function { y * 0.5 + 0.5 } color_map { [0 rgb " +
                   vec(e.ground * e.intensity) + "] [0.5 rgb " + vec(e.horizon * e.intensity) + "] [1 rgb " +
                   vec(e.zenith * e.intensity) + "] } }\n" + visible + "}\n";
        case Environment::Kind::Image: break;
    }
    std::string path = e.image ? e.image->name : e.imageWritten;
    std::string extension = path.substr(path.find_last_of('.') + 1);
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    std::string type = extension == "jpg" || extension == "jpeg" ? "jpeg" : extension == "tif" ? "tiff" : extension;
    bool srgb = e.image && e.image->srgbDecoded;
    return "sky_sphere {\n  pigment { image_map { " + type + " \"" + path + "\"" + (srgb ? " gamma srgb" : "") +
           " interpolate 2 map_type 1 } rotate <0, " + num(e.rotationDegrees - 90.0) + ", 0> }\n" + visible + "}\n";
}

bool exportsTexture(const Material& m, const Shape& shape) {
    return m.diffuseTexture && !m.diffuseTexture.written.empty() &&
           (std::holds_alternative<Sphere>(shape) || std::holds_alternative<Mesh>(shape));
}

// pigment, finish and interior of one object (see the header for the
// mapping and for what is not exact).
std::string texture(const Material& m, bool shadows, const Shape& shape) {
    std::ostringstream s;
    if (!shadows) s << "  no_shadow\n";
    // Shadow rays through a transparent surface are filtered by filter·Cd +
    // transmit = kt·mix(white, Cd, kd) per crossing, exactly as ours.
    // Approximate: refracted light is filtered the same way (ours: kt alone)
    // and POV-Ray dims the local terms by the pigment's opacity.
    auto colour = [&](const glm::dvec3& c) {
        if (m.transmission <= 0.0) return "rgb " + vec(c);
        return "rgbft <" + num(c.r) + ", " + num(c.g) + ", " + num(c.b) + ", " + num(m.transmission * m.diffuse) +
               ", " + num(m.transmission * (1.0 - m.diffuse)) + ">";
    };
    // The checker is POV-Ray's own pattern (first colour in the cells of
    // even sum), scaled and moved as ours; same coordinates (see the camera).
    // A texture multiplies Cd: exact for a white Cd (the only case exported
    // as such; see povrayInexactMappings).
    if (exportsTexture(m, shape))
        s << "  pigment { " << imageMap(m, shape) << " }\n";
    else if (m.checkerSize > 0.0)
        s << "  pigment { checker " << colour(m.diffuseColor) << " " << colour(m.checkerColor) << " scale "
          << num(m.checkerSize) << " translate " << vec(m.checkerOrigin) << " }\n";
    else
        s << "  pigment { " << colour(m.diffuseColor) << " }\n";
    // Every finish value is written, so POV-Ray's defaults (ambient 0.1,
    // diffuse 0.6, phong_size 40, ...) never apply.
    s << "  finish {\n"
      << "    ambient " << num(m.ambient) << " emission 0\n"
      << "    diffuse " << num(m.diffuse) << " brilliance 1 crand 0\n";
    double phong = m.specular * (m.specularColor.r + m.specularColor.g + m.specularColor.b) / 3.0;
    s << "    phong " << num(phong) << " phong_size " << num(m.shininess) << "\n"
      << "    specular 0 metallic 0\n";
    glm::dvec3 reflection = m.reflection * m.specularColor;
    s << "    reflection { rgb " << vec(reflection) << " }\n"
      << "  }\n";
    if (m.transmission > 0.0) {
        s << "  interior { ior " << num(m.ior);
        // POV-Ray's exponential fade (fade_power >= 1000) multiplies light
        // that travelled d inside, refracted or shadow, by
        // exp(-(1 - fade_color)·d / fade_distance): with fade_distance
        // 1/max(sigma) and fade_color 1 - sigma/max(sigma), exp(-sigma·d).
        double sigmaMax = std::max({m.absorption.r, m.absorption.g, m.absorption.b});
        if (sigmaMax > 0.0)
            s << " fade_distance " << num(1.0 / sigmaMax) << " fade_power 1001 fade_color rgb "
              << vec(glm::dvec3(1.0) - m.absorption / sigmaMax);
        s << " }\n";
    }
    return s.str();
}

std::string uvVectors(const std::array<glm::dvec2, 3>& uv) {
    auto v2 = [](const glm::dvec2& v) { return "<" + num(v.x) + ", " + num(v.y) + ">"; };
    return " uv_vectors " + v2(uv[0]) + ", " + v2(uv[1]) + ", " + v2(uv[2]);
}

// A triangle without area renders nothing here; POV-Ray would warn about it.
bool zeroArea(const Triangle& t) { return glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)) == 0.0; }

bool anyTransparent(const Csg& csg) {
    return std::any_of(csg.children.begin(), csg.children.end(), [](const CsgChild& c) {
        const Csg* nested = std::get_if<Csg>(&c.shape);
        return c.material.transmission > 0.0 || (nested && anyTransparent(*nested));
    });
}

struct ShapeWriter {
    std::ostringstream& s;
    const std::string& material;
    bool shadows = true;

    void operator()(const Sphere& sp) const {
        s << "sphere { " << vec(sp.center) << ", " << num(sp.radius) << "\n" << material << "}\n";
    }
    void operator()(const Cylinder& c) const {
        glm::dvec3 top = c.base + glm::normalize(c.axis) * c.height;
        // Capped unless "open" is given, like ours.
        s << "cylinder { " << vec(c.base) << ", " << vec(top) << ", " << num(c.radius) << "\n" << material << "}\n";
    }
    void operator()(const Plane& p) const {
        glm::dvec3 n = glm::normalize(p.normal);
        s << "plane { " << vec(n) << ", " << num(glm::dot(n, p.point)) << "\n" << material << "}\n";
    }
    void operator()(const Triangle& t) const {
        if (zeroArea(t)) return;
        s << "triangle { " << vec(t.v0) << ", " << vec(t.v1) << ", " << vec(t.v2) << "\n" << material << "}\n";
    }
    void operator()(const Box& b) const {
        s << "box { " << vec(b.min) << ", " << vec(b.max) << "\n" << material << "}\n";
    }
    // POV-Ray's CSG has our operations (difference: the first child minus
    // the others) and our material rule: the csg object's texture goes to
    // the children without one of their own. Its union keeps the inner
    // surfaces, which only transparency shows: then merge, which drops them
    // as ours does.
    void operator()(const Csg& csg) const {
        const char* op = csg.operation == Csg::Operation::Intersection ? "intersection"
                         : csg.operation == Csg::Operation::Difference ? "difference"
                         : anyTransparent(csg)                         ? "merge"
                                                                       : "union";
        s << op << " {\n";
        for (const CsgChild& child : csg.children) {
            std::string own = child.ownMaterial ? texture(child.material, shadows, child.shape) : std::string();
            std::visit(ShapeWriter{s, own, shadows}, child.shape);
        }
        s << material << "}\n";
    }
    void operator()(const Mesh& m) const {
        // POV-Ray refuses an empty mesh.
        if (std::all_of(m.triangles.begin(), m.triangles.end(), zeroArea)) return;
        // Smooth meshes as smooth_triangle: POV-Ray interpolates the vertex
        // normals across the triangle as we do (Phong).
        s << "mesh {\n";
        for (size_t i = 0; i < m.triangles.size(); ++i) {
            const Triangle& t = m.triangles[i];
            if (zeroArea(t)) continue;
            // Texture coordinates ride on each triangle (uv_vectors).
            std::string uv = m.uvs.empty() ? "" : uvVectors(m.uvs[i]);
            if (m.normals.empty()) {
                s << "  triangle { " << vec(t.v0) << ", " << vec(t.v1) << ", " << vec(t.v2) << uv << " }\n";
            } else {
                const auto& n = m.normals[i];
                s << "  smooth_triangle { " << vec(t.v0) << ", " << vec(n[0]) << ", " << vec(t.v1) << ", "
                  << vec(n[1]) << ", " << vec(t.v2) << ", " << vec(n[2]) << uv << " }\n";
            }
        }
        s << material << "}\n";
    }
};

// Inverse-square falloff as POV-Ray's fade (see the header): a fade
// distance far below any distance to a lit surface, the colour scaled up.
constexpr double kFadeDistance = 1e-4;
// A spot's cone as this many spotlights (see the header).
constexpr int kSpotPieces = 16;
// How far back a directional light's parallel source is placed: beyond the
// format's coordinates (scene/xml_reader.h, kMaxMagnitude 1e6).
constexpr double kParallelDistance = 1e7;

// An area light of ours as POV-Ray's area_light (see the header): a grid of
// ceil(sqrt(N))^2 jittered points for our N shadow samples, every one used
// (no adaptive), each with its own direction (area_illumination on). A
// sphere is the disc of its radius facing the shaded point (circular
// orient); a rect light its edges u and v. Empty for a point light.
std::string areaLight(const Light& light) {
    if (!light.area()) return "";
    int side = int(std::ceil(std::sqrt(double(light.shadowSamples))));
    std::string grid = ", " + std::to_string(side) + ", " + std::to_string(side) + " jitter area_illumination on";
    if (light.type == Light::Type::Rect) return " area_light " + vec(light.u) + ", " + vec(light.v) + grid;
    double diameter = 2.0 * light.radius;
    return " area_light " + vec({diameter, 0, 0}) + ", " + vec({0, diameter, 0}) + grid + " circular orient";
}

// One light of ours as POV-Ray light_source blocks. POV-Ray's default
// fade_power 0 means no falloff, as ours without <falloff>.
std::string lightSource(const Light& light) {
    std::ostringstream s;
    glm::dvec3 colour = light.color * light.intensity;
    bool inverseSquare = light.falloff == Light::Falloff::InverseSquare && light.type != Light::Type::Directional;
    std::string fade;
    if (inverseSquare) {
        colour /= 2.0 * kFadeDistance * kFadeDistance;
        fade = " fade_distance " + num(kFadeDistance) + " fade_power 2";
    }
    glm::dvec3 direction = glm::normalize(light.direction);
    fade += areaLight(light);
    if (light.type == Light::Type::Point || light.type == Light::Type::Rect) {
        s << "light_source { " << vec(light.position) << " color rgb " << vec(colour) << fade << " }\n";
    } else if (light.type == Light::Type::Directional) {
        glm::dvec3 location = -direction * kParallelDistance;
        s << "light_source { " << vec(location) << " color rgb " << vec(colour) << " parallel point_at "
          << vec(location + direction) << " }\n";
    } else {
        // Piece k ramps from 0 at s_k = k/N to 1 at s_k+1 (s the normalised
        // cosine of the KHR formula), weighted s_k+1^2 - s_k^2: the pieces
        // sum to 1 inside the inner cone.
        double cosInner = std::cos(glm::radians(light.innerAngleDegrees));
        double cosOuter = std::cos(glm::radians(light.outerAngleDegrees));
        auto angleAt = [&](double sk) { return glm::degrees(std::acos(cosOuter + sk * (cosInner - cosOuter))); };
        s << "// a spot light: " << kSpotPieces << " spotlights\n";
        for (int k = 0; k < kSpotPieces; ++k) {
            double lo = double(k) / kSpotPieces, hi = double(k + 1) / kSpotPieces;
            s << "light_source { " << vec(light.position) << " color rgb " << vec(colour * (hi * hi - lo * lo))
              << " spotlight point_at " << vec(light.position + direction) << " radius " << num(angleAt(hi))
              << " falloff " << num(angleAt(lo)) << " tightness 0" << fade << " }\n";
        }
    }
    return s.str();
}

}  // namespace

std::string exportPovray(const Scene& scene, const PovrayExportOptions& options) {
    const Camera& camera = scene.camera;
    int width = options.width > 0 ? options.width : camera.width;
    int height = options.height > 0 ? options.height : camera.height;

    std::ostringstream s;
    s << "// Exported by whitted from " << scene.sourcePath.string() << " for " << width << "x" << height
      << ", max depth " << options.maxDepth << ".\n"
      << "// Render: povray -D +W" << width << " +H" << height << " +FE File_Gamma=1.0 +I<this file>\n"
      << "#version 3.7;\n\n";

    // max_trace_level counts the camera ray as level 1 (TraceRay refuses a
    // ray once traceLevel >= max_trace_level, and the camera ray starts at
    // 0); our max depth counts secondary bounces only. adc_bailout 0: no
    // ray is dropped for a small weight (ours never drops one).
    s << "global_settings {\n"
      << "  assumed_gamma 1.0\n"
      << "  ambient_light rgb " << vec(scene.ambientLight) << "\n"
      << "  max_trace_level " << options.maxDepth + 1 << "\n"
      << "  adc_bailout 0\n"
      << "}\n"
      << environmentSdl(scene) << "\n";

    // Our camera frame (host/render/gpu_scene.cpp): right = cross(forward,
    // up), up' = cross(right, forward), the window spanning
    // ±tan(fov/2)·aspect and ±tan(fov/2) at unit distance. POV-Ray's
    // perspective camera shoots direction + x·right + y·up with x, y in
    // [-1/2, 1/2] (x growing to the right of the image, y to the top), so
    // right and up are the full window extents. Given explicitly (no
    // look_at, no sky), these vectors are used as they are: the same rays
    // in the same coordinates, whatever the handedness.
    glm::dvec3 forward = glm::normalize(camera.windowCenter - camera.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::dvec3 up = glm::cross(right, forward);
    double tanHalf = std::tan(glm::radians(camera.verticalFovDegrees) / 2.0);
    double aspect = double(width) / double(height);
    s << "camera {\n"
      << "  perspective\n"
      << "  location " << vec(camera.eye) << "\n"
      << "  direction " << vec(forward) << "\n"
      << "  right " << vec(right * (2.0 * tanHalf * aspect)) << "\n"
      << "  up " << vec(up * (2.0 * tanHalf)) << "\n";
    // The thin lens as focal blur (the header says how it maps).
    if (camera.apertureRadius > 0)
        s << "  aperture " << num(4.0 * camera.apertureRadius) << "\n"
          << "  focal_point " << vec(camera.eye + forward * camera.focusDistanceOrDefault()) << "\n"
          << "  blur_samples " << options.blurSamples << "\n"
          << "  confidence 0.999 variance 0\n";
    s << "}\n\n";

    for (const Light& light : scene.lights) s << lightSource(light);
    s << "\n";

    for (const Object& object : scene.objects) {
        if (object.sourceLine > 0) s << "// " << where(scene, object) << "\n";
        std::string material = texture(object.material, options.shadows, object.shape);
        std::visit(ShapeWriter{s, material, options.shadows}, object.shape);
    }
    return s.str();
}

namespace {

// The materials of a csg object's children, nested ones included.
void csgMaterials(const Csg& csg, std::vector<const Material*>& out) {
    for (const CsgChild& child : csg.children) {
        out.push_back(&child.material);
        if (const Csg* nested = std::get_if<Csg>(&child.shape)) csgMaterials(*nested, out);
    }
}

}  // namespace

std::vector<std::string> povrayInexactMappings(const Scene& scene) {
    std::vector<std::string> notes;
    for (const Object& object : scene.objects) {
        std::vector<const Material*> used = {&object.material};
        if (const Csg* csg = std::get_if<Csg>(&object.shape)) csgMaterials(*csg, used);
        for (const Material* material : used) {
            const Material& m = *material;
            if (m.specular > 0.0 && !isGrey(m.specularColor))
                notes.push_back(where(scene, object) +
                                ": a Phong highlight with a coloured specular_color (POV-Ray's phong highlight takes "
                                "the light's colour; exported as ks times the mean of Cs)");
            if (m.diffuseTexture && (material != &object.material || !exportsTexture(m, object.shape) ||
                                     m.diffuseColor != glm::dvec3(1.0)))
                notes.push_back(where(scene, object) +
                                ": an image texture on a shape other than a sphere or a mesh, from a model file's "
                                "embedded image, or with a diffuse_color other than white (exported untextured)");
            if (m.normalMap) notes.push_back(where(scene, object) + ": a normal map (not exported)");
            if (m.fresnel)
                notes.push_back(where(scene, object) +
                                ": fresnel (Schlick's approximation here, the full Fresnel equations in POV-Ray; "
                                "not exported)");
            if (m.roughness > 0.0)
                notes.push_back(where(scene, object) +
                                ": roughness (POV-Ray reflects and refracts sharply; exported as a mirror)");
            if (m.transmissionColor != glm::dvec3(1.0))
                notes.push_back(where(scene, object) + ": a transmission_color (not exported)");
            if (m.emission != glm::dvec3(0.0))
                notes.push_back(where(scene, object) +
                                ": emission (POV-Ray's finish emission is multiplied by the pigment; not exported)");
            if (m.ambientColor)
                notes.push_back(where(scene, object) +
                                ": an ambient_color (POV-Ray's ambient is multiplied by the pigment; not exported)");
            if (m.transmission > 0.0)
                notes.push_back(where(scene, object) +
                                ": transmission (POV-Ray dims the local terms by the pigment's opacity and filters "
                                "refracted light by the pigment; exported approximately, its shadows exactly)");
        }
    }
    if (const std::optional<Environment>& e = scene.environment) {
        std::string at = scene.sourcePath.string() + ":" + std::to_string(e->sourceLine);
        if (e->shadowSamples > 0)
            notes.push_back(at + ": the environment's light (POV-Ray's background and sky_sphere light nothing; "
                                 "not exported)");
        if (!e->visible) notes.push_back(at + ": an environment hidden from the camera (not exported)");
        if (e->kind == Environment::Kind::Image && e->intensity != 1.0)
            notes.push_back(at + ": an environment image's intensity (not exported)");
    }
    for (const Light& light : scene.lights)
        if (light.type == Light::Type::Rect && !light.twoSided)
            notes.push_back(scene.sourcePath.string() + ":" + std::to_string(light.sourceLine) +
                            ": a one-sided rect light (POV-Ray's area_light shines from both faces)");
    return notes;
}

}  // namespace whitted

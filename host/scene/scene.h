// The CPU scene model: what the XML loader produces and what the renderer
// uploads. Plain data, world space, right-handed, no GPU types.
#pragma once

#include "scene/environment.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace whitted {

struct TextureData;  // io/texture_file.h

// An image texture of a material: the path as the scene file wrote it
// (relative to the scene file's folder) and its decoded texels, shared by
// the objects and scene copies that use the same file.
struct TextureRef {
    std::string written;
    std::shared_ptr<const TextureData> data;
    explicit operator bool() const { return data != nullptr; }
};

// Pinhole camera. The image plane ("window") is centred on windowCenter and
// perpendicular to forward = windowCenter - eye. Image right is
// cross(forward, up); image up completes the right-handed frame.
// An orthographic camera's rays are parallel to forward and start on the
// plane through eye perpendicular to it, over a window windowHeight high
// (world units; its width from the image's aspect): a glTF camera's 2 ymag.
struct Camera {
    enum class Projection { Perspective, Orthographic };
    glm::dvec3 eye{0, 0, 0};
    glm::dvec3 windowCenter{0, 0, -1};
    glm::dvec3 up{0, 1, 0};
    double verticalFovDegrees = 60.0;  // perspective
    Projection projection = Projection::Perspective;
    double windowHeight = 2.0;  // orthographic
    int width = 640;
    int height = 480;
    // Set from an intrinsic matrix (Python's Camera.set_from_matrices,
    // scene/camera_matrices.h): pixels of the width x height image, OpenCV's
    // (origin at the top-left pixel's centre, x right, y down). While set, a
    // perspective camera's window comes from these, not verticalFovDegrees;
    // eye/windowCenter/up still give the pose. In the XML format as
    // <intrinsics fx fy cx cy/> (scenes/README.md "Scene files").
    struct Intrinsics {
        double fx = 0, fy = 0, cx = 0, cy = 0;
        bool operator==(const Intrinsics&) const = default;
    };
    std::optional<Intrinsics> intrinsics;
    // Depth of field (scenes/README.md "Depth of field"): a thin lens of
    // this radius (scene units) in the plane of right and up about eye,
    // focused on the plane focusDistance along the view; 0 is a pinhole.
    // Without a focus distance the lens focuses at the window centre's
    // distance, |windowCenter - eye|.
    double apertureRadius = 0.0;
    std::optional<double> focusDistance;
    double focusDistanceOrDefault() const;
};

// Whether a camera has an image frame: its eye and window centre apart, its
// up not along the view. The XML loader and the Python module refuse what
// this says, each in its own words (device rays would be NaN).
enum class CameraFrameProblem { None, EyeAtWindow, UpAlongView };
CameraFrameProblem cameraFrameProblem(const Camera& camera);

// The Phong exponent of a glossy material's reflection and refraction lobes:
// 2 / alpha^2 - 2 with alpha = roughness^2 (Walter et al. 2007's match of a
// Phong exponent to a Beckmann width; roughness as glTF's perceptual one).
// Infinite at 0 (a mirror), 0 at 1 (cos^0: the whole hemisphere).
double glossyLobeExponent(double roughness);

// A light (scenes/README.md "Scene files"): the seed's point light, and the
// spot and directional lights of glTF's KHR_lights_punctual and POV-Ray.
// What arrives at a point at distance d is color * intensity, divided by d^2
// with inverse-square falloff; a spot scales it by
// saturate((cos theta - cos outer) / (cos inner - cos outer))^2, theta the
// angle from its direction (the KHR_lights_punctual formula).
// Area lights (distribution ray tracing, Cook, Porter and Carpenter 1984): a
// point or spot light with a radius is a sphere, a Rect light a rectangle;
// each is shadowSamples point lights of the whole colour at points sampled on
// it, averaged, so a small one matches a point light (scenes/README.md
// "Area lights").
struct Light {
    enum class Type { Point, Spot, Directional, Rect };
    enum class Falloff { None, InverseSquare };
    Type type = Type::Point;
    glm::dvec3 position{0, 0, 0};    // point and spot; a directional light has none
    glm::dvec3 direction{0, 0, -1};  // spot and directional: unit, the way the light travels
    glm::dvec3 color{1, 1, 1};       // linear RGB radiant intensity
    double intensity = 1.0;          // multiplies color
    Falloff falloff = Falloff::None;  // None: the seed's lights, no falloff
    double innerAngleDegrees = 0.0;   // spot: 0 <= inner < outer <= 90
    double outerAngleDegrees = 45.0;
    double radius = 0.0;              // point and spot: a sphere of this radius; 0 is a point
    int shadowSamples = 1;            // area lights: shadow rays per camera sample, 1..kMaxShadowSamples
    glm::dvec3 u{1, 0, 0};            // rect: full edge vectors about position; it faces u x v
    glm::dvec3 v{0, 1, 0};
    bool twoSided = false;            // rect: shines from both faces
    std::string name{};  // optional (<name>, a glTF light's name)
    int sourceLine = 0;

    // A sphere of positive radius or a rectangle: its shadow rays go to sampled points.
    bool area() const {
        return type == Type::Rect || ((type == Type::Point || type == Type::Spot) && radius > 0.0);
    }
};

// Whether a rect light's edges u and v span an area (neither zero, not parallel).
bool rectEdgesSpan(const glm::dvec3& u, const glm::dvec3& v);

// Phong + Whitted material (see scenes/README.md "Shading model").
struct Material {
    glm::dvec3 diffuseColor{1, 1, 1};   // Cd
    glm::dvec3 specularColor{1, 1, 1};  // Cs
    double ambient = 0.0;               // ka ("ambiente_coef")
    double diffuse = 1.0;               // kd
    double specular = 0.0;              // ks
    double shininess = 32.0;            // Phong exponent
    double reflection = 0.0;            // kr (defaults to ks when reflective)
    double transmission = 0.0;          // kt
    double ior = 1.0;                   // index of refraction against air
    // Glossy reflection and refraction (scenes/README.md "Shading model"):
    // in [0, 1], 0 a perfect mirror; the rays follow a Phong lobe of
    // exponent glossyLobeExponent(roughness) about the ideal direction.
    double roughness = 0.0;
    // Solid checker (POV-Ray's checker pigment scaled by checkerSize): the
    // cell floor((p - checkerOrigin) / size + 0.001) with an odd sum of its
    // coordinates takes checkerColor instead of Cd. checkerSize 0: none.
    glm::dvec3 checkerColor{1, 1, 1};
    double checkerSize = 0.0;
    glm::dvec3 checkerOrigin{0, 0, 0};  // the object's <position> (with a checker)
    glm::dvec3 absorption{0, 0, 0};     // Beer-Lambert sigma per unit length, inside the object
    // Image texture multiplying Cd (scenes/README.md "Textures"), and on planes the
    // world length of one repeat of it.
    TextureRef diffuseTexture{};
    double textureScale = 1.0;
    // Tangent-space normal map (linear data, OpenGL convention: green is
    // +v) and how far it tilts the normal: its x, y scaled by the strength.
    TextureRef normalMap{};
    double normalStrength = 1.0;
    // With fresnel, `reflection` is F0 of Schlick's approximation: the
    // reflected ray weighs Cs (kr + (1 - kr)(1 - cos theta)^5) and the
    // transmitted one kt (1 - F) (POV-Ray's `fresnel on`).
    bool fresnel = false;
    glm::dvec3 transmissionColor{1, 1, 1};  // tints refracted light and the shadow filter (MTL Tf)
    glm::dvec3 emission{0, 0, 0};           // added where a ray hits the surface; lights nothing else
    std::optional<glm::dvec3> ambientColor{};  // the ambient term's colour (MTL Ka); none: Cd
    TextureRef emissionTexture{};  // multiplies `emission` (glTF's emissiveTexture)
    // Linear data whose green channel multiplies `roughness` where a ray hits
    // (glTF's metallicRoughnessTexture); needs roughness > 0.
    TextureRef roughnessTexture{};

    // The textures, which read a surface's texture coordinates: one list, so
    // that code over all of them (attributes, copies, watched files) misses none.
    std::array<TextureRef*, 4> textures() { return {&diffuseTexture, &normalMap, &emissionTexture, &roughnessTexture}; }
    std::array<const TextureRef*, 4> textures() const {
        return {&diffuseTexture, &normalMap, &emissionTexture, &roughnessTexture};
    }
    bool textured() const { return diffuseTexture || normalMap || emissionTexture || roughnessTexture; }
    void dropTextures() {
        for (TextureRef* t : textures()) *t = {};
    }
};

struct Sphere {
    glm::dvec3 center;
    double radius;
};

// Capped cylinder: base is the centre of the bottom cap, it extends `height`
// along the unit vector `axis`.
struct Cylinder {
    glm::dvec3 base;
    glm::dvec3 axis;
    double radius;
    double height;
};

// Infinite two-sided plane through `point`.
struct Plane {
    glm::dvec3 point;
    glm::dvec3 normal;  // unit length
};

// Two-sided triangle, world-space vertices. Its geometric normal follows the
// winding: normalize(cross(v1 - v0, v2 - v0)).
struct Triangle {
    glm::dvec3 v0, v1, v2;
};

// Axis-aligned box.
struct Box {
    glm::dvec3 min;
    glm::dvec3 max;
};

// A triangle mesh, world-space vertices (the loader applies the object's
// scale, rotation and position). normals is empty for a flat-shaded mesh, or
// holds the unit vertex normals of each triangle (v0, v1, v2 order), world
// space, for smooth shading; their side may differ from the winding's.
// uvs is empty, or holds the texture coordinates of each triangle's
// vertices (v up, (0, 0) the image's bottom-left corner).
// tangents is empty, or holds each triangle's unit vertex tangents (world
// space, along +u; zero vectors where the file's were unusable), from a
// model file, for normal maps.
struct Mesh {
    std::vector<Triangle> triangles;
    std::vector<std::array<glm::dvec3, 3>> normals;
    // A mesh read from a model file (<file>): where from and how it was
    // placed, so that the scene writer writes the reference again rather
    // than its triangles. Moving the mesh moves `position` with it.
    struct FileSource {
        std::filesystem::path path;  // absolute: the scene file's folder applied
        glm::dvec3 position{0};      // the object's <position>
        glm::dvec3 scale{1};
        glm::dvec3 rotationDegrees{0};
        // A file whose own materials apply (the object set no colour) is
        // split into one object per material: part k of them, the writer
        // writing the <file> once, for part 0, without a colour. -1: whole.
        int part = -1;
        // <file part="...">: the part of the file the object takes (a glTF
        // mesh primitive "mesh M primitive P", or "material NAME" of any
        // other file), empty for the whole file; and its <matrix>, which
        // places the part instead of <scale> and <rotation>.
        std::string partName;
        std::optional<glm::dmat4> matrix;
    };
    std::optional<FileSource> source;
    std::vector<std::array<glm::dvec2, 3>> uvs;
    std::vector<std::array<glm::dvec3, 3>> tangents;
};

struct CsgChild;

// Limits of a csg tree, set by the shader's fixed-size state (the same
// numbers as in shaders/device_types.h, static_asserted in
// host/shapes/csg.cpp): leaf shapes under one top-level csg object, and
// csg objects nested in each other (a csg object of leaves only: 1).
inline constexpr size_t kCsgMaxLeaves = 16;
inline constexpr int kCsgMaxDepth = 8;

// Constructive solid geometry (scenes/README.md "CSG"): the union, intersection or
// difference (the first child minus the others) of closed solids: spheres,
// cylinders, boxes and nested csg objects. The children are in world space;
// position is the csg object's <position>, which they were placed from.
struct Csg {
    enum class Operation { Union, Intersection, Difference };
    Operation operation = Operation::Union;
    glm::dvec3 position{0, 0, 0};
    std::vector<CsgChild> children;
};

using Shape = std::variant<Sphere, Cylinder, Plane, Triangle, Box, Mesh, Csg>;

// A child of a csg object. Its material is its own when its <object> gives
// any material element (ownMaterial), else the csg object's (POV-Ray's rule).
struct CsgChild {
    Shape shape;
    Material material;
    bool ownMaterial = false;
    int sourceLine = 0;
};

// The leaf shapes (spheres, cylinders, boxes) under a csg object, those of
// nested csg objects included: what kCsgMaxLeaves limits.
size_t csgLeafCount(const Csg& csg);

struct Object {
    Shape shape;
    Material material;
    std::string name{};  // optional (<name>; a glTF node's or an OBJ group's name)
    int sourceLine = 0;  // line of the <object> element, for messages
};

// Instancing (scenes/README.md "Instances"): a prototype is a group of mesh
// and triangle objects in its own space, stored once and drawn only through
// its instances; each instance places it by an affine transform
// (world = worldFromObject * object), optionally with a material of its own
// that replaces every prototype object's. The renderer walks each
// prototype's tree in object space (the two-level BVH of Wald, Boulos and
// Shirley 2007; shaders/instance.glsl).
struct Prototype {
    std::string name{};
    std::vector<Object> objects{};  // meshes and triangles, prototype space
    int sourceLine = 0;
};

struct Instance {
    uint32_t prototype = 0;  // index into Scene::prototypes
    glm::dmat4 worldFromObject{1.0};  // affine, invertible
    std::optional<Material> material{};
    std::string name{};
    int sourceLine = 0;
};

struct Scene {
    std::filesystem::path sourcePath;
    Camera camera;
    glm::dvec3 ambientLight{1, 1, 1};  // A
    std::optional<Environment> environment;  // none: a ray that leaves the scene sees black
    std::vector<Light> lights;
    std::vector<Object> objects;
    std::vector<Prototype> prototypes;
    std::vector<Instance> instances;  // drawn after the objects: instance i has object id objects.size() + i
    std::vector<std::string> warnings;  // degenerate but legal input
    // The lines a summary warning stands for (each glTF node's degenerate
    // triangles): shown by `whitted render --verbose` and kept in the render
    // record, so that a long list does not bury the other warnings.
    std::vector<std::string> warningDetails;
};

}  // namespace whitted

// GPU data layout shared by the C++ host and the GLSL shaders, declared once
// (the nvpro-samples host_device.h pattern). This core holds what every
// pipeline reads: the scene's arrays and their bindings, the per-render
// FrameParams, the output layers and the limits; each pipeline's own
// interface is a header of its own that includes this one:
//   tracer_types.h    the tracer (shaders/whitted.comp): tiles, counters, adaptive buffers
//   ray_tree_types.h  the ray-tree recorder (shaders/ray_tree.glsl)
//   ray_cast_types.h  ray casting (shaders/cast_rays.comp)
//   display_types.h   the window's display pass (shaders/display.comp)
// Every field has a name; the few that mean something different per shape
// (Primitive) are read through the named accessors beside it. The structs are
// laid out so that std430 (std140 for FrameParams) and C++ agree without
// GL_EXT_scalar_block_layout: each 16 bytes hold a vec4, a vec3 and a 4-byte
// scalar, two vec2s or four scalars, with explicit pad fields where a slot is
// unused. The host side static_asserts every size and offset
// (host/render/gpu_scene.cpp; ray_tree.cpp and ray_cast.cpp for their own).
#ifndef WHITTED_DEVICE_TYPES_H
#define WHITTED_DEVICE_TYPES_H

// The headers of this family declare their constants with WHITTED_CONST,
// zero-initialise their fields with WHITTED_ZERO and define their functions
// with WHITTED_FUNCTION, so that one text is both C++ and GLSL.
#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace whitted::gpu {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec3 = glm::uvec3;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
using glm::floatBitsToUint;
}  // namespace whitted::gpu
#define WHITTED_CONST inline constexpr
// Every field of a struct starts at zero on the host, so a designated
// initializer names only the fields it sets.
#define WHITTED_ZERO = {}
#define WHITTED_FUNCTION inline
#else
#define WHITTED_CONST const
#define WHITTED_ZERO
#define WHITTED_FUNCTION
#endif

#ifdef __cplusplus
namespace whitted::gpu {
#endif

WHITTED_CONST uint kWorkgroupSize = 8;  // 8x8 invocations, one pixel each

// Descriptor bindings of the single descriptor set. The shader reads the
// scene's arrays through the device addresses in FrameParams
// (shaders/scene.glsl); the storage-buffer variant reads them through
// bindings kBindingBvhNodeBuffer..kBindingLightBuffer below. The tracer's
// own bindings are in tracer_types.h.
WHITTED_CONST uint kBindingParams = 0;    // uniform FrameParams
// The scene's top-level acceleration structure, in the ray-query variant of
// the shader only (shaders/ray_query.glsl).
WHITTED_CONST uint kBindingTlas = 10;
// The BVH nodes, primitives, materials and lights once more, as storage buffers: the shader
// variant built with -DWHITTED_SCENE_STORAGE_BUFFERS reads them from here, for
// drivers that load a storage buffer faster than a device address (Mesa
// 22.3's lavapipe; shaders/scene.glsl, shaders/bvh.glsl).
WHITTED_CONST uint kBindingBvhNodeBuffer = 12;    // BvhNode[] (the buffer at FrameParams.bvhNodeAddress)
WHITTED_CONST uint kBindingPrimitiveBuffer = 13;  // Primitive[] (FrameParams.primitiveAddress)
WHITTED_CONST uint kBindingMaterialBuffer = 14;   // Material[] (FrameParams.materialAddress)
WHITTED_CONST uint kBindingLightBuffer = 15;      // Light[] (FrameParams.lightAddress)
// Image textures (diffuse and normal maps): an array of combined image
// samplers indexed by Material texture slots (shaders/texture.glsl).
WHITTED_CONST uint kBindingTextures = 11;
// Size of that array: unused entries hold a 1x1 dummy image.
WHITTED_CONST uint kMaxTextures = 32;
// Material.diffuseTexture or normalMap of a material without that texture.
WHITTED_CONST uint kNoTexture = 0xffffffffu;

// Shape tags in Primitive.shape.
WHITTED_CONST uint kShapeSphere = 0;
WHITTED_CONST uint kShapeCylinder = 1;
WHITTED_CONST uint kShapePlane = 2;
WHITTED_CONST uint kShapeTriangle = 3;
WHITTED_CONST uint kShapeBox = 4;
// A CSG object (shaders/shapes/csg.glsl): its tree lives in the CsgNode
// array; its leaves are ordinary primitives kept after the BVH's and the
// unbounded ones, so a hit reports the leaf primitive that was struck.
WHITTED_CONST uint kShapeCsg = 5;
// An instance of a prototype (shaders/instance.glsl): a stand-in in the
// scene's BVH whose box is the instance's world box; reaching it, the walk
// goes on in the prototype's own tree in object space. Only in the BVH;
// a hit never reports it.
WHITTED_CONST uint kShapeInstance = 6;

// CSG limits (scenes/README.md "CSG"), set by the shader's fixed-size state in
// intersectCsg (shaders/shapes/csg.glsl): each leaf's span along the ray is
// held in arrays of kCsgMaxLeaves entries and the set of leaves a point is
// inside in one 32-bit mask; the tree is evaluated as a postfix program on a
// stack of one bit per entry, which a tree of nesting depth d (a csg whose
// children are all leaves has depth 1) fills to d + 1 <= kCsgStackSize bits.
// The loader refuses larger trees.
WHITTED_CONST uint kCsgMaxLeaves = 16;  // leaf shapes per top-level csg object
WHITTED_CONST uint kCsgStackSize = 9;
WHITTED_CONST uint kCsgMaxDepth = kCsgStackSize - 1;  // csg objects nested in each other

// CsgNode.op: a leaf (CsgNode.leaf = its slot among the object's leaves) or a
// boolean operation folding the two values on top of the stack into one.
WHITTED_CONST uint kCsgLeaf = 0;
WHITTED_CONST uint kCsgUnion = 1;
WHITTED_CONST uint kCsgIntersection = 2;
WHITTED_CONST uint kCsgDifference = 3;  // the lower value minus the top one

// Primitive.extra0 of a triangle: kTriangleSmooth when a, b, c .w hold its
// vertex normals, octahedral-encoded (host/shapes/triangle.cpp), each
// coordinate in kOctahedralBits bits.
WHITTED_CONST uint kTriangleSmooth = 1;
WHITTED_CONST uint kOctahedralBits = 15;

// Output layers, each TileParams.outputSize's width*height vec4 holding the
// SUM over samples (w of the colour layers: the samples taken).
// Colour components ambient+diffuse+specular+reflection+transmission add up
// to kAovColor exactly (each ray's contribution is tagged with the component
// of the primary hit that spawned it).
WHITTED_CONST uint kAovColor = 0;
WHITTED_CONST uint kAovAmbient = 1;
WHITTED_CONST uint kAovDiffuse = 2;
WHITTED_CONST uint kAovSpecular = 3;
WHITTED_CONST uint kAovReflection = 4;
WHITTED_CONST uint kAovTransmission = 5;
WHITTED_CONST uint kAovNormal = 6;     // xyz shading normal, w hit mask
WHITTED_CONST uint kAovCoefs0 = 7;     // ka, kd, ks, depth (primary hit)
WHITTED_CONST uint kAovCoefs1 = 8;     // kr, kt, ior, hit mask
WHITTED_CONST uint kAovCount = 9;
// Reflection and transmission split by ray-tree depth (README "Auxiliary
// images"), only in a render that asks for them: with B bounces
// (FrameParams.options >> kOptionAovBouncesShift), layer kAovCount + k - 1
// sums what rays at depth k of the primary hit's reflection subtree bring
// back and kAovCount + B + k - 1 the same for transmission, k = 1 .. B; the
// last of each holds every depth >= B, so they add up to kAovReflection and
// kAovTransmission. w: the samples taken, as in the colour layers.
WHITTED_CONST uint kAovBouncesMax = 16;
// The object and material masks (README "Auxiliary images"), only in a
// render that asks for them (kOptionWriteIds): one layer after the split
// ones whose x and y hold, as uint bits, the object and material index of
// what the pixel-centre ray hits first (kNoObject: nothing), written once by
// the pixel's first dispatch and never summed or divided by the host.

// Capacity of the explicit ray stack; a Whitted tree traversed depth first
// never holds more than maxDepth + 1 pending rays.
WHITTED_CONST uint kRayStackSize = 24;
WHITTED_CONST uint kMaxDepthLimit = kRayStackSize - 2;

// The largest image side (scene files, --width/--height, textures) and the
// most samples a pixel may take: every check of these limits uses these.
WHITTED_CONST uint kMaxImageSide = 16384;
WHITTED_CONST uint kMaxSamplesPerPixel = 65536;

// Capacity of the BVH traversal stack; the builder limits the binary
// tree's depth to kBvhStackSize - 1.
WHITTED_CONST uint kBvhStackSize = 48;
// The shader walks the tree collapsed to up to kBvhWidth children a node
// (host/accel/bvh.h, collapseToWide), which stops opening children where a
// walk could stack more than kBvhWideStackSize entries.
WHITTED_CONST uint kBvhWideStackSize = kBvhStackSize * 3 / 2;
WHITTED_CONST uint kBvhWidth = 8;
// A leaf holds 1 to kBvhMaxLeafSize primitives (the builder's bound).
WHITTED_CONST uint kBvhMaxLeafSize = 8;
// A walk's stack entry: a wide node's index, or kBvhLeafEntry | (count - 1)
// << kBvhLeafCountShift | first primitive for a leaf; so a tree has at most
// kBvhMaxNodes nodes over kBvhMaxPrimitives primitives.
WHITTED_CONST uint kBvhLeafEntry = 0x80000000u;
WHITTED_CONST uint kBvhLeafCountShift = 28u;
WHITTED_CONST uint kBvhMaxPrimitives = 1u << kBvhLeafCountShift;
WHITTED_CONST uint kBvhMaxNodes = kBvhLeafEntry;

// Specialization constant ids (shaders/shapes/primitive.glsl, intersect.glsl).
WHITTED_CONST uint kSpecShapeMask = 0;     // bit (1 << kShape*) set: the BVH holds that shape
WHITTED_CONST uint kSpecTransparency = 1;  // nonzero: some material has kt > 0
WHITTED_CONST uint kSpecListShapeMask = 2; // as kSpecShapeMask, for the primitives outside the BVH
// The distribution effects a scene uses (kDistribution* bits; unset: all of them), so that a scene without them
// compiles none of their sampling: a lens (FrameParams.apertureRadius > 0), glossy materials (kMaterialGlossy),
// area lights (kLightRect, or radius > 0).
WHITTED_CONST uint kSpecDistribution = 4;
WHITTED_CONST uint kDistributionLens = 1u;
WHITTED_CONST uint kDistributionGloss = 2u;
WHITTED_CONST uint kDistributionAreaLights = 4u;
// The shading features a scene uses (kFeature* bits; unset: all of them), so that a scene without them compiles
// none of their code (shaders/material.glsl): Fresnel (kMaterialFresnel), absorption, solid checkers, smooth mesh
// triangles (kTriangleSmooth), spot and directional lights, inverse-square falloff.
WHITTED_CONST uint kSpecFeatures = 5;
WHITTED_CONST uint kFeatureFresnel = 1u;
WHITTED_CONST uint kFeatureAbsorption = 2u;
WHITTED_CONST uint kFeatureChecker = 4u;
WHITTED_CONST uint kFeatureSmoothTriangles = 8u;
WHITTED_CONST uint kFeatureSpotLights = 16u;
WHITTED_CONST uint kFeatureDirectionalLights = 32u;
WHITTED_CONST uint kFeatureFalloff = 64u;
// An <environment> (EnvironmentParams.kind != kEnvironmentNone; shaders/environment.glsl), and its light
// (EnvironmentParams.shadowSamples > 0): a scene without one compiles neither.
WHITTED_CONST uint kFeatureEnvironment = 128u;
WHITTED_CONST uint kFeatureEnvironmentLight = 256u;
WHITTED_CONST uint kFeatureAll = 511u;

// FrameParams.options bit flags.
WHITTED_CONST uint kOptionWriteAovs = 1u;
// Bits 8..15: the number B of split reflection/transmission layers (0: none).
WHITTED_CONST uint kOptionAovBouncesShift = 8u;
WHITTED_CONST uint kOptionTextureLodZero = 2u;  // sample textures at mip level 0 (tests of the ray-cone LOD)
WHITTED_CONST uint kOptionWriteIds = 4u;        // write the id layer (object and material masks)

// One geometric primitive. Its words a, b, c and extra0/extra1 mean
// something different for each shape, so they are read and written only
// through the named accessors below (each shape's functions in
// shaders/shapes/ take what they return):
//   sphere:   a = (centre, radius)
//   cylinder: a = (bottom cap centre, radius), b = (unit axis, height)
//   plane:    a = (point, 0), b = (unit normal, 0)
//   triangle: a, b, c = vertices (xyz); w = vertex normals when smooth,
//             extra0 = kTriangleSmooth then
//   box:      a = min corner, b = max corner
//   csg:      a.xyz, b.xyz = bounds; a.w, b.w = uint bits of the first leaf
//             primitive and the leaf count; extra0, extra1 = its program's
//             first CsgNode and node count (host/shapes/csg.cpp)
//   extra1 of every other primitive (csg leaves too, which are what a hit
//   reports): the index of its object in the scene's object list, the
//   object_id mask (host/render/gpu_scene.cpp).
// Primitives in the BVH come first, in leaf order; the unbounded ones
// (planes) follow and are tested one by one.
struct Primitive {
    vec4 a WHITTED_ZERO;
    vec4 b WHITTED_ZERO;
    vec4 c WHITTED_ZERO;
    uint shape WHITTED_ZERO;     // kShape* tag
    uint material WHITTED_ZERO;  // index into Material[]
    uint extra0 WHITTED_ZERO;
    uint extra1 WHITTED_ZERO;
};

WHITTED_FUNCTION vec3 sphereCenter(Primitive p) { return vec3(p.a); }
WHITTED_FUNCTION float sphereRadius(Primitive p) { return p.a.w; }
WHITTED_FUNCTION vec3 cylinderBase(Primitive p) { return vec3(p.a); }  // the bottom cap's centre
WHITTED_FUNCTION float cylinderRadius(Primitive p) { return p.a.w; }
WHITTED_FUNCTION vec3 cylinderAxis(Primitive p) { return vec3(p.b); }  // unit length
WHITTED_FUNCTION float cylinderHeight(Primitive p) { return p.b.w; }
WHITTED_FUNCTION vec3 planePoint(Primitive p) { return vec3(p.a); }
WHITTED_FUNCTION vec3 planeUnitNormal(Primitive p) { return vec3(p.b); }
WHITTED_FUNCTION vec3 triangleV0(Primitive p) { return vec3(p.a); }
WHITTED_FUNCTION vec3 triangleV1(Primitive p) { return vec3(p.b); }
WHITTED_FUNCTION vec3 triangleV2(Primitive p) { return vec3(p.c); }
// Whether a triangle has vertex normals (a smooth mesh triangle), and the
// three of them, octahedral-encoded.
WHITTED_FUNCTION bool triangleSmooth(Primitive p) { return p.extra0 == kTriangleSmooth; }
WHITTED_FUNCTION uvec3 triangleNormals(Primitive p) {
    return uvec3(floatBitsToUint(p.a.w), floatBitsToUint(p.b.w), floatBitsToUint(p.c.w));
}
WHITTED_FUNCTION vec3 boxMin(Primitive p) { return vec3(p.a); }
WHITTED_FUNCTION vec3 boxMax(Primitive p) { return vec3(p.b); }
WHITTED_FUNCTION vec3 csgBoundsMin(Primitive p) { return vec3(p.a); }
WHITTED_FUNCTION vec3 csgBoundsMax(Primitive p) { return vec3(p.b); }
// A csg object's leaf primitives (first, count) and its program's CsgNodes (first, count).
WHITTED_FUNCTION uvec2 csgLeaves(Primitive p) { return uvec2(floatBitsToUint(p.a.w), floatBitsToUint(p.b.w)); }
WHITTED_FUNCTION uvec2 csgProgram(Primitive p) { return uvec2(p.extra0, p.extra1); }
// A point of every shape: a sphere's centre, a cylinder's base, a plane's
// point, a triangle's first vertex, a box's or csg object's min corner.
WHITTED_FUNCTION vec3 primitiveAnchor(Primitive p) { return vec3(p.a); }
// The object a primitive (not a csg object) belongs to, as the object_id mask numbers it.
WHITTED_FUNCTION uint primitiveObject(Primitive p) { return p.extra1; }
// An instance's stand-in (kShapeInstance): its world box and its index into InstanceRecord[].
WHITTED_FUNCTION uint primitiveInstance(Primitive p) { return p.extra0; }

#ifdef __cplusplus
// The host packs each shape through these (host/shapes/*.cpp).
inline Primitive spherePrimitive(vec3 center, float radius, uint material) {
    return {.a = vec4(center, radius), .shape = kShapeSphere, .material = material};
}
inline Primitive cylinderPrimitive(vec3 base, vec3 unitAxis, float radius, float height, uint material) {
    return {.a = vec4(base, radius), .b = vec4(unitAxis, height), .shape = kShapeCylinder, .material = material};
}
inline Primitive planePrimitive(vec3 point, vec3 unitNormal, uint material) {
    return {.a = vec4(point, 0.0f), .b = vec4(unitNormal, 0.0f), .shape = kShapePlane, .material = material};
}
inline Primitive trianglePrimitive(vec3 v0, vec3 v1, vec3 v2, uint material) {
    return {.a = vec4(v0, 0.0f), .b = vec4(v1, 0.0f), .c = vec4(v2, 0.0f), .shape = kShapeTriangle,
            .material = material};
}
// Makes triangle p smooth with the three octahedral-encoded vertex normals.
inline void setTriangleNormals(Primitive& p, uvec3 normals) {
    p.a.w = glm::uintBitsToFloat(normals.x);
    p.b.w = glm::uintBitsToFloat(normals.y);
    p.c.w = glm::uintBitsToFloat(normals.z);
    p.extra0 = kTriangleSmooth;
}
inline Primitive boxPrimitive(vec3 min, vec3 max, uint material) {
    return {.a = vec4(min, 0.0f), .b = vec4(max, 0.0f), .shape = kShapeBox, .material = material};
}
inline Primitive csgPrimitive(vec3 boundsMin, vec3 boundsMax, uvec2 leaves, uvec2 program, uint material) {
    return {.a = vec4(boundsMin, glm::uintBitsToFloat(leaves.x)),
            .b = vec4(boundsMax, glm::uintBitsToFloat(leaves.y)),
            .shape = kShapeCsg,
            .material = material,
            .extra0 = program.x,
            .extra1 = program.y};
}
// Moves a csg object's first leaf to `first` (the leaves' place in the whole primitive array).
inline void setCsgFirstLeaf(Primitive& p, uint first) { p.a.w = glm::uintBitsToFloat(first); }
inline void setPrimitiveObject(Primitive& p, uint object) { p.extra1 = object; }
inline Primitive instancePrimitive(vec3 boundsMin, vec3 boundsMax, uint instance, uint object) {
    return {.a = vec4(boundsMin, 0.0f), .b = vec4(boundsMax, 0.0f), .shape = kShapeInstance, .extra0 = instance,
            .extra1 = object};
}
#endif

// Material.flags bits.
WHITTED_CONST uint kMaterialFresnel = 1u;       // kr is F0 of Schlick's approximation
WHITTED_CONST uint kMaterialAmbientColor = 2u;  // the ambient term takes ambientColor instead of Cd
WHITTED_CONST uint kMaterialGlossy = 4u;        // roughness > 0: reflected and refracted rays sample a lobe of glossExponent

// Phong + Whitted material.
struct Material {
    vec3 diffuse WHITTED_ZERO;         // Cd
    float pad0 WHITTED_ZERO;
    vec3 specular WHITTED_ZERO;        // Cs
    float pad1 WHITTED_ZERO;
    float ka WHITTED_ZERO;
    float kd WHITTED_ZERO;
    float ks WHITTED_ZERO;
    float shininess WHITTED_ZERO;
    float kr WHITTED_ZERO;
    float kt WHITTED_ZERO;
    float ior WHITTED_ZERO;
    uint flags WHITTED_ZERO;           // kMaterial* bits
    vec3 checkerColor WHITTED_ZERO;
    float checkerSize WHITTED_ZERO;    // 0: no checker
    vec3 checkerOrigin WHITTED_ZERO;   // the object's position, where a cell starts
    float pad3 WHITTED_ZERO;
    vec3 absorption WHITTED_ZERO;      // sigma rgb per unit length inside the object
    float pad4 WHITTED_ZERO;
    uint diffuseTexture WHITTED_ZERO;  // index into the kBindingTextures array, or kNoTexture
    uint normalMap WHITTED_ZERO;       // likewise
    uint emissionTexture WHITTED_ZERO; // likewise: multiplies emission
    uint roughnessTexture WHITTED_ZERO; // likewise: its green channel multiplies roughness (kMaterialGlossy)
    float textureScale WHITTED_ZERO;   // planes: world units per repeat
    float normalStrength WHITTED_ZERO;
    float glossExponent WHITTED_ZERO;  // kMaterialGlossy: the Phong exponent of the reflection and refraction lobes
    float roughness WHITTED_ZERO;      // kMaterialGlossy with a roughnessTexture: the roughness it multiplies
    vec3 transmissionColor WHITTED_ZERO;  // tints refracted light and the shadow filter (white: none)
    float pad9 WHITTED_ZERO;
    vec3 emission WHITTED_ZERO;           // added where a ray hits the surface
    float pad10 WHITTED_ZERO;
    vec3 ambientColor WHITTED_ZERO;       // the ambient term's colour with kMaterialAmbientColor, else Cd
    float pad11 WHITTED_ZERO;
};

// Per-primitive surface attributes (FrameParams.attributeAddress), in the
// primitives' order; present when some mesh triangle needs them (a textured
// mesh). Triangles: the (u, v) of its three vertices. Other shapes compute
// their (u, v) from the hit point (shaders/shapes/*.glsl) and ignore theirs.
// Mesh triangles from a model file with tangents: tangents the three vertex
// tangents (octahedral, as vertex normals), hasTangents 1; else 0 and normal
// maps use dp/du (shaders/texture.glsl).
struct SurfaceAttributes {
    vec2 uv0 WHITTED_ZERO;
    vec2 uv1 WHITTED_ZERO;
    vec2 uv2 WHITTED_ZERO;
    vec2 pad0 WHITTED_ZERO;
    uvec3 tangents WHITTED_ZERO;
    uint hasTangents WHITTED_ZERO;
};

// Light.type and Light.falloff (scenes/README.md "Lights").
WHITTED_CONST uint kLightPoint = 0u;
WHITTED_CONST uint kLightSpot = 1u;
WHITTED_CONST uint kLightDirectional = 2u;  // no position: its shadow rays go to infinity
WHITTED_CONST uint kLightRect = 3u;         // a rectangle: position +- u/2 +- v/2
WHITTED_CONST uint kFalloffNone = 0u;
WHITTED_CONST uint kFalloffInverseSquare = 1u;

// A light: what arrives at distance d is color (the scene's colour times
// its intensity), divided by d^2 with kFalloffInverseSquare; a spot scales
// it by saturate((cos theta - cosOuter) / (cosInner - cosOuter))^2, theta
// the angle from its direction (KHR_lights_punctual). An area light (a
// point or spot with radius > 0: a sphere; kLightRect) is shadowSamples
// point lights of that colour at points sampled on it, averaged
// (shaders/shading.glsl, sampleLightPoint).
struct Light {
    vec3 position WHITTED_ZERO;   // point, spot and rect (its centre)
    uint type WHITTED_ZERO;       // kLight*
    vec3 color WHITTED_ZERO;      // colour times intensity
    uint falloff WHITTED_ZERO;    // kFalloff*
    vec3 direction WHITTED_ZERO;  // spot and directional: unit, the way the light travels
    float cosInner WHITTED_ZERO;  // spot: cosines of the inner and outer cone angles
    float cosOuter WHITTED_ZERO;
    float radius WHITTED_ZERO;         // point and spot: the sphere's radius, 0 for a point
    uint shadowSamples WHITTED_ZERO;   // shadow rays per camera sample, >= 1
    uint twoSided WHITTED_ZERO;        // rect: 1 when it shines from both faces
    vec3 u WHITTED_ZERO;               // rect: the full edge vectors; it faces u x v
    float pad0 WHITTED_ZERO;
    vec3 v WHITTED_ZERO;
    float pad1 WHITTED_ZERO;
};

// A node of the compressed 8-wide BVH the shader walks (host/accel/bvh.h,
// collapseToWide; Ylitie, Karras and Laine 2017): 80 bytes for up to eight
// children. Child k's box is quantised to 8 bits a bound on the node's grid:
// on axis a, lo = origin[a] + q * 2^(e[a] - 127) for its lo byte q (the same
// for hi), e[a] byte a of `exponents`. The host rounds lo down and hi up, so
// the decoded box contains the child's exact box (the product is exact: a
// power of two times 8 bits). Byte k of childInfo0 (children 0-3) and
// childInfo1 (4-7): 0 for no child, kBvhChildInner | r for an inner child (node
// childBase + r), else the leaf's primitive count; a node's leaf children
// hold consecutive primitives from primitiveBase, in slot order. quantX.x
// holds the lo bytes of children 0-3 on x, .y those of 4-7, .z and .w the hi
// bytes (quantY and quantZ likewise).
WHITTED_CONST uint kBvhChildInner = 0x80u;
struct BvhNode {
    vec3 origin WHITTED_ZERO;
    uint exponents WHITTED_ZERO;
    uint childBase WHITTED_ZERO;
    uint primitiveBase WHITTED_ZERO;
    uint childInfo0 WHITTED_ZERO;
    uint childInfo1 WHITTED_ZERO;
    uvec4 quantX WHITTED_ZERO;
    uvec4 quantY WHITTED_ZERO;
    uvec4 quantZ WHITTED_ZERO;
};

// One instruction of a csg object's postfix program (host/shapes/csg.cpp):
// (kCsgLeaf, leaf slot) pushes whether the point is inside that leaf; an
// operation pops two values and pushes their combination. An n-ary node of
// the scene file becomes its first child, then each further child followed
// by the operation (a left fold).
struct CsgNode {
    uint op WHITTED_ZERO;    // kCsgLeaf or kCsg* operation
    uint leaf WHITTED_ZERO;  // kCsgLeaf: the leaf's slot among the object's leaves
    uint pad0 WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
};

// One instance of a prototype (Scene::instances; shaders/instance.glsl): its
// affine transforms as the rows of 3x4 matrices (xyz the linear part, w the
// translation), the root of its prototype's tree in BvhNode[] (the
// prototype's nodes and primitives follow the scene's own), the object id
// the masks give it, a material replacing its prototype's, or
// kNoMaterialOverride, and where the prototype's primitives start. A negative determinant of the linear part (a
// mirroring instance) needs nothing special: normals go through the inverse
// transpose, which keeps a closed mesh's outward side outward, as the
// loader's flattened copy keeps it by turning the winding over.
WHITTED_CONST uint kNoMaterialOverride = 0xffffffffu;
WHITTED_CONST uint kNoInstance = 0xffffffffu;
struct InstanceRecord {
    vec4 worldFromObject0 WHITTED_ZERO;
    vec4 worldFromObject1 WHITTED_ZERO;
    vec4 worldFromObject2 WHITTED_ZERO;
    vec4 objectFromWorld0 WHITTED_ZERO;
    vec4 objectFromWorld1 WHITTED_ZERO;
    vec4 objectFromWorld2 WHITTED_ZERO;
    uint rootNode WHITTED_ZERO;
    uint object WHITTED_ZERO;    // the object_id mask's index
    uint material WHITTED_ZERO;  // kNoMaterialOverride: the prototype's own
    uint firstPrimitive WHITTED_ZERO;  // the prototype's first in Primitive[] (ray queries: its BLAS's primitive 0)
};

// FrameParams.projection: how camera rays leave the eye (shaders/camera.glsl).
WHITTED_CONST uint kProjectionPerspective = 0u;
WHITTED_CONST uint kProjectionOrthographic = 1u;

// EnvironmentParams.kind (scenes/README.md "Environment").
WHITTED_CONST uint kEnvironmentNone = 0u;
WHITTED_CONST uint kEnvironmentColor = 1u;
WHITTED_CONST uint kEnvironmentGradient = 2u;
WHITTED_CONST uint kEnvironmentImage = 3u;

// The world around the scene (shaders/environment.glsl): what a ray that leaves the scene sees, and the light
// it gives. Colours are already times the intensity. The image's importance-sampling distribution
// (pbrt-v4's PiecewiseConstant2D over luminance x sin theta, host/render/gpu_environment.cpp) is a float
// array at distributionAddress: the marginal CDF over the image's rows (height + 1 values), then each row's
// conditional CDF over its columns (width + 1 values a row).
struct EnvironmentParams {
    vec3 color WHITTED_ZERO;           // kEnvironmentColor: the colour; kEnvironmentGradient: the zenith's
    uint kind WHITTED_ZERO;            // kEnvironment*
    vec3 horizon WHITTED_ZERO;         // gradient: the horizon's colour
    uint image WHITTED_ZERO;           // kEnvironmentImage: its slot in the kBindingTextures array
    vec3 ground WHITTED_ZERO;          // gradient: the nadir's colour
    float rotation WHITTED_ZERO;       // radians about +y (counter-clockwise seen from above)
    float intensity WHITTED_ZERO;      // kEnvironmentImage: multiplies the texels
    uint visible WHITTED_ZERO;         // 0: camera rays do not see it (mirrors, glass and lighting still do)
    uint shadowSamples WHITTED_ZERO;   // its light's shadow rays per camera sample; 0: it lights nothing
    uint pad0 WHITTED_ZERO;
    uvec2 distributionAddress WHITTED_ZERO;  // kEnvironmentImage: float[], see above
    uvec2 imageSize WHITTED_ZERO;            // kEnvironmentImage: the distribution's width and height
};

// Per-render constants (uniform buffer). The addresses are device addresses
// as (low, high) words.
struct FrameParams {
    vec3 eye WHITTED_ZERO;                 // camera position (orthographic: the window's centre)
    uint projection WHITTED_ZERO;          // kProjection*
    vec3 forward WHITTED_ZERO;             // unit view direction
    float apertureRadius WHITTED_ZERO;     // thin lens radius (shaders/camera.glsl); 0: pinhole
    vec3 right WHITTED_ZERO;               // image right, scaled by tan(fov/2) * aspect (orthographic: half the window's width)
    float focusDistance WHITTED_ZERO;      // with a lens: the plane of focus's distance along the unit view axis
    vec3 up WHITTED_ZERO;                  // image up, scaled by tan(fov/2) (orthographic: half the window's height)
    float pad3 WHITTED_ZERO;
    vec3 ambientLight WHITTED_ZERO;        // A
    float pad4 WHITTED_ZERO;
    uint width WHITTED_ZERO;
    uint height WHITTED_ZERO;
    uint primitiveCount WHITTED_ZERO;
    uint lightCount WHITTED_ZERO;
    uint samplesPerPixel WHITTED_ZERO;
    uint maxDepth WHITTED_ZERO;
    uint options WHITTED_ZERO;             // kOption* flags
    uint seed WHITTED_ZERO;
    uint bvhNodeCount WHITTED_ZERO;
    uint firstListPrimitive WHITTED_ZERO;  // the primitives outside the BVH (planes): first and count
    uint listPrimitiveCount WHITTED_ZERO;
    uint pad5 WHITTED_ZERO;
    uvec2 primitiveAddress WHITTED_ZERO;   // Primitive[]
    uvec2 bvhNodeAddress WHITTED_ZERO;     // BvhNode[]
    uvec2 materialAddress WHITTED_ZERO;    // Material[]
    uvec2 lightAddress WHITTED_ZERO;       // Light[]
    uvec2 csgNodeAddress WHITTED_ZERO;     // CsgNode[] (CSG trees)
    uvec2 attributeAddress WHITTED_ZERO;   // SurfaceAttributes[] (UVs, tangents), 0 when none
    // The per-pixel buffers the tracer writes and reads (shaders/scene.glsl), by address as the scene's arrays:
    uvec2 outputAddress WHITTED_ZERO;       // vec4[]: the output layers' sums
    uvec2 pixelListAddress WHITTED_ZERO;    // uint[]: the pixels of a list dispatch
    uvec2 guideAddress WHITTED_ZERO;        // uvec4[]: the adaptive guide
    uvec2 sampleStatsAddress WHITTED_ZERO;  // uvec4[]: the sample statistics of the list's pixels
    EnvironmentParams environment WHITTED_ZERO;  // kind kEnvironmentNone: the background is black
    uvec2 instanceAddress WHITTED_ZERO;  // InstanceRecord[], 0 when the scene has no instances
    uvec2 pad6 WHITTED_ZERO;
};

// Object id of a sample that hit nothing.
WHITTED_CONST uint kNoObject = 0xffffffffu;

// Integer hash (Jarzynski and Olano, "Hash Functions for GPU Rendering",
// JCGT 2020: pcg): a pixel's sample pattern seed (shaders/sampling.glsl) and
// a mask id's colour (display_types.h, idColorRgb8).
WHITTED_FUNCTION uint hashPcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#endif

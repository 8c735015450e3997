// GPU data layout shared by the C++ host and the GLSL shaders: structs,
// binding numbers, AOV layers and the work-group size are declared once here
// (the nvpro-samples host_device.h pattern). Every field has a name. The
// structs are laid out so that std430 (std140 for FrameParams) and C++ agree
// without GL_EXT_scalar_block_layout: each 16 bytes hold a vec4, a vec3 and
// a 4-byte scalar, two vec2s or four scalars, with explicit pad fields where
// a slot is unused. The host side static_asserts every size and offset in
// host/render/gpu_scene.cpp.
#ifndef WHITTED_DEVICE_TYPES_H
#define WHITTED_DEVICE_TYPES_H

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
#define WHITTED_CONST inline constexpr
// Every field of a struct starts at zero on the host, so a designated
// initializer names only the fields it sets.
#define WHITTED_ZERO = {}
#else
#define WHITTED_CONST const
#define WHITTED_ZERO
#endif

WHITTED_CONST uint kWorkgroupSize = 8;  // 8x8 invocations, one pixel each

// Descriptor bindings of the single descriptor set. The shader reads the
// scene's arrays through the device addresses in FrameParams
// (shaders/scene.glsl); the storage-buffer variant reads them through
// bindings kBindingBvhNodeBuffer..kBindingLightBuffer below.
WHITTED_CONST uint kBindingParams = 0;    // uniform FrameParams
WHITTED_CONST uint kBindingOutput = 4;    // vec4[kAovCount * TileParams.outputSize pixels]
WHITTED_CONST uint kBindingCounters = 5;  // RayCounters
// Adaptive anti-aliasing (host/render/adaptive.*): the pixels a refinement
// pass traces, the first pass's per-pixel guide, per-entry sample statistics.
WHITTED_CONST uint kBindingPixelList = 7;   // uint[]: x | y << 16
WHITTED_CONST uint kBindingGuide = 8;       // uvec4[] over TileParams.guideSize: display colour bits, object id
WHITTED_CONST uint kBindingSampleStats = 9; // uvec4[2 * entries]: min colour bits + object, max colour bits + mixed
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
// The auxiliary outputs a render may ask for (FrameParams.options & (kOptionWriteAovs | kOptionWriteIds)), so that
// a render without them compiles none of their code (shaders/whitted.comp; unset: all of them).
WHITTED_CONST uint kSpecOutputOptions = 3;
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
WHITTED_CONST uint kFeatureAll = 127u;

// FrameParams.options bit flags.
WHITTED_CONST uint kOptionWriteAovs = 1u;
// Bits 8..15: the number B of split reflection/transmission layers (0: none).
WHITTED_CONST uint kOptionAovBouncesShift = 8u;
WHITTED_CONST uint kOptionTextureLodZero = 2u;  // sample textures at mip level 0 (tests of the ray-cone LOD)
WHITTED_CONST uint kOptionWriteIds = 4u;        // write the id layer (object and material masks)

// One geometric primitive. Meaning of a, b, c by shape (each shape's
// functions in shaders/shapes/ name them):
//   sphere:   a = (centre, radius)
//   cylinder: a = (bottom cap centre, radius), b = (unit axis, height)
//   plane:    a = (point, 0), b = (unit normal, 0)
//   triangle: a, b, c = vertices (xyz); w = vertex normals when smooth
//   box:      a = min corner, b = max corner
//   csg:      a.xyz, b.xyz = bounds; a.w, b.w = uint bits of the first leaf
//             primitive and the leaf count (host/shapes/csg.cpp)
// Primitives in the BVH come first, in leaf order; the unbounded ones
// (planes) follow and are tested one by one.
struct Primitive {
    vec4 a WHITTED_ZERO;
    vec4 b WHITTED_ZERO;
    vec4 c WHITTED_ZERO;
    uint shape WHITTED_ZERO;     // kShape* tag
    uint material WHITTED_ZERO;  // index into Material[]
    uint extra0 WHITTED_ZERO;    // triangle: kTriangleSmooth or 0; csg: its program's first CsgNode
    // csg: its program's node count; every other primitive (csg leaves
    // too, which are what a hit reports): the index of its object in the
    // scene's object list, the object_id mask (host/render/gpu_scene.cpp)
    uint extra1 WHITTED_ZERO;
};

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

// FrameParams.projection: how camera rays leave the eye (shaders/camera.glsl).
WHITTED_CONST uint kProjectionPerspective = 0u;
WHITTED_CONST uint kProjectionOrthographic = 1u;

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
};

// TileParams.flags bits.
WHITTED_CONST uint kTileList = 1u;       // pixels from the pixel list (listFirst, listCount)
WHITTED_CONST uint kTileOverwrite = 2u;  // replace the pixels' sums (and statistics) instead of adding
WHITTED_CONST uint kTileGuide = 4u;      // write the guide (colour, object) of each pixel
WHITTED_CONST uint kTileStats = 8u;      // write the sample statistics of each list entry

// Entries of the pixel list traced by one work group in list mode.
WHITTED_CONST uint kListGroupSize = kWorkgroupSize * kWorkgroupSize;
// Object id of a sample that hit nothing.
WHITTED_CONST uint kNoObject = 0xffffffffu;

// Per-dispatch constants (push constants): which pixels, which samples of
// which pattern, and where the output layers and guide sit in the image.
struct TileParams {
    uvec2 tileOrigin WHITTED_ZERO;    // rect mode: the first pixel of the tile
    uvec2 tileSize WHITTED_ZERO;      // rect mode: its width and height
    uint firstSample WHITTED_ZERO;    // index of the first sample
    uint sampleCount WHITTED_ZERO;
    uint patternSize WHITTED_ZERO;    // n of the n x n sample pattern
    uint flags WHITTED_ZERO;          // kTile* bits
    uvec2 outputOrigin WHITTED_ZERO;  // the first pixel of the pixels the output layers hold
    uvec2 outputSize WHITTED_ZERO;    // their width and height
    uvec2 guideOrigin WHITTED_ZERO;   // likewise for the guide
    uvec2 guideSize WHITTED_ZERO;
    uint listFirst WHITTED_ZERO;      // list mode: the first entry of the pixel list and the count
    uint listCount WHITTED_ZERO;
    // The ray-tree build (-DWHITTED_RAY_TREE, shaders/ray_tree.glsl) only:
    // the device address of the RayTreeRecord it fills; unread otherwise.
    uvec2 rayTreeAddress WHITTED_ZERO;
};

// Rays traced, counted by the shader (reset before each dispatch).
struct RayCounters {
    uint primary WHITTED_ZERO;
    uint shadow WHITTED_ZERO;
    uint secondary WHITTED_ZERO;
    uint pad WHITTED_ZERO;
};

// ---- The ray-tree inspector (shaders/ray_tree.glsl, host/render/ray_tree.h) ----
// The build of shaders/whitted.comp with -DWHITTED_RAY_TREE records every
// ray of one pixel's centre sample into a RayTreeRecord (at
// TileParams.rayTreeAddress): its rays in the order they are traced, the
// shadow rays of each and the surfaces each shadow ray crosses. What does not
// fit is counted in RayTreeRecord.dropped, and so is every ray and shadow ray
// of a dropped ray's subtree (left out); a record with dropped > 0 is not
// fully recorded, and says so.
WHITTED_CONST uint kRayTreeMaxRays = 256;
WHITTED_CONST uint kRayTreeMaxShadowRays = 1024;
WHITTED_CONST uint kRayTreeMaxCrossings = 2048;

// RayTreeRay.kind.
WHITTED_CONST uint kRayCamera = 0;
WHITTED_CONST uint kRayReflection = 1;
WHITTED_CONST uint kRayRefraction = 2;
WHITTED_CONST uint kRayTotalInternal = 3;  // a reflection carrying the transmitted share too

// RayTreeShadowRay.outcome.
WHITTED_CONST uint kShadowLit = 0;       // nothing in the way
WHITTED_CONST uint kShadowBlocked = 1;   // an opaque surface (RayTreeShadowRay.blocker)
WHITTED_CONST uint kShadowFiltered = 2;  // only transparent surfaces, each filtering the light

// One ray. Its contribution to the pixel is weight * (ambient + diffuse +
// specular) as traceSamples adds it; diffuse and specular are the sums over
// its shadow rays' per-light terms. A ray that hits nothing has primitive
// kNoObject and brings nothing back (the background is black).
struct RayTreeRay {
    vec3 origin WHITTED_ZERO;
    uint kind WHITTED_ZERO;           // kRay*
    vec3 direction WHITTED_ZERO;
    uint depth WHITTED_ZERO;          // 0: the camera ray
    vec3 point WHITTED_ZERO;          // the hit point, origin + t * direction
    float t WHITTED_ZERO;
    vec3 normal WHITTED_ZERO;         // shading normal at the hit, facing the ray
    uint primitive WHITTED_ZERO;      // the primitive struck, kNoObject for a miss
    vec3 weight WHITTED_ZERO;         // the throughput that scales its local terms (after absorption)
    uint material WHITTED_ZERO;       // the object's material index (objects come first: the object index)
    vec3 ambient WHITTED_ZERO;
    uint shape WHITTED_ZERO;          // kShape* of the primitive struck
    vec3 diffuse WHITTED_ZERO;
    uint frontFace WHITTED_ZERO;      // 1: the outside of the surface was hit
    vec3 specular WHITTED_ZERO;
    uint parent WHITTED_ZERO;         // index of the ray it was spawned by, kNoObject for the camera ray
    vec3 emission WHITTED_ZERO;       // zero until materials emit (issue 16)
    uint firstShadowRay WHITTED_ZERO; // its shadow rays: RayTreeRecord.shadowRays[first .. first + count)
    vec3 contribution WHITTED_ZERO;   // weight * (ambient + diffuse + specular + emission)
    uint shadowRayCount WHITTED_ZERO;
};

// One shadow ray from a hit point towards a light, traced by the renderer's
// own shadow walk (traceQuery, shaders/intersect.glsl), which goes
// on past an opaque surface in the recorder's build so that every surface in
// (0, distance) is found. visibility is what the walk returned;
// transmittance the product of the filters of the crossings it handed to
// the recorder (crossings[first .. first + count), in order along the ray,
// and those left out), 0 when one is opaque, which tests compare.
struct RayTreeShadowRay {
    vec3 origin WHITTED_ZERO;
    uint ray WHITTED_ZERO;            // the RayTreeRay it belongs to
    vec3 direction WHITTED_ZERO;      // unit, towards the light
    uint light WHITTED_ZERO;          // index into the scene's lights
    vec3 visibility WHITTED_ZERO;
    float distance WHITTED_ZERO;      // to the light
    vec3 diffuse WHITTED_ZERO;        // this light's share of the ray's diffuse term
    uint outcome WHITTED_ZERO;        // kShadow*
    vec3 specular WHITTED_ZERO;       // and of its specular term
    uint blocker WHITTED_ZERO;        // kShadowBlocked: the nearest opaque primitive, else kNoObject
    vec3 transmittance WHITTED_ZERO;  // the product of the crossings' filters times the absorption
    float blockerT WHITTED_ZERO;      // kShadowBlocked: its distance along the ray, else distance
    vec3 absorption WHITTED_ZERO;     // exp(-sigma * length inside), the Beer-Lambert share of transmittance
    uint firstCrossing WHITTED_ZERO;
    uint crossingCount WHITTED_ZERO;
    uint blockerMaterial WHITTED_ZERO;  // the blocker's material (object) index, else kNoObject
    uint droppedCrossings WHITTED_ZERO; // crossings found but not written (the record's crossings were full);
                                        // the outcome and transmittance still count them
    uint pad0 WHITTED_ZERO;
};

// A surface a shadow ray crosses, and the filter kt * mix(white, Cd, kd) * Ct
// it applies there (shadowCrossing, shaders/intersect.glsl). An opaque one
// is recorded too, with filter 0.
struct RayTreeCrossing {
    vec3 filterColour WHITTED_ZERO;
    float t WHITTED_ZERO;
    uint primitive WHITTED_ZERO;
    uint material WHITTED_ZERO;
    uint pad0 WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
};

struct RayTreeRecord {
    uint rayCount WHITTED_ZERO;
    uint shadowRayCount WHITTED_ZERO;
    uint crossingCount WHITTED_ZERO;
    uint dropped WHITTED_ZERO;        // rays, shadow rays or crossings that did not fit, or whose parent did not
    RayTreeRay rays[kRayTreeMaxRays];
    RayTreeShadowRay shadowRays[kRayTreeMaxShadowRays];
    RayTreeCrossing crossings[kRayTreeMaxCrossings];
};

// ---- Ray casting (Renderer.cast_rays in Python; host/render/ray_cast.h, shaders/cast_rays.comp) ----
// One invocation a ray, kCastGroupSize a work group, the rays and their hits
// in arrays at the device addresses of CastParams (push constants).
WHITTED_CONST uint kCastGroupSize = 64;

// A ray: its unit direction and the farthest hit distance along it.
struct CastRay {
    vec3 origin WHITTED_ZERO;
    float tMax WHITTED_ZERO;
    vec3 direction WHITTED_ZERO;  // unit length
    float pad0 WHITTED_ZERO;
};

// What a ray hits first: primitive kNoObject for a miss (the rest is then 0).
struct CastHit {
    vec3 normal WHITTED_ZERO;  // the unit geometric normal the intersection gives (outward; a triangle's winding)
    float t WHITTED_ZERO;      // the distance along the unit direction
    vec2 uv WHITTED_ZERO;      // the texture coordinates surfaceUv gives (shaders/texture.glsl)
    uint object WHITTED_ZERO;  // Primitive.extra1: the object's index, as the object_id mask has it
    uint primitive WHITTED_ZERO;  // the index into the Primitive array (the host maps it to its object's numbering)
};

struct CastParams {
    uvec2 rayAddress WHITTED_ZERO;  // CastRay[count]
    uvec2 hitAddress WHITTED_ZERO;  // CastHit[count]
    uint count WHITTED_ZERO;
    uint pad0 WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
    uint pad2 WHITTED_ZERO;
};

// ---- The live window (whitted view, shaders/display.comp) ----
// Bindings of the display pass: the renderer's output sums in, packed RGBA8 out.
WHITTED_CONST uint kBindingDisplayInput = 0;   // vec4[] sums, as kBindingOutput
WHITTED_CONST uint kBindingDisplayOutput = 1;  // uint[width * height], RGBA8

// What the display pass shows (DisplayParams.kind), like output/aov_output.
WHITTED_CONST uint kDisplayColor = 0;   // a colour layer: mean, clamp, sRGB
WHITTED_CONST uint kDisplayScalar = 1;  // one channel's mean times scalarScale
WHITTED_CONST uint kDisplayDepth = 2;   // m / (m + d), m = depthMedian
WHITTED_CONST uint kDisplayNormal = 3;  // n / 2 + 0.5
WHITTED_CONST uint kDisplayId = 4;      // the id in channel `channel` of the id layer, as idColorRgb8

// Push constants of the display pass.
struct DisplayParams {
    uint kind WHITTED_ZERO;     // kDisplay*
    uint layer WHITTED_ZERO;    // the output layer shown (kAov*)
    uint channel WHITTED_ZERO;  // kDisplayScalar: its channel
    uint pad0 WHITTED_ZERO;
    uint width WHITTED_ZERO;
    uint height WHITTED_ZERO;
    uint pad1 WHITTED_ZERO;
    uint pad2 WHITTED_ZERO;
    float scalarScale WHITTED_ZERO;
    float depthMedian WHITTED_ZERO;
    float exposure WHITTED_ZERO;  // kDisplayColor: the mean is scaled by 2^exposure before encoding (--exposure)
    float pad4 WHITTED_ZERO;
};

// The colour of a mask id in 8-bit files and the window: a fixed hash of the
// id (pcg, as hashPcg in shaders/sampling.glsl), each channel in 64..255 so
// that no object is as black as the background (kNoObject). Packed
// r | g << 8 | b << 16.
#ifdef __cplusplus
inline
#endif
uint idColorRgb8(uint id) {
    if (id == kNoObject) return 0u;
    uint state = id * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    word = (word >> 22u) ^ word;
    return (word & 0xbfbfbfu) + 0x404040u;
}

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#undef WHITTED_CONST
#undef WHITTED_ZERO
#endif

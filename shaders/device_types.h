// GPU data layout shared by the C++ host and the GLSL shaders: structs,
// binding numbers, AOV layers and the work-group size are declared once here
// (the nvpro-samples host_device.h pattern). Every struct is made of vec4 /
// uvec4 members only so std430 and C++ agree without hand padding; the host
// side static_asserts the sizes in host/render/gpu_scene.cpp.
#ifndef WHITTED_DEVICE_TYPES_H
#define WHITTED_DEVICE_TYPES_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace whitted::gpu {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
#define WHITTED_CONST inline constexpr
#else
#define WHITTED_CONST const
#endif

WHITTED_CONST uint kWorkgroupSize = 8;  // 8x8 invocations, one pixel each

// Descriptor bindings of the single descriptor set. The scene's arrays
// (Primitive[], BvhNode[], Material[], Light[]) have no binding: the shader
// reads them through the device addresses in FrameParams (shaders/scene.glsl).
WHITTED_CONST uint kBindingParams = 0;    // uniform FrameParams
WHITTED_CONST uint kBindingOutput = 4;    // vec4[kAovCount * outputRect pixels]
WHITTED_CONST uint kBindingCounters = 5;  // RayCounters
// Adaptive anti-aliasing (host/render/adaptive.*): the pixels a refinement
// pass traces, the first pass's per-pixel guide, per-entry sample statistics.
WHITTED_CONST uint kBindingPixelList = 7;   // uint[]: x | y << 16
WHITTED_CONST uint kBindingGuide = 8;       // uvec4[] over TileParams.guideRect: display colour bits, object id
WHITTED_CONST uint kBindingSampleStats = 9; // uvec4[2 * entries]: min colour bits + object, max colour bits + mixed
// The scene's top-level acceleration structure, in the ray-query variant of
// the shader only (shaders/ray_query.glsl).
WHITTED_CONST uint kBindingTlas = 10;
// The BVH nodes, primitives, materials and lights once more, as storage buffers: the shader
// variant built with -DWHITTED_SCENE_STORAGE_BUFFERS reads them from here, for
// drivers that load a storage buffer faster than a device address (Mesa
// 22.3's lavapipe; shaders/scene.glsl, shaders/bvh.glsl).
WHITTED_CONST uint kBindingBvhNodeBuffer = 12;  // BvhNode[] (the buffer at FrameParams.addresses0.zw)
WHITTED_CONST uint kBindingPrimitiveBuffer = 13;  // Primitive[] (the buffer at FrameParams.addresses0.xy)
WHITTED_CONST uint kBindingMaterialBuffer = 14;   // Material[] (FrameParams.addresses1.xy)
WHITTED_CONST uint kBindingLightBuffer = 15;      // Light[] (FrameParams.addresses1.zw)
// Image textures (diffuse and normal maps): an array of combined image
// samplers indexed by Material texture slots (shaders/texture.glsl).
WHITTED_CONST uint kBindingTextures = 11;
// Size of that array: unused entries hold a 1x1 dummy image.
WHITTED_CONST uint kMaxTextures = 32;
// Material.textureSlots entry of a material without that texture.
WHITTED_CONST uint kNoTexture = 0xffffffffu;

// Shape tags in Primitive.info.x.
WHITTED_CONST uint kShapeSphere = 0;
WHITTED_CONST uint kShapeCylinder = 1;
WHITTED_CONST uint kShapePlane = 2;
WHITTED_CONST uint kShapeTriangle = 3;
WHITTED_CONST uint kShapeBox = 4;
// A CSG object (shaders/shapes/csg.glsl): its tree lives in the CsgNode
// array; its leaves are ordinary primitives kept after the BVH's and the
// unbounded ones, so a hit reports the leaf primitive that was struck.
WHITTED_CONST uint kShapeCsg = 5;

// CSG limits (README "CSG"), set by the shader's fixed-size state in
// intersectCsg (shaders/shapes/csg.glsl): each leaf's span along the ray is
// held in arrays of kCsgMaxLeaves entries and the set of leaves a point is
// inside in one 32-bit mask; the tree is evaluated as a postfix program on a
// stack of one bit per entry, which a tree of nesting depth d (a csg whose
// children are all leaves has depth 1) fills to d + 1 <= kCsgStackSize bits.
// The loader refuses larger trees.
WHITTED_CONST uint kCsgMaxLeaves = 16;  // leaf shapes per top-level csg object
WHITTED_CONST uint kCsgStackSize = 9;
WHITTED_CONST uint kCsgMaxDepth = kCsgStackSize - 1;  // csg objects nested in each other

// CsgNode.info.x: a leaf (info.y = its slot among the object's leaves) or a
// boolean operation folding the two values on top of the stack into one.
WHITTED_CONST uint kCsgLeaf = 0;
WHITTED_CONST uint kCsgUnion = 1;
WHITTED_CONST uint kCsgIntersection = 2;
WHITTED_CONST uint kCsgDifference = 3;  // the lower value minus the top one

// Primitive.info.z of a triangle: kTriangleSmooth when a, b, c .w hold its
// vertex normals, octahedral-encoded (host/shapes/triangle.cpp), each
// coordinate in kOctahedralBits bits.
WHITTED_CONST uint kTriangleSmooth = 1;
WHITTED_CONST uint kOctahedralBits = 15;

// Output layers, each TileParams.outputRect's width*height vec4 holding the
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
// (FrameParams.options.z >> kOptionAovBouncesShift), layer kAovCount + k - 1
// sums what rays at depth k of the primary hit's reflection subtree bring
// back and kAovCount + B + k - 1 the same for transmission, k = 1 .. B; the
// last of each holds every depth >= B, so they add up to kAovReflection and
// kAovTransmission. w: the samples taken, as in the colour layers.
WHITTED_CONST uint kAovBouncesMax = 16;

// Capacity of the explicit ray stack; a Whitted tree traversed depth first
// never holds more than maxDepth + 1 pending rays.
WHITTED_CONST uint kRayStackSize = 24;
WHITTED_CONST uint kMaxDepthLimit = kRayStackSize - 2;

// The largest image side (scene files, --width/--height, textures) and the
// most samples a pixel may take: every check of these limits uses these.
WHITTED_CONST uint kMaxImageSide = 16384;
WHITTED_CONST uint kMaxSamplesPerPixel = 65536;

// Capacity of the BVH traversal stack; the builder limits the tree depth
// to fit.
WHITTED_CONST uint kBvhStackSize = 48;
// The shader walks the tree collapsed to 4 children a node
// (host/accel/bvh.h, collapseToWide): at most 3 entries pushed for every 2
// binary levels descended.
WHITTED_CONST uint kBvhWideStackSize = kBvhStackSize * 3 / 2;
// An inner node's lo.w: its first child slot in the low bits, its number
// of children (2 to 4) minus 2 above kBvhChildCountShift; so a tree has
// at most kBvhMaxNodes slots.
WHITTED_CONST uint kBvhChildCountShift = 29u;
WHITTED_CONST uint kBvhChildIndexMask = (1u << kBvhChildCountShift) - 1u;
WHITTED_CONST uint kBvhMaxNodes = 1u << kBvhChildCountShift;

// Specialization constant ids (shaders/shapes/primitive.glsl, intersect.glsl).
WHITTED_CONST uint kSpecShapeMask = 0;     // bit (1 << kShape*) set: the BVH holds that shape
WHITTED_CONST uint kSpecTransparency = 1;  // nonzero: some material has kt > 0
WHITTED_CONST uint kSpecListShapeMask = 2; // as kSpecShapeMask, for the primitives outside the BVH

// FrameParams.options.z bit flags.
WHITTED_CONST uint kOptionWriteAovs = 1u;
// Bits 8..15: the number B of split reflection/transmission layers (0: none).
WHITTED_CONST uint kOptionAovBouncesShift = 8u;
WHITTED_CONST uint kOptionTextureLodZero = 2u;  // sample textures at mip level 0 (tests of the ray-cone LOD)

// One geometric primitive. Meaning of a, b, c by shape:
//   sphere:   a = (centre, radius)
//   cylinder: a = (bottom cap centre, radius), b = (unit axis, height)
//   plane:    a = (point, 0), b = (unit normal, 0)
//   triangle: a, b, c = vertices (xyz); w = vertex normals when smooth
//   box:      a = min corner, b = max corner
//   csg:      a.xyz, b.xyz = bounds; a.w, b.w = uint bits of the first leaf
//             primitive and the leaf count; info.z, info.w = first CsgNode
//             and node count (host/shapes/csg.cpp)
// info = (shape tag, material index, kTriangleSmooth or 0, 0). Primitives in the BVH come first,
// in leaf order; the unbounded ones (planes) follow and are tested one by one.
struct Primitive {
    vec4 a;
    vec4 b;
    vec4 c;
    uvec4 info;
};

// Phong + Whitted material. diffuse/specular rgb are Cd/Cs.
struct Material {
    vec4 diffuse;
    vec4 specular;
    vec4 coefs0;         // ka, kd, ks, shininess
    vec4 coefs1;         // kr, kt, ior, 0
    vec4 checker;        // checker colour rgb, cell size (0: no checker)
    vec4 checkerOrigin;  // xyz: the object's position, where a cell starts
    vec4 absorption;     // sigma rgb per unit length inside the object, 0
    uvec4 textureSlots;  // diffuse texture, normal map (index into the kBindingTextures array, or kNoTexture), 0, 0
    vec4 textureParams;  // texture scale (planes: world units per repeat), normal strength, 0, 0
};

// Per-primitive surface attributes (FrameParams.addresses2.zw), in the
// primitives' order; present when some mesh triangle needs them (a textured
// mesh). Triangles: the (u, v) of its three vertices. Other shapes compute
// their (u, v) from the hit point (shaders/shapes/*.glsl) and ignore theirs.
// Mesh triangles from a model file with tangents: tangents.xyz the
// three vertex tangents (octahedral, as vertex normals), tangents.w 1; else
// tangents.w 0 and normal maps use dp/du (shaders/texture.glsl).
struct SurfaceAttributes {
    vec4 uv01;      // u0, v0, u1, v1
    vec4 uv2;       // u2, v2, 0, 0
    uvec4 tangents;
};

struct Light {
    vec4 position;
    vec4 color;
};

// A node of the flattened BVH (host/accel/bvh.h). lo/hi hold the bounds;
// the w components hold uint bits: an inner node has hi.w = 0 and its
// children in adjacent slots from lo.w (the builder's binary tree: two, at
// lo.w and lo.w + 1; the 4-wide tree the shader walks, collapseToWide: two
// to four, lo.w & kBvhChildIndexMask the first, (lo.w >> kBvhChildCountShift)
// + 2 their count); a leaf has hi.w = primitive count > 0 and its
// primitives at lo.w .. lo.w + count - 1.
struct BvhNode {
    vec4 lo;
    vec4 hi;
};

// One instruction of a csg object's postfix program (host/shapes/csg.cpp):
// info = (kCsgLeaf, leaf slot, 0, 0) pushes whether the point is inside that
// leaf; an operation pops two values and pushes their combination. An n-ary
// node of the scene file becomes its first child, then each further child
// followed by the operation (a left fold).
struct CsgNode {
    uvec4 info;
};

// Per-render constants (uniform buffer).
struct FrameParams {
    vec4 eye;           // camera position
    vec4 forward;       // unit view direction
    vec4 right;         // image right, scaled by tan(fov/2) * aspect
    vec4 up;            // image up, scaled by tan(fov/2)
    vec4 ambientLight;  // A
    uvec4 sizes;        // width, height, primitive count, light count
    uvec4 options;      // samples per pixel, max depth, flags, seed
    uvec4 accel;        // BVH node count, first and count of the primitives outside it (planes), 0
    uvec4 addresses0;   // device addresses (low, high words) of Primitive[] and BvhNode[]
    uvec4 addresses1;   // of Material[] and Light[]
    uvec4 addresses2;   // of CsgNode[] (CSG trees) and the per-primitive surface attributes (UVs, tangents)
};

// TileParams.samples.w bit flags.
WHITTED_CONST uint kTileList = 1u;       // pixels from the pixel list (tile.x first entry, tile.y count)
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
    uvec4 tile;        // rect mode: x0, y0, width, height; list mode: first entry, count, 0, 0
    uvec4 samples;     // first sample index, sample count, pattern size n, kTile* flags
    uvec4 outputRect;  // x0, y0, width, height of the pixels the output layers hold
    uvec4 guideRect;   // x0, y0, width, height of the pixels the guide holds
};

// Rays traced, counted by the shader (reset before each dispatch).
struct RayCounters {
    uint primary;
    uint shadow;
    uint secondary;
    uint pad;
};

// ---- The live window (whitted view, shaders/display.comp) ----
// Bindings of the display pass: the renderer's output sums in, packed RGBA8 out.
WHITTED_CONST uint kBindingDisplayInput = 0;   // vec4[] sums, as kBindingOutput
WHITTED_CONST uint kBindingDisplayOutput = 1;  // uint[width * height], RGBA8

// What the display pass shows (DisplayParams.view.x), like output/aov_output.
WHITTED_CONST uint kDisplayColor = 0;   // a colour layer: mean, clamp, sRGB
WHITTED_CONST uint kDisplayScalar = 1;  // one channel's mean times scale.x
WHITTED_CONST uint kDisplayDepth = 2;   // m / (m + d), m = scale.y
WHITTED_CONST uint kDisplayNormal = 3;  // n / 2 + 0.5

// Push constants of the display pass.
struct DisplayParams {
    uvec4 view;   // kind, layer, channel, 0
    uvec4 size;   // width, height, 0, 0
    vec4 scale;   // scalar scale, depth median, 0, 0
};

#ifdef __cplusplus
}  // namespace whitted::gpu
#endif
#undef WHITTED_CONST
#endif

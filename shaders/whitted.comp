#version 460
// Whitted ray tracing, one invocation per pixel of the current tile, all of
// the tile's samples in a loop. Recursion is replaced by an explicit stack of
// pending rays (depth-first), each carrying its throughput weight, its depth
// and the colour component of the primary hit it descends from.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require

#include "tracer_types.h"
#include "tracer_buffers.glsl"
#include "camera.glsl"
#include "color.glsl"
#include "sampling.glsl"
#include "shading.glsl"

layout(local_size_x = kWorkgroupSize, local_size_y = kWorkgroupSize, local_size_z = 1) in;

// The auxiliary outputs this pipeline can write (host/render/device_policy.cpp, specializationFor): a render
// without them leaves their code out of what the driver compiles.
layout(constant_id = kSpecOutputOptions) const uint kOutputOptions = kOptionWriteAovs | kOptionWriteIds;
const uint kWriteAovs = kOutputOptions & kOptionWriteAovs;
const uint kWriteIds = kOutputOptions & kOptionWriteIds;
// Nonzero when the render splits reflection and transmission by depth (--aov-bounces).
const uint kSplitBounces = kOutputOptions >> kOptionAovBouncesShift;

// PendingRay.component of a lens render's pinhole ray, traced for the auxiliary layers only.
const uint kPinholeAovRay = 0xffu;
struct PendingRay {
    Ray ray;
    vec3 weight;
    uint depth;
    uint component;  // kAovReflection or kAovTransmission for secondary rays, kPinholeAovRay
#ifndef WHITTED_NO_TEXTURES
    // The ray cone's width at the ray's origin and its spread angle: it picks a texture's level
    // (shaders/texture.glsl), and nothing else, so the build for scenes without textures carries none, and
    // the cones' arithmetic compiles out with it.
    vec2 cone;
#endif
};

PendingRay pendingRay(Ray ray, vec3 weight, uint depth, uint component, vec2 cone) {
#ifdef WHITTED_NO_TEXTURES
    return PendingRay(ray, weight, depth, component);
#else
    return PendingRay(ray, weight, depth, component, cone);
#endif
}

vec2 pendingCone(PendingRay r) {
#ifdef WHITTED_NO_TEXTURES
    return vec2(0.0);
#else
    return r.cone;
#endif
}

// Per-sample results for the output layers.
struct SampleResult {
    vec3 components[5];  // ambient, diffuse, specular, reflection, transmission
    vec4 normal;         // primary hit: shading normal, hit
    vec4 coefs0;         // ka, kd, ks, depth
    vec4 coefs1;         // kr, kt, ior, hit
};

// What adaptive anti-aliasing decides from (host/render/adaptive.cpp): the
// range of the samples' display colours and whether they saw one object.
struct SampleSpread {
    vec3 lo;
    vec3 hi;
    uint object;  // object (material index) of the first sample, kNoObject for none
    bool mixed;   // the samples saw more than one object (or the background)
};

// The samples' colours are compared as a display shows them (color.glsl).
void addToSpread(inout SampleSpread spread, vec3 color, uint object, bool firstSample) {
    vec3 shown = linearToSrgb(color);
    if (firstSample) {
        spread.lo = shown;
        spread.hi = shown;
        spread.object = object;
        spread.mixed = false;
    } else {
        spread.lo = min(spread.lo, shown);
        spread.hi = max(spread.hi, shown);
        spread.mixed = spread.mixed || object != spread.object;
    }
}

// Reflection and transmission split by ray-tree depth (the layers after
// kAovCount, device_types.h), only when a render asks for them: each
// secondary ray's light is added straight into its layer at the pixel's
// place (gSplitPixel; kNoObject outside the output rectangle), so a render
// without them keeps no extra per-sample state. A ray at depth d goes to
// bounce min(d, B): the last layer also holds everything deeper.
uint gSplitBounces = 0u;
uint gSplitPixel = kNoObject;
uint gSplitPixels = 0u;

void addBounceSplit(uint component, uint depth, vec3 light) {
    if (gSplitBounces == 0u || gSplitPixel == kNoObject) return;
    uint layer = kAovCount + (component == kAovTransmission ? gSplitBounces : 0u) + min(depth, gSplitBounces) - 1u;
    uint i = layer * gSplitPixels + gSplitPixel;
    outputLayers[i].rgb += light;
}

// The rays still to trace of the current sample's ray tree, depth first: the
// children of a shaded hit are pushed on top, the next ray popped from it.
PendingRay gStack[kRayStackSize];
int gTop = 0;

// Where traceSamples stands in a pixel's samples [first, end) of pattern
// size patternSize, and the current sample's colour so far.
struct SampleWalk {
    uvec2 pixel;
    uint first;
    uint end;
    uint patternSize;
    uint pixelSeed;
    uint next;        // the next camera sample: the current one is next - 1
    vec2 pixelCone;   // a camera ray's cone (PendingRay.cone)
    bool lens;        // camera rays leave from points of a thin lens
    vec3 color;       // the current sample's colour so far
    uint object;      // the material its camera ray hit, kNoObject for none
};

// What a ray's hit is shaded with: the surface point, its normals and its
// material (textures applied), and the local terms its lights add up.
struct ShadedHit {
    Material m;
    LocalShading local;
    vec3 p;           // the hit point
    vec3 pOutside;    // p offset to the side the ray came from: its shadow rays and reflection start there
    vec3 n;           // the geometric normal, facing the ray
    vec3 ns;          // the shading normal, facing the ray
    bool frontFace;   // the outside of the surface was hit
    float coneWidth;  // the ray cone's width at p
    float curvature;  // the surface's signed curvature along the ray, positive where convex towards it
    uint material;
#ifdef WHITTED_RAY_TREE
    Hit hit;
    Primitive prim;
#endif
};

// Adds the finished sample's colour and object to the spread, and clears
// them for the next sample.
void finishSample(inout SampleWalk s, inout SampleSpread spread) {
    if (s.next > s.first) addToSpread(spread, s.color, s.object, s.next == s.first + 1u);
    s.color = vec3(0.0);
    s.object = kNoObject;
}

// The next ray to trace. When the stack is empty, the probe or the next camera
// sample enters it first, through the one call of generateCameraRay. With a
// lens, each sample's camera ray leaves from a point of the lens; the depth,
// normal and coefficient layers still come from the sample's pinhole ray
// (through the lens centre), traced for them alone (kPinholeAovRay), so they
// stay sharp at every distance.
PendingRay popRay(bool probing, inout SampleWalk s, inout SampleSpread spread, inout uvec3 rayCount) {
    if (gTop == 0) {
        if (!probing) finishSample(s, spread);
        vec2 offset = probing ? vec2(0.5) : pixelSampleOffset(s.next, s.patternSize, s.pixelSeed);
        vec2 size = vec2(params.width, params.height);
        Ray camera = generateCameraRay(vec2(s.pixel) + offset, size, params.eye, params.forward, params.right,
                                       params.up, params.projection);
        Ray pinhole = camera;
        if (s.lens && !probing)
            camera = thinLensRay(camera, params.right, params.up, params.apertureRadius, params.focusDistance,
                                 sampleDimension(s.next, s.patternSize, s.pixelSeed, kDimLens));
        gStack[gTop++] = pendingRay(camera, vec3(1.0), 0u, 0u, s.pixelCone);
        if (!probing) {
#ifdef WHITTED_RAY_TREE
            rayTreePush(gTop - 1, kRayCamera, camera, vec3(1.0), 0u);
#endif
            if (s.lens && (params.options & kWriteAovs) != 0u)
                gStack[gTop++] = pendingRay(pinhole, vec3(1.0), 0u, kPinholeAovRay, s.pixelCone);
            rayCount.x += 1u;
            ++s.next;
        }
    }
    PendingRay pending = gStack[--gTop];
#ifdef WHITTED_RAY_TREE
    if (!probing && pending.component != kPinholeAovRay) rayTreePop(gTop);
#endif
    if (pending.depth > 0u) rayCount.z += 1u;
    return pending;
}

#ifndef WHITTED_NO_TEXTURES  // the build for scenes without textures (host/render/device_policy.cpp)
// The material's textures at the hit: the ray cone's footprint (Ray Tracing
// Gems ch. 20) picks each one's level. A mapped normal is kept facing the
// viewer as shadingNormal() keeps an interpolated one.
void applyTextures(inout ShadedHit h, Primitive prim, Hit hit, vec3 dir) {
    uvec4 slots = uvec4(h.m.diffuseTexture, h.m.normalMap, h.m.emissionTexture, h.m.roughnessTexture);
    if (any(notEqual(slots, uvec4(kNoTexture)))) {
        SurfaceUv s = surfaceUv(prim, hit.primitive, hit.normal, h.p, h.m.textureScale);
        if (kSceneHasInstances && hit.instance != kNoInstance) s.tangent = instanceVector(hit.instance, s.tangent);
        float cosine = abs(dot(dir, h.n));
        if (slots.x != kNoTexture)
            h.m.diffuse *= textureColor(slots.x, s.uv, rayConeLod(slots.x, s, h.coneWidth, cosine));
        if (slots.z != kNoTexture)
            h.m.emission *= textureColor(slots.z, s.uv, rayConeLod(slots.z, s, h.coneWidth, cosine));
        // A roughness texture: the roughness here is <roughness> times its green
        // channel (glTF's metallicRoughnessTexture), and the lobe's exponent
        // follows as the host's glossyLobeExponent (Walter et al. 2007:
        // 2 / alpha^2 - 2, alpha = r^2); r = 0 is the mirror (exponent < 0: no lobe).
        if (kHasGloss && slots.w != kNoTexture) {
            float r = h.m.roughness * textureColor(slots.w, s.uv, rayConeLod(slots.w, s, h.coneWidth, cosine)).g;
            float alpha = r * r;
            h.m.glossExponent = alpha * alpha > 0.0 ? 2.0 / (alpha * alpha) - 2.0 : -1.0;
        }
        if (slots.y != kNoTexture) {
            h.ns = normalMapped(slots.y, h.m.normalStrength, s, h.ns, rayConeLod(slots.y, s, h.coneWidth, cosine));
            float facing = dot(h.ns, -dir);
            if (facing < 1e-3) h.ns = normalize(h.ns + (1e-3 - facing) * -dir);
        }
    }
}
#endif

// The surface that pending's ray hit, in h. A pinhole ray only adds its
// auxiliary layers: false for it, as there is nothing to shade.
bool surfaceAt(inout PendingRay pending, Hit hit, bool lens, out ShadedHit h, inout SampleResult result) {
    Primitive prim = hitPrimitive(hit);
    Ray ray = pending.ray;
    h.m = loadMaterial(prim.material);
    h.material = prim.material;
    // Which side was hit is decided by the geometric normal; shading uses the
    // normal facing the incoming ray (two-sided surfaces). The geometric
    // normal n also places the ray origins; the shading normal ns differs
    // from it on smooth mesh triangles only.
    h.frontFace = dot(ray.dir, hit.normal) < 0.0;
    h.n = h.frontFace ? hit.normal : -hit.normal;
    h.p = ray.origin + hit.t * ray.dir;
    h.pOutside = offsetRay(h.p, h.n);
    h.ns = kHasSmoothTriangles ? shadingNormal(prim, h.p, h.n, -ray.dir) : h.n;
    // Beer-Lambert: a ray that hits the inside of an object travelled hit.t
    // through it, so all that comes back along it is attenuated.
    if (kHasAbsorption && !h.frontFace) pending.weight *= exp(-h.m.absorption * hit.t);
    h.m.diffuse = pigment(h.m.diffuse, h.m.checkerColor, h.m.checkerSize, h.m.checkerOrigin, h.p);
    vec2 cone = pendingCone(pending);
    h.coneWidth = cone.x + cone.y * hit.t;
#ifndef WHITTED_NO_TEXTURES
    applyTextures(h, prim, hit, ray.dir);
#endif
    bool aovRay = pending.component == kPinholeAovRay;
    if (aovRay || (pending.depth == 0u && !lens)) {  // the auxiliary layers of the pinhole ray
        result.normal += vec4(h.ns, 1.0);
        result.coefs0 += vec4(h.m.ka, h.m.kd, h.m.ks, hit.t);
        result.coefs1 += vec4(h.m.kr, h.m.kt, h.m.ior, 1.0);
    }
    if (!aovRay) {
        // The children's cones start with this footprint; a curved surface
        // spreads them (paraxial optics, signed curvature k > 0 convex
        // towards the ray): a mirror adds 2 k w (focal length 1 / (2 k)),
        // refraction from index n1 into n2 scales the angle by
        // eta = n1 / n2 and adds -(1 - eta) k w (the surface's power).
        h.curvature = surfaceCurvature(prim, hit.normal, h.p) * (h.frontFace ? 1.0 : -1.0);
#ifdef WHITTED_RAY_TREE
        h.hit = hit;
        h.prim = prim;
#endif
    }
    return !aovRay;
}

// Traces pending's ray to its closest hit and shades it there (surfaceAt):
// the hit's shadow rays (shading.glsl, nextShadowRay) are traced after it,
// each through the same call of traceQuery as the ray itself, so the driver
// compiles one copy of the BVH walk where a closest-hit query and a shadow
// query inside the light loop would inline one each. On a SIMD CPU driver
// (lavapipe) lanes in two walks take turns, each walk run under a mask;
// in one walk they step together (measurements:
// tools/benchmark_results/notes-shader.md).
// False when there is nothing to shade: a miss (`missed`: the ray left the scene, and the probe's ids stay
// kNoObject), the probe or a pinhole ray.
bool shadeHit(inout PendingRay pending, bool probing, SampleWalk s, out ShadedHit h, inout SampleResult result,
              inout uvec2 ids, out bool missed) {
    missed = false;
    Ray queryRay = pending.ray;
    float tMax = 3.0e38;
    bool shadow = false, shaded = false;
    ShadowQuery query;
    LightWalk walk;
    do {
        Hit hit;
        vec3 visibility;
        bool found = traceQuery(queryRay, tMax, shadow, hit, visibility);
        if (shadow) {
#ifdef WHITTED_RAY_TREE
            rayTreeShadowRayEnd(visibility);
#endif
            addShadowedLight(h.local, h.m, query, visibility);
        } else {
            if (!found) {
                missed = !probing;
                break;
            }
#ifdef WHITTED_PROFILE_NO_SHADING  // tools/profile_shader.sh: camera rays traced, not shaded
            result.components[0] += abs(hit.normal);
            break;
#endif
            if (probing) {  // the probe takes the ids of what it hit, nothing else
                Primitive prim = hitPrimitive(hit);
                ids = uvec2(primitiveObject(prim), prim.material);
                break;
            }
            if (!surfaceAt(pending, hit, s.lens, h, result)) break;
            h.local = startShading(h.m, walk);
            shaded = true;
        }
        // The hit's next shadow ray, if it has one left, is the next query.
        shadow = nextShadowRay(h.local, walk, h.m, h.pOutside, h.ns, h.n, -pending.ray.dir, s.next - 1u,
                               s.patternSize, s.pixelSeed, query);
        if (shadow) {
            queryRay = query.ray;
            tMax = query.dist;
#ifdef WHITTED_RAY_TREE
            rayTreeShadowRayBegin(query.light, queryRay, tMax, h.local.diffuse, h.local.specular);
#endif
        }
    } while (shadow);
    return shaded;
}

// Adds the shaded hit's light to the sample and to the layer of its
// component. Emission is added where a ray hits the surface (it lights
// nothing else); it counts in the ambient component, the other constant term.
void addHitLight(PendingRay pending, inout ShadedHit h, inout SampleWalk s, inout SampleResult result,
                 inout uvec3 rayCount) {
    h.local.ambient += h.m.emission;
    rayCount.y += h.local.shadowRays;
    if (pending.depth == 0u) {  // weight 1 unless the camera is inside an absorbing object
        result.components[0] += pending.weight * h.local.ambient;
        result.components[1] += pending.weight * h.local.diffuse;
        result.components[2] += pending.weight * h.local.specular;
        s.color += pending.weight * (h.local.ambient + h.local.diffuse + h.local.specular);
        s.object = h.material;
    } else {
        vec3 light = pending.weight * (h.local.ambient + h.local.diffuse + h.local.specular);
        result.components[pending.component - 1u] += light;
        addBounceSplit(pending.component, pending.depth, light);
        s.color += light;
    }
#ifdef WHITTED_RAY_TREE
    rayTreeShaded(h.hit, h.prim, h.frontFace, h.p, h.ns, pending.weight, h.local, h.m.emission);
#endif
}

// A ray that left the scene sees the environment (shaders/environment.glsl), times its weight: a camera ray
// (unless the environment is invisible to them) in the ambient component, the other constant term beside
// emission; a reflected or refracted ray in its own component and depth layer. A pinhole ray adds nothing.
void addEnvironmentSeen(PendingRay pending, inout SampleWalk s, inout SampleResult result) {
    if (pending.component == kPinholeAovRay) return;
    if (pending.depth == 0u && params.environment.visible == 0u) return;
    vec3 radiance = environmentRadiance(pending.ray.dir);
    vec3 light = pending.weight * radiance;
    if (pending.depth == 0u) {
        result.components[0] += light;
    } else {
        result.components[pending.component - 1u] += light;
        addBounceSplit(pending.component, pending.depth, light);
    }
    s.color += light;
#ifdef WHITTED_RAY_TREE
    rayTreeMissed(pending.weight, radiance);
#endif
}

// The weights of the shaded hit's reflected and transmitted rays. With
// fresnel, kr is F0 of Schlick's approximation (Schlick 1994):
// F = kr + (1 - kr)(1 - cos theta)^5; the reflected ray weighs Cs F, the
// transmitted one kt (1 - F). Leaving the denser side, theta is the angle on
// the thinner side (F = 1 under total internal reflection), so F is the same
// both ways through a surface.
void childWeights(ShadedHit h, vec3 dir, out vec3 reflectWeight, out float transmitWeight) {
    float kr = h.m.kr, kt = h.m.kt, ior = h.m.ior;
    transmitWeight = kt;
    if (kHasFresnel && (h.m.flags & kMaterialFresnel) != 0u) {
        float cosTheta = clamp(dot(-dir, h.ns), 0.0, 1.0);
        float eta = h.frontFace ? 1.0 / ior : ior;
        if (kt > 0.0 && eta > 1.0) {
            float sin2Transmitted = eta * eta * (1.0 - cosTheta * cosTheta);
            cosTheta = sin2Transmitted >= 1.0 ? 0.0 : sqrt(1.0 - sin2Transmitted);
        }
        float f = kr + (1.0 - kr) * pow(1.0 - cosTheta, 5.0);
        reflectWeight = f * h.m.specular;
        transmitWeight = kt * (1.0 - f);
    } else {
        reflectWeight = kr * h.m.specular;
    }
}

// Pushes the shaded hit's secondary rays: refraction by Snell's law with the
// object's IOR against air; total internal reflection sends the transmitted
// share into the reflected ray. Directions bent by the shading normal that
// would stay on the wrong side of the geometric surface fall back to the
// geometric normal's.
void pushChildren(PendingRay pending, ShadedHit h, SampleWalk s) {
    Ray ray = pending.ray;
    float kt = h.m.kt, ior = h.m.ior;
    uint childDepth = pending.depth + 1u;
    vec3 reflectWeight;
    float transmitWeight;
    childWeights(h, ray.dir, reflectWeight, transmitWeight);
    // A glossy material (roughness > 0) sends each child along a direction
    // drawn from a lobe about the ideal one (shading.glsl, glossyDirection),
    // from this sample's dimension for the ray's depth (sampling.glsl).
    bool glossy = kHasGloss && (h.m.flags & kMaterialGlossy) != 0u && h.m.glossExponent >= 0.0;
    vec2 lobeSample = glossy ? sampleDimension(s.next - 1u, s.patternSize, s.pixelSeed,
                                               kDimLobeBase + min(pending.depth, 13u))
                             : vec2(0.0);
    if (kt > 0.0) {
        float eta = h.frontFace ? 1.0 / ior : ior;
        vec3 refracted = refract(ray.dir, h.ns, eta);
        if (dot(refracted, h.n) >= 0.0) refracted = refract(ray.dir, h.n, eta);
        if (all(equal(refracted, vec3(0.0)))) {
            reflectWeight += vec3(transmitWeight);
#ifdef WHITTED_RAY_TREE
            rayTreeTotalInternal();
#endif
        } else if (transmitWeight > 0.0) {
            uint component = pending.depth == 0u ? kAovTransmission : pending.component;
            vec2 cone = vec2(h.coneWidth, eta * pendingCone(pending).y - (1.0 - eta) * h.curvature * h.coneWidth);
            refracted = normalize(refracted);
            if (glossy) refracted = glossyDirection(refracted, -h.n, h.m.glossExponent, lobeSample);
            gStack[gTop++] = pendingRay(Ray(offsetRay(h.p, -h.n), refracted),
                                        pending.weight * (transmitWeight * h.m.transmissionColor), childDepth,
                                        component, cone);
#ifdef WHITTED_RAY_TREE
            rayTreePush(gTop - 1, kRayRefraction, gStack[gTop - 1].ray, gStack[gTop - 1].weight, childDepth);
#endif
        }
    }
    if (any(greaterThan(reflectWeight, vec3(0.0)))) {
        uint component = pending.depth == 0u ? kAovReflection : pending.component;
        vec3 reflected = reflect(ray.dir, h.ns);
        if (dot(reflected, h.n) <= 0.0) reflected = reflect(ray.dir, h.n);
        if (glossy) reflected = glossyDirection(reflected, h.n, h.m.glossExponent, lobeSample);
        vec2 cone = vec2(h.coneWidth, pendingCone(pending).y + 2.0 * h.curvature * h.coneWidth);
        gStack[gTop++] = pendingRay(Ray(h.pOutside, reflected), pending.weight * reflectWeight, childDepth,
                                    component, cone);
#ifdef WHITTED_RAY_TREE
        rayTreePush(gTop - 1, rayTreeReflectionKind(), gStack[gTop - 1].ray, gStack[gTop - 1].weight, childDepth);
#endif
    }
}

// Traces samples [first, end) of pattern size patternSize of a pixel in ONE
// loop: when a sample's ray tree is done, the next sample's camera ray enters
// the stack in the same iteration. Lanes run in lockstep on a SIMD CPU driver
// (lavapipe), so a loop per sample would make every lane wait for the
// longest ray tree of each sample; with one loop a lane waits only at the
// end. Each lane still adds its own samples in order, so the sums are
// unchanged. Each iteration pops a ray, shades its hit and pushes its
// children.
// With `probe`, the ray through the pixel's centre is traced first, as the samples' rays are, and what it
// hits first goes to `ids` (object, material; kNoObject for none).
void traceSamples(uvec2 pixel, uint first, uint end, uint patternSize, uint pixelSeed, inout SampleResult result,
                  inout SampleSpread spread, inout uvec3 rayCount, bool probe, inout uvec2 ids) {
    // A camera ray's cone: width 0 at the eye, spread one pixel's angle
    // (Ray Tracing Gems ch. 20, eq. 20.30: atan(2 tan(fov/2) / height));
    // orthographic: one pixel wide, no spread.
    float height = float(params.height);
    bool orthographic = params.projection == kProjectionOrthographic;
    vec2 pixelCone = orthographic ? vec2(2.0 * length(params.up) / height, 0.0)
                                  : vec2(0.0, atan(2.0 * length(params.up) / height));
    bool lens = kHasLens && params.apertureRadius > 0.0;
    SampleWalk s = SampleWalk(pixel, first, end, patternSize, pixelSeed, first, pixelCone, lens, vec3(0.0), kNoObject);
    gTop = 0;
    while (probe || gTop > 0 || s.next < end) {
        bool probing = probe;
        probe = false;
        PendingRay pending = popRay(probing, s, spread, rayCount);
#ifdef WHITTED_PROFILE_CAMERA_ONLY  // tools/profile_shader.sh: camera rays made, none traced
        continue;
#endif
        ShadedHit h;
        bool missed;
        if (!shadeHit(pending, probing, s, h, result, ids, missed)) {
            if (kHasEnvironment && missed) addEnvironmentSeen(pending, s, result);
            continue;
        }
        addHitLight(pending, h, s, result, rayCount);
        if (pending.depth < params.maxDepth) pushChildren(pending, h, s);
    }
    finishSample(s, spread);
}

// Adds (or with kTileOverwrite stores) v into output layer `layer` at `o`.
void accumulate(uint layer, uint outPixels, uint o, vec4 v, bool overwrite) {
    uint i = layer * outPixels + o;
    outputLayers[i] = overwrite ? v : outputLayers[i] + v;
}

// Points addBounceSplit at the pixel's place `o` among outPixels, and starts
// the split layers' sums there (cleared or kept, with the sample count in w,
// as accumulate() does for the other layers).
void startBounceSplit(uint outPixels, uint o, uint count, bool overwrite) {
    gSplitBounces = kSplitBounces == 0u ? 0u : params.options >> kOptionAovBouncesShift;
    gSplitPixels = outPixels;
    gSplitPixel = o;
    for (uint k = 0u; k < 2u * gSplitBounces; ++k) {
        uint i = (kAovCount + k) * gSplitPixels + gSplitPixel;
        vec4 samples = vec4(0.0, 0.0, 0.0, float(count));
        outputLayers[i] = overwrite ? samples : outputLayers[i] + samples;
    }
}

// Adds the pixel's sums to the colour layer and, when the render writes
// them, to the auxiliary layers; the host divides by the sample count (w of
// the colour layer).
void accumulateLayers(uint outPixels, uint o, vec3 color, SampleResult result, uint count, bool overwrite) {
    accumulate(kAovColor, outPixels, o, vec4(color, float(count)), overwrite);
    if ((params.options & kWriteAovs) != 0u) {
        for (uint c = 0u; c < 5u; ++c)
            accumulate(kAovAmbient + c, outPixels, o, vec4(result.components[c], float(count)), overwrite);
        accumulate(kAovNormal, outPixels, o, result.normal, overwrite);
        accumulate(kAovCoefs0, outPixels, o, result.coefs0, overwrite);
        accumulate(kAovCoefs1, outPixels, o, result.coefs1, overwrite);
    }
}

// Stores the statistics of this dispatch's samples of list entry `entry`,
// merged with the earlier dispatches of the same refinement pass.
void storeSampleStats(uint entry, SampleSpread spread, bool overwrite) {
    if (!overwrite) {
        uvec4 lo = sampleStats[2u * entry], hi = sampleStats[2u * entry + 1u];
        spread.mixed = spread.mixed || hi.w != 0u || lo.w != spread.object;
        spread.lo = min(spread.lo, uintBitsToFloat(lo.rgb));
        spread.hi = max(spread.hi, uintBitsToFloat(hi.rgb));
        spread.object = lo.w;
    }
    sampleStats[2u * entry] = uvec4(floatBitsToUint(spread.lo), spread.object);
    sampleStats[2u * entry + 1u] = uvec4(floatBitsToUint(spread.hi), spread.mixed ? 1u : 0u);
}

void main() {
    uint flags = tileParams.flags;
    uvec2 pixel;
    uint entry = 0u;
    if ((flags & kTileList) != 0u) {
        // List mode: one invocation per listed pixel (adaptive refinement).
        uint index = gl_WorkGroupID.x * kListGroupSize + gl_LocalInvocationIndex;
        if (index >= tileParams.listCount) return;
        entry = tileParams.listFirst + index;
        uint packed = pixelList[entry];
        pixel = uvec2(packed & 0xffffu, packed >> 16);
    } else {
        uvec2 local = gl_GlobalInvocationID.xy;
        if (local.x >= tileParams.tileSize.x || local.y >= tileParams.tileSize.y) return;
        pixel = tileParams.tileOrigin + local;
    }
    // The pattern of a pixel depends on its place in the whole image only,
    // so a region or a band traces exactly the samples a full render does.
    uint pixelSeed = hashPcg((pixel.y * params.width + pixel.x) ^ params.seed);

    SampleResult result;
    for (int i = 0; i < 5; ++i) result.components[i] = vec3(0.0);
    result.normal = vec4(0.0);
    result.coefs0 = vec4(0.0);
    result.coefs1 = vec4(0.0);
    SampleSpread spread = SampleSpread(vec3(0.0), vec3(0.0), kNoObject, false);
    uvec3 rayCount = uvec3(0u);

    uint first = tileParams.firstSample;
    uint count = tileParams.sampleCount;
    bool overwrite = (flags & kTileOverwrite) != 0u;
    uvec2 outputOrigin = tileParams.outputOrigin, outputSize = tileParams.outputSize;
    bool inRect = all(greaterThanEqual(pixel, outputOrigin)) && all(lessThan(pixel, outputOrigin + outputSize));
    uint outPixels = outputSize.x * outputSize.y;
    uint o = (pixel.y - outputOrigin.y) * outputSize.x + (pixel.x - outputOrigin.x);
    if ((params.options & kWriteAovs) != 0u && inRect) startBounceSplit(outPixels, o, count, overwrite);
    // The object and material masks: what the ray through the pixel's centre
    // hits first, traced once, by the dispatch that holds the pixel's sample 0
    // (the adaptive refinements' lists never do), and stored, not summed, so
    // no sample pattern or filter blends ids. This probe is not counted among
    // the camera rays.
    bool probe = (params.options & kWriteIds) != 0u && inRect && first == 0u && (flags & kTileList) == 0u;
    uvec2 ids = uvec2(kNoObject);
    traceSamples(pixel, first, first + count, tileParams.patternSize, pixelSeed, result, spread, rayCount, probe,
                 ids);
    vec3 color = result.components[0] + result.components[1] + result.components[2] +
                 result.components[3] + result.components[4];

    // Accumulate sums into the output rectangle. Guide pixels outside it (the
    // adaptive first pass's one-pixel border) write only the guide.
    if (inRect) {
        accumulateLayers(outPixels, o, color, result, count, overwrite);
        if (probe) {  // the object and material masks (traceSamples traced the probe)
            uint idLayer = kAovCount + 2u * (params.options >> kOptionAovBouncesShift);
            outputLayers[idLayer * outPixels + o] = vec4(uintBitsToFloat(ids.x), uintBitsToFloat(ids.y), 0.0, 0.0);
        }
    }
    if ((flags & kTileGuide) != 0u) {
        uvec2 g = pixel - tileParams.guideOrigin;
        guide[g.y * tileParams.guideSize.x + g.x] = uvec4(floatBitsToUint(linearToSrgb(color)), spread.object);
    }
    if ((flags & kTileStats) != 0u) storeSampleStats(entry, spread, overwrite);

    // One atomic add per counter and subgroup, not per invocation: lavapipe
    // runs a per-invocation atomic lane by lane, on a counter that the other
    // cores' threads add to as well (tools/benchmark_results/notes-shader.md).
    uvec3 groupCount = subgroupAdd(rayCount);
    if (subgroupElect()) {
        atomicAdd(counters.primary, groupCount.x);
        atomicAdd(counters.shadow, groupCount.y);
        atomicAdd(counters.secondary, groupCount.z);
    }
}

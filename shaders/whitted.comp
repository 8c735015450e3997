#version 460
// Whitted ray tracing, one invocation per pixel of the current tile, all of
// the tile's samples in a loop. Recursion is replaced by an explicit stack of
// pending rays (depth-first), each carrying its throughput weight, its depth
// and the colour component of the primary hit it descends from.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require

#include "device_types.h"
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

// Traces samples [first, end) of pattern size patternSize of a pixel in ONE loop: when
// a sample's ray tree is done, the next sample's camera ray enters the stack
// in the same iteration. Lanes run in lockstep on a SIMD CPU driver
// (lavapipe), so a loop per sample would make every lane wait for the
// longest ray tree of each sample; with one loop a lane waits only at the
// end. Each lane still adds its own samples in order, so the sums are
// unchanged.
// A ray from the stack is traced, then its hit's shadow rays (shading.glsl,
// nextShadowRay), all through the one call of traceQuery in the inner loop:
// the driver compiles one copy of the BVH walk, where the closest-hit query
// and the shadow query inside the light loop inlined one each. On
// lavapipe that made renders 11-44% faster (tools/benchmark_results/README.md,
// "Profiling and what each change gained") and left the first render's
// compile as it was.
// With `probe`, the ray through the pixel's centre is traced first, as the samples' rays are, and what it
// hits first goes to `ids` (object, material; kNoObject for none).
void traceSamples(uvec2 pixel, uint first, uint end, uint patternSize, uint pixelSeed, inout SampleResult result,
                  inout SampleSpread spread, inout uvec3 rayCount, bool probe, inout uvec2 ids) {
    PendingRay stack[kRayStackSize];
    int top = 0;
    uint maxDepth = params.maxDepth;
    uint nextSample = first;  // the current camera sample is nextSample - 1
    vec2 size = vec2(params.width, params.height);
    vec3 sampleColor = vec3(0.0);  // the current sample's colour so far
    uint sampleObject = kNoObject;
    // A camera ray's cone: width 0 at the eye, spread one pixel's angle
    // (Ray Tracing Gems ch. 20, eq. 20.30: atan(2 tan(fov/2) / height));
    // orthographic: one pixel wide, no spread.
    bool orthographic = params.projection == kProjectionOrthographic;
    vec2 pixelCone = orthographic ? vec2(2.0 * length(params.up) / size.y, 0.0)
                                  : vec2(0.0, atan(2.0 * length(params.up) / size.y));
    // With a lens, each sample's camera ray leaves from a point of the lens;
    // the depth, normal and coefficient layers still come from the sample's
    // pinhole ray (through the lens centre), traced for them alone
    // (kPinholeAovRay), so they stay sharp at every distance.
    bool lens = kHasLens && params.apertureRadius > 0.0;
    bool pinholeAovs = lens && (params.options & kWriteAovs) != 0u;

    while (probe || top > 0 || nextSample < end) {
        // The probe and each camera sample enter the stack through one call of generateCameraRay.
        bool probing = probe;
        if (top == 0) {
            if (!probing) {
                if (nextSample > first) addToSpread(spread, sampleColor, sampleObject, nextSample == first + 1u);
                sampleColor = vec3(0.0);
                sampleObject = kNoObject;
            }
            vec2 offset = probing ? vec2(0.5) : pixelSampleOffset(nextSample, patternSize, pixelSeed);
            Ray camera = generateCameraRay(vec2(pixel) + offset, size, params.eye, params.forward, params.right,
                                           params.up, params.projection);
            Ray pinhole = camera;
            if (lens && !probing)
                camera = thinLensRay(camera, params.right, params.up, params.apertureRadius, params.focusDistance,
                                     sampleDimension(nextSample, patternSize, pixelSeed, kDimLens));
            stack[top++] = pendingRay(camera, vec3(1.0), 0u, 0u, pixelCone);
            if (probing) {
                probe = false;
            } else {
#ifdef WHITTED_RAY_TREE
                rayTreePush(top - 1, kRayCamera, camera, vec3(1.0), 0u);
#endif
                if (pinholeAovs) stack[top++] = pendingRay(pinhole, vec3(1.0), 0u, kPinholeAovRay, pixelCone);
                rayCount.x += 1u;
                ++nextSample;
            }
        }
        PendingRay pending = stack[--top];
        bool aovRay = pending.component == kPinholeAovRay;
#ifdef WHITTED_RAY_TREE
        if (!probing && !aovRay) rayTreePop(top);
#endif
        if (pending.depth > 0u) rayCount.z += 1u;
#ifdef WHITTED_PROFILE_CAMERA_ONLY  // tools/profile_shader.sh: camera rays made, none traced
        continue;
#endif

        // The ray's closest hit, then the shadow rays of its lights, each
        // through the one call of traceQuery.
        Ray ray = pending.ray;
        Ray queryRay = ray;
        float tMax = 3.0e38;
        bool shadow = false, shaded = false;
        ShadowQuery query;
        LightWalk walk;
        LocalShading local;
        Material m;  // the material at the hit (textures applied)
        vec3 p, pOutside, n, ns;
        bool frontFace;
        float coneWidth, curvature;
        uint hitMaterial;
#ifdef WHITTED_RAY_TREE
        Hit shadedHit;
        Primitive shadedPrim;
#endif
        do {
            Hit hit;
            vec3 visibility;
            bool found = traceQuery(queryRay, tMax, shadow, hit, visibility);
            if (shadow) {
#ifdef WHITTED_RAY_TREE
                rayTreeShadowRayEnd(visibility);
#endif
                addShadowedLight(local, m, query, visibility);
            } else {
                if (!found) break;  // background is black (and the probe's ids stay kNoObject)
#ifdef WHITTED_PROFILE_NO_SHADING  // tools/profile_shader.sh: camera rays traced, not shaded
                result.components[0] += abs(hit.normal);
                break;
#endif
                Primitive prim = primitives[hit.primitive];
                if (probing) {
                    ids = uvec2(prim.extra1, prim.material);
                    break;
                }
                m = loadMaterial(prim.material);
                hitMaterial = prim.material;

                // Which side was hit is decided by the geometric normal; shading
                // uses the normal facing the incoming ray (two-sided surfaces). The
                // geometric normal n also places the ray origins; the shading normal
                // ns differs from it on smooth mesh triangles only.
                frontFace = dot(ray.dir, hit.normal) < 0.0;
                n = frontFace ? hit.normal : -hit.normal;
                p = ray.origin + hit.t * ray.dir;
                pOutside = offsetRay(p, n);
                ns = kHasSmoothTriangles ? shadingNormal(prim, p, n, -ray.dir) : n;
                // Beer-Lambert: a ray that hits the inside of an object travelled
                // hit.t through it, so all that comes back along it is attenuated.
                if (kHasAbsorption && !frontFace) pending.weight *= exp(-m.absorption * hit.t);
                m.diffuse = pigment(m.diffuse, m.checkerColor, m.checkerSize, m.checkerOrigin, p);
                // The cone's footprint here filters the diffuse texture, the
                // emission texture and the normal map; a mapped normal is kept facing
                // the viewer as shadingNormal() keeps an interpolated one.
                vec2 cone = pendingCone(pending);
                coneWidth = cone.x + cone.y * hit.t;
#ifndef WHITTED_NO_TEXTURES  // the build for scenes without textures (host/render/device_policy.cpp)
                uvec4 slots = uvec4(m.diffuseTexture, m.normalMap, m.emissionTexture, m.roughnessTexture);
                if (any(notEqual(slots, uvec4(kNoTexture)))) {
                    SurfaceUv s = surfaceUv(prim, hit.primitive, hit.normal, p, m.textureScale);
                    float cosine = abs(dot(ray.dir, n));
                    if (slots.x != kNoTexture)
                        m.diffuse *= textureColor(slots.x, s.uv, rayConeLod(slots.x, s, coneWidth, cosine));
                    if (slots.z != kNoTexture)
                        m.emission *= textureColor(slots.z, s.uv, rayConeLod(slots.z, s, coneWidth, cosine));
                    // A roughness texture: the roughness here is <roughness> times
                    // its green channel (glTF's metallicRoughnessTexture), and the
                    // lobe's exponent follows as the host's glossyLobeExponent
                    // (Walter et al. 2007: 2 / alpha^2 - 2, alpha = r^2); r = 0 is
                    // the mirror (exponent < 0: no lobe).
                    if (kHasGloss && slots.w != kNoTexture) {
                        float r = m.roughness * textureColor(slots.w, s.uv, rayConeLod(slots.w, s, coneWidth, cosine)).g;
                        float alpha = r * r;
                        m.glossExponent = alpha * alpha > 0.0 ? 2.0 / (alpha * alpha) - 2.0 : -1.0;
                    }
                    if (slots.y != kNoTexture) {
                        ns = normalMapped(slots.y, m.normalStrength, s, ns, rayConeLod(slots.y, s, coneWidth, cosine));
                        float facing = dot(ns, -ray.dir);
                        if (facing < 1e-3) ns = normalize(ns + (1e-3 - facing) * -ray.dir);
                    }
                }
#endif

                if (aovRay || (pending.depth == 0u && !lens)) {  // the auxiliary layers of the pinhole ray
                    result.normal += vec4(ns, 1.0);
                    result.coefs0 += vec4(m.ka, m.kd, m.ks, hit.t);
                    result.coefs1 += vec4(m.kr, m.kt, m.ior, 1.0);
                    if (aovRay) break;
                }
                // The children's cones start with this footprint; a curved surface
                // spreads them (paraxial optics, signed curvature k > 0 convex
                // towards the ray): a mirror adds 2 k w (focal length 1 / (2 k)),
                // refraction from index n1 into n2 scales the angle by
                // eta = n1 / n2 and adds -(1 - eta) k w (the surface's power).
                curvature = surfaceCurvature(prim, hit.normal, p) * (frontFace ? 1.0 : -1.0);
#ifdef WHITTED_RAY_TREE
                shadedHit = hit;
                shadedPrim = prim;
#endif
                local = startShading(m, walk);
                shaded = true;
            }
            // The hit's next shadow ray, if it has one left, is the next query.
            shadow = nextShadowRay(local, walk, m, pOutside, ns, n, -ray.dir, nextSample - 1u, patternSize,
                                   pixelSeed, query);
            if (shadow) {
                queryRay = query.ray;
                tMax = query.dist;
#ifdef WHITTED_RAY_TREE
                rayTreeShadowRayBegin(query.light, queryRay, tMax, local.diffuse, local.specular);
#endif
            }
        } while (shadow);
        if (!shaded) continue;

        // The hit is shaded: its terms and its secondary rays.
        // Emission is added where a ray hits the surface (it lights nothing
        // else); it counts in the ambient component, the other constant term.
        local.ambient += m.emission;
        rayCount.y += local.shadowRays;
        if (pending.depth == 0u) {  // weight 1 unless the camera is inside an absorbing object
            result.components[0] += pending.weight * local.ambient;
            result.components[1] += pending.weight * local.diffuse;
            result.components[2] += pending.weight * local.specular;
            sampleColor += pending.weight * (local.ambient + local.diffuse + local.specular);
            sampleObject = hitMaterial;
        } else {
            vec3 light = pending.weight * (local.ambient + local.diffuse + local.specular);
            result.components[pending.component - 1u] += light;
            addBounceSplit(pending.component, pending.depth, light);
            sampleColor += light;
        }
#ifdef WHITTED_RAY_TREE
        rayTreeShaded(shadedHit, shadedPrim, frontFace, p, ns, pending.weight, local, m.emission);
#endif
        if (pending.depth >= maxDepth) continue;
        // Secondary rays: refraction by Snell's law with the object's IOR
        // against air; total internal reflection sends the transmitted share
        // into the reflected ray. Directions bent by the shading normal that
        // would stay on the wrong side of the geometric surface fall back to
        // the geometric normal's.
        float kr = m.kr, kt = m.kt, ior = m.ior;
        uint childDepth = pending.depth + 1u;
        // With fresnel, kr is F0 of Schlick's approximation (Schlick 1994):
        // F = kr + (1 - kr)(1 - cos theta)^5; the reflected ray weighs Cs F,
        // the transmitted one kt (1 - F). Leaving the denser side, theta is
        // the angle on the thinner side (F = 1 under total internal
        // reflection), so F is the same both ways through a surface.
        float transmitWeight = kt;
        vec3 reflectWeight;
        if (kHasFresnel && (m.flags & kMaterialFresnel) != 0u) {
            float cosTheta = clamp(dot(-ray.dir, ns), 0.0, 1.0);
            float eta = frontFace ? 1.0 / ior : ior;
            if (kt > 0.0 && eta > 1.0) {
                float sin2Transmitted = eta * eta * (1.0 - cosTheta * cosTheta);
                cosTheta = sin2Transmitted >= 1.0 ? 0.0 : sqrt(1.0 - sin2Transmitted);
            }
            float f = kr + (1.0 - kr) * pow(1.0 - cosTheta, 5.0);
            reflectWeight = f * m.specular;
            transmitWeight = kt * (1.0 - f);
        } else {
            reflectWeight = kr * m.specular;
        }
        // A glossy material (roughness > 0) sends each child along a direction
        // drawn from a lobe about the ideal one (shading.glsl, glossyDirection), from
        // this sample's dimension for the ray's depth (sampling.glsl).
        bool glossy = kHasGloss && (m.flags & kMaterialGlossy) != 0u && m.glossExponent >= 0.0;
        vec2 lobeSample = glossy ? sampleDimension(nextSample - 1u, patternSize, pixelSeed,
                                                   kDimLobeBase + min(pending.depth, 13u))
                                 : vec2(0.0);
        if (kt > 0.0) {
            float eta = frontFace ? 1.0 / ior : ior;
            vec3 refracted = refract(ray.dir, ns, eta);
            if (dot(refracted, n) >= 0.0) refracted = refract(ray.dir, n, eta);
            if (all(equal(refracted, vec3(0.0)))) {
                reflectWeight += vec3(transmitWeight);
#ifdef WHITTED_RAY_TREE
                rayTreeTotalInternal();
#endif
            } else if (transmitWeight > 0.0) {
                uint component = pending.depth == 0u ? kAovTransmission : pending.component;
                vec2 cone = vec2(coneWidth, eta * pendingCone(pending).y - (1.0 - eta) * curvature * coneWidth);
                refracted = normalize(refracted);
                if (glossy) refracted = glossyDirection(refracted, -n, m.glossExponent, lobeSample);
                stack[top++] = pendingRay(Ray(offsetRay(p, -n), refracted),
                                          pending.weight * (transmitWeight * m.transmissionColor), childDepth,
                                          component, cone);
#ifdef WHITTED_RAY_TREE
                rayTreePush(top - 1, kRayRefraction, stack[top - 1].ray, stack[top - 1].weight, childDepth);
#endif
            }
        }
        if (any(greaterThan(reflectWeight, vec3(0.0)))) {
            uint component = pending.depth == 0u ? kAovReflection : pending.component;
            vec3 reflected = reflect(ray.dir, ns);
            if (dot(reflected, n) <= 0.0) reflected = reflect(ray.dir, n);
            if (glossy) reflected = glossyDirection(reflected, n, m.glossExponent, lobeSample);
            vec2 cone = vec2(coneWidth, pendingCone(pending).y + 2.0 * curvature * coneWidth);
            stack[top++] = pendingRay(Ray(pOutside, reflected),
                                      pending.weight * reflectWeight, childDepth, component, cone);
#ifdef WHITTED_RAY_TREE
            rayTreePush(top - 1, rayTreeReflectionKind(), stack[top - 1].ray, stack[top - 1].weight, childDepth);
#endif
        }
    }
    if (end > first) addToSpread(spread, sampleColor, sampleObject, end == first + 1u);
}

// Adds (or with kTileOverwrite stores) v into output layer `layer` at `o`.
void accumulate(uint layer, uint outPixels, uint o, vec4 v, bool overwrite) {
    uint i = layer * outPixels + o;
    outputLayers[i] = overwrite ? v : outputLayers[i] + v;
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
    if ((params.options & kWriteAovs) != 0u && inRect) {
        // The split layers' sums start here (cleared or kept, with the
        // sample count in w, as accumulate() does for the other layers).
        gSplitBounces = kSplitBounces == 0u ? 0u : params.options >> kOptionAovBouncesShift;
        gSplitPixels = outputSize.x * outputSize.y;
        gSplitPixel = (pixel.y - outputOrigin.y) * outputSize.x + (pixel.x - outputOrigin.x);
        for (uint k = 0u; k < 2u * gSplitBounces; ++k) {
            uint i = (kAovCount + k) * gSplitPixels + gSplitPixel;
            vec4 samples = vec4(0.0, 0.0, 0.0, float(count));
            outputLayers[i] = overwrite ? samples : outputLayers[i] + samples;
        }
    }
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

    // Accumulate sums into the output rectangle; the host divides by the
    // sample count (w of the colour layer). Guide pixels outside it (the
    // adaptive first pass's one-pixel border) write only the guide.
    if (inRect) {
        uint outPixels = outputSize.x * outputSize.y;
        uint o = (pixel.y - outputOrigin.y) * outputSize.x + (pixel.x - outputOrigin.x);
        accumulate(kAovColor, outPixels, o, vec4(color, float(count)), overwrite);
        if ((params.options & kWriteAovs) != 0u) {
            for (uint c = 0u; c < 5u; ++c)
                accumulate(kAovAmbient + c, outPixels, o, vec4(result.components[c], float(count)), overwrite);
            accumulate(kAovNormal, outPixels, o, result.normal, overwrite);
            accumulate(kAovCoefs0, outPixels, o, result.coefs0, overwrite);
            accumulate(kAovCoefs1, outPixels, o, result.coefs1, overwrite);
        }
        if (probe) {  // the object and material masks (traceSamples traced the probe)
            uint idLayer = kAovCount + 2u * (params.options >> kOptionAovBouncesShift);
            outputLayers[idLayer * outPixels + o] = vec4(uintBitsToFloat(ids.x), uintBitsToFloat(ids.y), 0.0, 0.0);
        }
    }
    if ((flags & kTileGuide) != 0u) {
        uvec2 g = pixel - tileParams.guideOrigin;
        guide[g.y * tileParams.guideSize.x + g.x] = uvec4(floatBitsToUint(linearToSrgb(color)), spread.object);
    }
    if ((flags & kTileStats) != 0u) {
        // Statistics of this dispatch's samples, merged with the earlier
        // dispatches of the same refinement pass.
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

    // One atomic add per counter and subgroup, not per invocation: lavapipe
    // runs a per-invocation atomic lane by lane, on a counter that the other
    // cores' threads add to as well (tools/benchmark_results/README.md, "Profiling and what each change gained").
    uvec3 groupCount = subgroupAdd(rayCount);
    if (subgroupElect()) {
        atomicAdd(counters.primary, groupCount.x);
        atomicAdd(counters.shadow, groupCount.y);
        atomicAdd(counters.secondary, groupCount.z);
    }
}

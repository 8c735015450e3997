#version 460
// Whitted ray tracing, one invocation per pixel of the current tile, all of
// the tile's samples in a loop. Recursion is replaced by an explicit stack of
// pending rays (depth-first), each carrying its throughput weight, its depth
// and the colour component of the primary hit it descends from.
#extension GL_GOOGLE_include_directive : require

#include "device_types.h"
#include "camera.glsl"
#include "sampling.glsl"
#include "shading.glsl"

layout(local_size_x = kWorkgroupSize, local_size_y = kWorkgroupSize, local_size_z = 1) in;

struct PendingRay {
    Ray ray;
    vec3 weight;
    uint depth;
    uint component;  // kAovReflection or kAovTransmission for secondary rays
};

// Per-sample results for the output layers.
struct SampleResult {
    vec3 components[5];  // ambient, diffuse, specular, reflection, transmission
    vec4 normal;         // primary hit: shading normal, hit
    vec4 coefs0;         // ka, kd, ks, depth
    vec4 coefs1;         // kr, kt, ior, hit
};

// Traces samples [first, end) of a pixel in ONE loop: when a sample's ray
// tree is done, the next sample's camera ray enters the stack in the same
// iteration. Lanes run in lockstep on a SIMD CPU driver (lavapipe), so a
// loop per sample would make every lane wait for the longest ray tree of
// each sample; with one loop a lane waits only at the end. Each lane still
// adds its own samples in order, so the sums are unchanged.
void traceSamples(uvec2 pixel, uint first, uint end, uint pixelSeed, inout SampleResult result,
                  inout uvec3 rayCount) {
    PendingRay stack[kRayStackSize];
    int top = 0;
    uint maxDepth = params.options.y;
    uint nextSample = first;
    vec2 size = vec2(params.sizes.xy);

    while (top > 0 || nextSample < end) {
        if (top == 0) {
            vec2 offset = pixelSampleOffset(nextSample, params.options.x, pixelSeed);
            Ray ray = generateCameraRay(vec2(pixel) + offset, size, params.eye.xyz, params.forward.xyz,
                                        params.right.xyz, params.up.xyz);
            stack[top++] = PendingRay(ray, vec3(1.0), 0u, 0u);
            rayCount.x += 1u;
            ++nextSample;
        }
        PendingRay pending = stack[--top];
        Ray ray = pending.ray;
        if (pending.depth > 0u) rayCount.z += 1u;
        Hit hit;
        if (!traceClosest(ray, 3.0e38, hit)) continue;  // background is black

        Primitive prim = primitives[hit.primitive];
        Material m = materials[prim.info.y];
        float kr = m.coefs1.x, kt = m.coefs1.y, ior = m.coefs1.z;

        // Which side was hit is decided by the geometric normal; shading
        // uses the normal facing the incoming ray (two-sided surfaces). The
        // geometric normal n also places the ray origins; the shading normal
        // ns differs from it on smooth mesh triangles only.
        bool frontFace = dot(ray.dir, hit.normal) < 0.0;
        vec3 n = frontFace ? hit.normal : -hit.normal;
        vec3 p = ray.origin + hit.t * ray.dir;
        vec3 pOutside = offsetRay(p, n);
        vec3 ns = shadingNormal(prim, p, n, -ray.dir);

        LocalShading local = shadeLocal(m, pOutside, ns, n, -ray.dir);
        rayCount.y += local.shadowRays;
        if (pending.depth == 0u) {
            result.components[0] += local.ambient;
            result.components[1] += local.diffuse;
            result.components[2] += local.specular;
            result.normal += vec4(ns, 1.0);
            result.coefs0 += vec4(m.coefs0.xyz, hit.t);
            result.coefs1 += vec4(kr, kt, ior, 1.0);
        } else {
            result.components[pending.component - 1u] +=
                pending.weight * (local.ambient + local.diffuse + local.specular);
        }
        if (pending.depth >= maxDepth) continue;

        // Secondary rays: refraction by Snell's law with the object's IOR
        // against air; total internal reflection sends the transmitted share
        // into the reflected ray. Directions bent by the shading normal that
        // would stay on the wrong side of the geometric surface fall back to
        // the geometric normal's.
        uint childDepth = pending.depth + 1u;
        vec3 reflectWeight = kr * m.specular.rgb;
        if (kt > 0.0) {
            float eta = frontFace ? 1.0 / ior : ior;
            vec3 refracted = refract(ray.dir, ns, eta);
            if (dot(refracted, n) >= 0.0) refracted = refract(ray.dir, n, eta);
            if (all(equal(refracted, vec3(0.0)))) {
                reflectWeight += vec3(kt);
            } else {
                uint component = pending.depth == 0u ? kAovTransmission : pending.component;
                stack[top++] = PendingRay(Ray(offsetRay(p, -n), normalize(refracted)),
                                          pending.weight * kt, childDepth, component);
            }
        }
        if (any(greaterThan(reflectWeight, vec3(0.0)))) {
            uint component = pending.depth == 0u ? kAovReflection : pending.component;
            vec3 reflected = reflect(ray.dir, ns);
            if (dot(reflected, n) <= 0.0) reflected = reflect(ray.dir, n);
            stack[top++] = PendingRay(Ray(pOutside, reflected),
                                      pending.weight * reflectWeight, childDepth, component);
        }
    }
}

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tileParams.tile.z || local.y >= tileParams.tile.w) return;
    uvec2 pixel = tileParams.tile.xy + local;
    uint width = params.sizes.x;
    uint height = params.sizes.y;
    uint pixelIndex = pixel.y * width + pixel.x;
    uint pixelSeed = hashPcg(pixelIndex ^ params.options.w);

    SampleResult result;
    for (int i = 0; i < 5; ++i) result.components[i] = vec3(0.0);
    result.normal = vec4(0.0);
    result.coefs0 = vec4(0.0);
    result.coefs1 = vec4(0.0);
    uvec3 rayCount = uvec3(0u);

    uint first = tileParams.samples.x;
    uint count = tileParams.samples.y;
    traceSamples(pixel, first, first + count, pixelSeed, result, rayCount);

    // Accumulate sums; the host divides by the sample count.
    uint pixels = width * height;
    vec3 color = result.components[0] + result.components[1] + result.components[2] +
                 result.components[3] + result.components[4];
    outputLayers[kAovColor * pixels + pixelIndex] += vec4(color, float(count));
    if ((params.options.z & kOptionWriteAovs) != 0u) {
        for (uint c = 0u; c < 5u; ++c)
            outputLayers[(kAovAmbient + c) * pixels + pixelIndex] += vec4(result.components[c], float(count));
        outputLayers[kAovNormal * pixels + pixelIndex] += result.normal;
        outputLayers[kAovCoefs0 * pixels + pixelIndex] += result.coefs0;
        outputLayers[kAovCoefs1 * pixels + pixelIndex] += result.coefs1;
    }

    atomicAdd(counters.primary, rayCount.x);
    atomicAdd(counters.shadow, rayCount.y);
    atomicAdd(counters.secondary, rayCount.z);
}

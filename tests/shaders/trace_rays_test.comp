#version 460
// Casts a batch of given rays through the renderer's own traceClosest
// (shaders/intersect.glsl: the BVH walk, or ray queries in the build with
// -DWHITTED_RAY_QUERY) against a Renderer's uploaded scene, whose descriptor
// set and specialization it is bound with (createTracerPipeline), so tests
// can compare each ray's hit with a double-precision CPU evaluation
// (tests/watertight_test.cpp). The batch lives at the device address in
// TileParams.rayTreeAddress (the push constants every build of the tracer
// has), listCount rays: ray i reads (origin, 0), (dir, 0) from entries 2i
// and 2i + 1 and writes (t, primitive, 0, 0) over entry 2i, t = -1 for a
// miss.
#extension GL_GOOGLE_include_directive : require
#include "intersect.glsl"

layout(local_size_x = 64) in;
layout(buffer_reference, std430, buffer_reference_align = 16) buffer RayBatch { vec4 v[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= tileParams.listCount) return;
    RayBatch batch = RayBatch(tileParams.rayTreeAddress);
    Ray ray = Ray(batch.v[2u * i].xyz, batch.v[2u * i + 1u].xyz);
    Hit hit;
    bool found = traceClosest(ray, 3.0e38, hit);
    batch.v[2u * i] = found ? vec4(hit.t, uintBitsToFloat(hit.primitive), 0.0, 0.0) : vec4(-1.0, 0.0, 0.0, 0.0);
}

// The tracer's own buffers (shaders/whitted.comp), as laid out in
// tracer_types.h: the output layers, the ray counters, the adaptive pass's
// pixel list, guide and sample statistics, and the per-dispatch TileParams.
#ifndef WHITTED_TRACER_BUFFERS_GLSL
#define WHITTED_TRACER_BUFFERS_GLSL
#include "scene.glsl"
#include "tracer_types.h"

layout(std430, set = 0, binding = kBindingOutput) buffer OutputBlock { vec4 outputLayerBuffer[]; };
layout(std430, set = 0, binding = kBindingCounters) buffer CounterBlock { RayCounters counters; };
layout(std430, set = 0, binding = kBindingPixelList) readonly buffer PixelListBlock { uint pixelListBuffer[]; };
layout(std430, set = 0, binding = kBindingGuide) writeonly buffer GuideBlock { uvec4 guideBuffer[]; };
layout(std430, set = 0, binding = kBindingSampleStats) buffer StatsBlock { uvec4 sampleStatsBuffer[]; };
layout(push_constant) uniform TileBlock { TileParams tileParams; };

// The per-pixel buffers likewise (FrameParams.outputAddress ...): lavapipe compiles a storage buffer access
// into a loop over the lanes, each bounds-checked, and an address into one gather or scatter, so by address
// the writes of the auxiliary layers add little to the pipeline's compile
// (measurements: tools/benchmark_results/notes-shader.md).
layout(buffer_reference, std430, buffer_reference_align = 16) buffer OutputArray { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer PixelListArray { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer GuideArray { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer SampleStatsArray { uvec4 v[]; };
#ifdef WHITTED_SCENE_STORAGE_BUFFERS
#define outputLayers outputLayerBuffer
#define pixelList pixelListBuffer
#define guide guideBuffer
#define sampleStats sampleStatsBuffer
#else
#define outputLayers (OutputArray(params.outputAddress).v)
#define pixelList (PixelListArray(params.pixelListAddress).v)
#define guide (GuideArray(params.guideAddress).v)
#define sampleStats (SampleStatsArray(params.sampleStatsAddress).v)
#endif
#endif

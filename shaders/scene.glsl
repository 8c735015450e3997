// Scene buffers, as laid out in device_types.h.
#ifndef WHITTED_SCENE_GLSL
#define WHITTED_SCENE_GLSL
#include "device_types.h"

layout(std140, set = 0, binding = kBindingParams) uniform FrameParamsBlock { FrameParams params; };
layout(std430, set = 0, binding = kBindingPrimitives) readonly buffer PrimitiveBlock { Primitive primitives[]; };
layout(std430, set = 0, binding = kBindingMaterials) readonly buffer MaterialBlock { Material materials[]; };
layout(std430, set = 0, binding = kBindingLights) readonly buffer LightBlock { Light lights[]; };
layout(std430, set = 0, binding = kBindingOutput) buffer OutputBlock { vec4 outputLayers[]; };
layout(std430, set = 0, binding = kBindingCounters) buffer CounterBlock { RayCounters counters; };
layout(std430, set = 0, binding = kBindingBvhNodes) readonly buffer BvhBlock { BvhNode bvhNodes[]; };
layout(std430, set = 0, binding = kBindingPixelList) readonly buffer PixelListBlock { uint pixelList[]; };
layout(std430, set = 0, binding = kBindingGuide) writeonly buffer GuideBlock { uvec4 guide[]; };
layout(std430, set = 0, binding = kBindingSampleStats) buffer StatsBlock { uvec4 sampleStats[]; };
layout(push_constant) uniform TileBlock { TileParams tileParams; };

#endif

// The device's acceleration structures over the scene's bounded primitives,
// for tracing through VK_KHR_ray_query (shaders/ray_query.glsl).
#pragma once

#include "device_types.h"
#include "vk/buffer.h"

#include <span>

namespace whitted {

struct AccelerationStructure {
    Buffer storage;
    vk::raii::AccelerationStructureKHR handle{nullptr};
    vk::DeviceAddress address = 0;
};

// One BLAS of the triangles, one of the AABBs of the other bounded shapes
// (spheres, cylinders, boxes), each holding every primitive of `bounded` at
// its own index, those of the other kind inactive (NaN vertices) or empty (a
// point box, which the shader skips); a TLAS with the one
// or two instances. Built on the device (vkCmdBuildAccelerationStructuresKHR);
// the build inputs and scratch memory are freed when done.
struct SceneAccelerationStructures {
    AccelerationStructure triangles, boxes, top;
    double buildSeconds = 0;
    uint64_t bytes() const { return triangles.storage.size + boxes.storage.size + top.storage.size; }
};

SceneAccelerationStructures buildAccelerationStructures(VulkanContext& ctx, std::span<const gpu::Primitive> bounded);

}  // namespace whitted

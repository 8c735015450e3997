// The device's acceleration structures over the scene's bounded primitives,
// for tracing through VK_KHR_ray_query (shaders/ray_query.glsl).
#pragma once

#include "device_types.h"
#include "vk/buffer.h"

#include <span>
#include <vector>

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
//
// Instances (shaders/instance.glsl): each prototype's triangles (its range
// of `primitives`, after the bounded ones) a BLAS of their own, and each
// instance a TLAS instance of it with its worldFromObject transform and
// custom index 1 + its index (0: the scene's own BLASes). The instances'
// stand-ins among `bounded` are left out of the scene's own BLASes (as
// inactive stand-ins, as another shape's are).
struct SceneInstances {
    std::span<const gpu::Primitive> primitives;      // the whole primitive array
    std::span<const gpu::InstanceRecord> records;    // firstPrimitive, worldFromObject
    std::span<const glm::uvec2> prototypeRanges;     // first primitive and count of each prototype
    std::span<const uint32_t> instancePrototypes;    // each instance's prototype
};

struct SceneAccelerationStructures {
    AccelerationStructure triangles, boxes, top;
    std::vector<AccelerationStructure> prototypes;
    double buildSeconds = 0;
    uint64_t bytes() const {
        uint64_t b = triangles.storage.size + boxes.storage.size + top.storage.size;
        for (const AccelerationStructure& p : prototypes) b += p.storage.size;
        return b;
    }
};

SceneAccelerationStructures buildAccelerationStructures(VulkanContext& ctx, std::span<const gpu::Primitive> bounded,
                                                        const SceneInstances& instances = {});

}  // namespace whitted

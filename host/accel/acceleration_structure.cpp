#include "accel/acceleration_structure.h"

#include "accel/aabb.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace whitted {
namespace {

constexpr vk::BufferUsageFlags kBuildInput = vk::BufferUsageFlagBits::eShaderDeviceAddress |
                                             vk::BufferUsageFlagBits::eAccelerationStructureBuildInputReadOnlyKHR;

// Bounds of a sphere, cylinder or box from its packed form (device_types.h),
// padded by a few float ulps as the BVH's are (render/gpu_scene.cpp): the
// shader intersects the float-rounded shape.
Aabb boundsOf(const gpu::Primitive& p) {
    Aabb b;
    switch (p.shape) {
        case gpu::kShapeSphere:
            b.extend(gpu::sphereCenter(p) - glm::vec3(gpu::sphereRadius(p)));
            b.extend(gpu::sphereCenter(p) + glm::vec3(gpu::sphereRadius(p)));
            break;
        case gpu::kShapeCylinder: {
            // Each cap disc of radius r perpendicular to unit axis u extends
            // r * sqrt(1 - u_i^2) along world axis i.
            glm::vec3 base = gpu::cylinderBase(p), axis = gpu::cylinderAxis(p);
            glm::vec3 extent = gpu::cylinderRadius(p) * glm::sqrt(glm::max(glm::vec3(0.0f), 1.0f - axis * axis));
            glm::vec3 top = base + axis * gpu::cylinderHeight(p);
            b.extend(base - extent);
            b.extend(base + extent);
            b.extend(top - extent);
            b.extend(top + extent);
            break;
        }
        case gpu::kShapeBox:
            b.extend(gpu::boxMin(p));
            b.extend(gpu::boxMax(p));
            break;
        case gpu::kShapeCsg:  // its bounds (host/shapes/csg.cpp)
            b.extend(gpu::csgBoundsMin(p));
            b.extend(gpu::csgBoundsMax(p));
            break;
        default:
            throw std::logic_error("acceleration structure: no bounds for shape " + std::to_string(p.shape));
    }
    glm::vec3 pad = 1e-6f * (glm::abs(b.min) + glm::abs(b.max)) + 1e-30f;
    b.min -= pad;
    b.max += pad;
    return b;
}

// Memory for one acceleration structure and the structure in it.
AccelerationStructure createStructure(const VulkanContext& ctx, vk::AccelerationStructureTypeKHR type,
                                      vk::DeviceSize size) {
    AccelerationStructure s;
    s.storage = createBuffer(ctx, size,
                             vk::BufferUsageFlagBits::eAccelerationStructureStorageKHR |
                                 vk::BufferUsageFlagBits::eShaderDeviceAddress,
                             MemoryUse::Device);
    s.handle = vk::raii::AccelerationStructureKHR(
        ctx.device, vk::AccelerationStructureCreateInfoKHR{.buffer = *s.storage.buffer, .size = size, .type = type});
    s.address = ctx.device.getAccelerationStructureAddressKHR({.accelerationStructure = *s.handle});
    return s;
}

// One structure to build: its geometry, sizes, storage and scratch.
struct Build {
    vk::AccelerationStructureGeometryKHR geometry;
    vk::AccelerationStructureBuildGeometryInfoKHR info;
    vk::AccelerationStructureBuildRangeInfoKHR range;
    Buffer scratch;
};

// Sizes `build` for `count` primitives, creates its structure and scratch
// (aligned as the device asks), and points the build info at both.
AccelerationStructure prepare(const VulkanContext& ctx, Build& build, vk::AccelerationStructureTypeKHR type,
                              uint32_t count, vk::DeviceSize scratchAlignment) {
    build.info = vk::AccelerationStructureBuildGeometryInfoKHR{
        .type = type,
        .flags = vk::BuildAccelerationStructureFlagBitsKHR::ePreferFastTrace,
        .mode = vk::BuildAccelerationStructureModeKHR::eBuild,
        .geometryCount = 1,
        .pGeometries = &build.geometry};
    vk::AccelerationStructureBuildSizesInfoKHR sizes = ctx.device.getAccelerationStructureBuildSizesKHR(
        vk::AccelerationStructureBuildTypeKHR::eDevice, build.info, count);
    AccelerationStructure s = createStructure(ctx, type, sizes.accelerationStructureSize);
    build.scratch = createBuffer(ctx, sizes.buildScratchSize + scratchAlignment,
                                 vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress,
                                 MemoryUse::Device);
    build.info.dstAccelerationStructure = *s.handle;
    build.info.scratchData.deviceAddress = (build.scratch.address + scratchAlignment - 1) / scratchAlignment * scratchAlignment;
    build.range = vk::AccelerationStructureBuildRangeInfoKHR{.primitiveCount = count};
    return s;
}

// The triangles' geometry input: three vertices per primitive, so that the
// query's primitive index is the Primitive's. Another shape's stand-in is a
// triangle of zero area at its first point (a centre or corner), which no
// ray hits: NaN vertices (inactive, as the spec allows) made lavapipe (Mesa
// 25.0) miss whole structures.
Buffer triangleInputs(VulkanContext& ctx, std::span<const gpu::Primitive> bounded) {
    uint32_t count = uint32_t(bounded.size());
    std::vector<glm::vec3> v(size_t(count) * 3);
    for (uint32_t i = 0; i < count; ++i) {
        bool triangle = bounded[i].shape == gpu::kShapeTriangle;
        v[3 * i] = gpu::primitiveAnchor(bounded[i]);
        v[3 * i + 1] = triangle ? gpu::triangleV1(bounded[i]) : v[3 * i];
        v[3 * i + 2] = triangle ? gpu::triangleV2(bounded[i]) : v[3 * i];
    }
    return createDeviceBuffer(ctx, v.data(), v.size() * sizeof(glm::vec3), kBuildInput);
}

// The other bounded shapes' geometry input: one AABB per primitive. A
// triangle's is an empty box at its first vertex, which the shader rejects
// should a ray pass exactly through it: NaN (inactive, as the spec allows)
// made lavapipe (Mesa 25.0) miss every AABB of the structure.
Buffer boxInputs(VulkanContext& ctx, std::span<const gpu::Primitive> bounded) {
    uint32_t count = uint32_t(bounded.size());
    std::vector<vk::AabbPositionsKHR> a(count);
    for (uint32_t i = 0; i < count; ++i) {
        if (bounded[i].shape == gpu::kShapeTriangle || bounded[i].shape == gpu::kShapeInstance) {
            glm::vec3 v = gpu::primitiveAnchor(bounded[i]);
            a[i] = vk::AabbPositionsKHR{v.x, v.y, v.z, v.x, v.y, v.z};
            continue;
        }
        Aabb b = boundsOf(bounded[i]);
        a[i] = vk::AabbPositionsKHR{b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
    }
    return createDeviceBuffer(ctx, a.data(), a.size() * sizeof(vk::AabbPositionsKHR), kBuildInput);
}

// The top level's input: one instance per bottom level built, identity
// transform, custom index 0; then one per scene instance, its prototype's
// structure under its transform, custom index 1 + its index. `count` is set
// to the number of instances.
Buffer instanceInputs(VulkanContext& ctx, const SceneAccelerationStructures& bottom, const SceneInstances& scene,
                      uint32_t& count) {
    std::vector<vk::AccelerationStructureInstanceKHR> instances;
    for (size_t i = 0; i < scene.records.size(); ++i) {
        const gpu::InstanceRecord& r = scene.records[i];
        vk::AccelerationStructureInstanceKHR instance{};
        const gpu::vec4* rows[3] = {&r.worldFromObject0, &r.worldFromObject1, &r.worldFromObject2};
        for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 4; ++col) instance.transform.matrix[row][col] = (*rows[row])[col];
        instance.instanceCustomIndex = uint32_t(i + 1);
        instance.mask = 0xff;
        instance.accelerationStructureReference = bottom.prototypes[scene.instancePrototypes[i]].address;
        instances.push_back(instance);
    }
    for (const AccelerationStructure* s : {&bottom.triangles, &bottom.boxes})
        if (s->address) {
            vk::AccelerationStructureInstanceKHR instance{};
            instance.transform.matrix[0][0] = instance.transform.matrix[1][1] = instance.transform.matrix[2][2] = 1.0f;
            instance.mask = 0xff;
            instance.accelerationStructureReference = s->address;
            instances.push_back(instance);
        }
    count = uint32_t(instances.size());
    return createDeviceBuffer(ctx, instances.empty() ? nullptr : instances.data(),
                              std::max<size_t>(instances.size(), 1) * sizeof(vk::AccelerationStructureInstanceKHR),
                              kBuildInput);
}

// A BLAS of `count` triangles, three vertices each at `vertices`.
vk::AccelerationStructureGeometryKHR triangleGeometry(const Buffer& vertices, uint32_t count) {
    return vk::AccelerationStructureGeometryKHR{
        .geometryType = vk::GeometryTypeKHR::eTriangles,
        .geometry = {.triangles = vk::AccelerationStructureGeometryTrianglesDataKHR{
                         .vertexFormat = vk::Format::eR32G32B32Sfloat,
                         .vertexData = {.deviceAddress = vertices.address},
                         .vertexStride = sizeof(glm::vec3),
                         .maxVertex = 3 * count - 1,
                         .indexType = vk::IndexType::eNoneKHR}},
        // Opaque: closest hits are committed by the driver; shadow rays
        // through glass ask for every candidate (gl_RayFlagsNoOpaqueEXT).
        .flags = vk::GeometryFlagBitsKHR::eOpaque | vk::GeometryFlagBitsKHR::eNoDuplicateAnyHitInvocation};
}

// Bottom levels together, then the top level (the last build), then the
// shader's reads.
void recordBuilds(VulkanContext& ctx, const std::vector<Build>& builds) {
    size_t bottomCount = builds.size() - 1;
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
        vk::MemoryBarrier inputs{.srcAccessMask = vk::AccessFlagBits::eTransferWrite | vk::AccessFlagBits::eHostWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eShaderRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer | vk::PipelineStageFlagBits::eHost,
                            vk::PipelineStageFlagBits::eAccelerationStructureBuildKHR, {}, inputs, nullptr, nullptr);
        auto record = [&](size_t first, size_t n) {
            std::vector<vk::AccelerationStructureBuildGeometryInfoKHR> infos;
            std::vector<const vk::AccelerationStructureBuildRangeInfoKHR*> ranges;
            for (size_t i = first; i < first + n; ++i) {
                infos.push_back(builds[i].info);
                ranges.push_back(&builds[i].range);
            }
            cmd.buildAccelerationStructuresKHR(infos, ranges);
        };
        if (bottomCount > 0) {
            record(0, bottomCount);
            vk::MemoryBarrier built{.srcAccessMask = vk::AccessFlagBits::eAccelerationStructureWriteKHR,
                                    .dstAccessMask = vk::AccessFlagBits::eAccelerationStructureReadKHR};
            cmd.pipelineBarrier(vk::PipelineStageFlagBits::eAccelerationStructureBuildKHR,
                                vk::PipelineStageFlagBits::eAccelerationStructureBuildKHR, {}, built, nullptr, nullptr);
        }
        record(bottomCount, 1);
        vk::MemoryBarrier toShader{.srcAccessMask = vk::AccessFlagBits::eAccelerationStructureWriteKHR,
                                   .dstAccessMask = vk::AccessFlagBits::eAccelerationStructureReadKHR};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eAccelerationStructureBuildKHR,
                            vk::PipelineStageFlagBits::eComputeShader, {}, toShader, nullptr, nullptr);
    });
}

}  // namespace

SceneAccelerationStructures buildAccelerationStructures(VulkanContext& ctx, std::span<const gpu::Primitive> bounded,
                                                        const SceneInstances& sceneInstances) {
    auto start = std::chrono::steady_clock::now();
    auto props = ctx.physicalDevice.getProperties2<vk::PhysicalDeviceProperties2,
                                                   vk::PhysicalDeviceAccelerationStructurePropertiesKHR>();
    vk::DeviceSize scratchAlignment =
        props.get<vk::PhysicalDeviceAccelerationStructurePropertiesKHR>().minAccelerationStructureScratchOffsetAlignment;
    uint32_t count = uint32_t(bounded.size());

    // Bottom levels: one of the triangles, one of the other bounded shapes,
    // each over every primitive so that the query's primitive index is the
    // Primitive's.
    bool anyTriangle = false, anyBox = false;
    for (const gpu::Primitive& p : bounded)
        if (p.shape != gpu::kShapeInstance) (p.shape == gpu::kShapeTriangle ? anyTriangle : anyBox) = true;
    Buffer vertices, boxes;
    SceneAccelerationStructures result;
    std::vector<Build> builds;
    // The builds' infos point at their geometry: no reallocation.
    builds.reserve(3 + sceneInstances.prototypeRanges.size());
    constexpr auto kNoDuplicates = vk::GeometryFlagBitsKHR::eNoDuplicateAnyHitInvocation;
    if (anyTriangle) {
        vertices = triangleInputs(ctx, bounded);
        Build& b = builds.emplace_back();
        b.geometry = triangleGeometry(vertices, count);
        result.triangles = prepare(ctx, b, vk::AccelerationStructureTypeKHR::eBottomLevel, count, scratchAlignment);
    }
    // Each prototype's triangles (all of them triangles), indexed from its first.
    std::vector<Buffer> prototypeVertices;
    for (glm::uvec2 range : sceneInstances.prototypeRanges) {
        prototypeVertices.push_back(triangleInputs(ctx, sceneInstances.primitives.subspan(range.x, range.y)));
        Build& b = builds.emplace_back();
        b.geometry = triangleGeometry(prototypeVertices.back(), range.y);
        result.prototypes.push_back(
            prepare(ctx, b, vk::AccelerationStructureTypeKHR::eBottomLevel, range.y, scratchAlignment));
    }
    if (anyBox) {
        boxes = boxInputs(ctx, bounded);
        Build& b = builds.emplace_back();
        b.geometry = vk::AccelerationStructureGeometryKHR{
            .geometryType = vk::GeometryTypeKHR::eAabbs,
            .geometry = {.aabbs = vk::AccelerationStructureGeometryAabbsDataKHR{
                             .data = {.deviceAddress = boxes.address}, .stride = sizeof(vk::AabbPositionsKHR)}},
            .flags = vk::GeometryFlagBitsKHR::eOpaque | kNoDuplicates};
        result.boxes = prepare(ctx, b, vk::AccelerationStructureTypeKHR::eBottomLevel, count, scratchAlignment);
    }

    uint32_t instanceCount = 0;
    Buffer instanceBuffer = instanceInputs(ctx, result, sceneInstances, instanceCount);
    Build& top = builds.emplace_back();
    top.geometry = vk::AccelerationStructureGeometryKHR{
        .geometryType = vk::GeometryTypeKHR::eInstances,
        .geometry = {.instances = vk::AccelerationStructureGeometryInstancesDataKHR{
                         .data = {.deviceAddress = instanceBuffer.address}}}};
    result.top = prepare(ctx, top, vk::AccelerationStructureTypeKHR::eTopLevel, instanceCount, scratchAlignment);

    recordBuilds(ctx, builds);
    result.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace whitted

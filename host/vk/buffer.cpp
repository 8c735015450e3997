#include "vk/buffer.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

namespace whitted {

// First memory type allowed by `typeBits` that has all of `required`,
// preferring one that also has `preferred`.
uint32_t findMemoryType(const vk::raii::PhysicalDevice& physical, uint32_t typeBits,
                        vk::MemoryPropertyFlags required, vk::MemoryPropertyFlags preferred) {
    auto props = physical.getMemoryProperties();
    std::optional<uint32_t> fallback;
    for (uint32_t i = 0; i < props.memoryTypeCount; ++i) {
        if (!(typeBits & (1u << i))) continue;
        auto flags = props.memoryTypes[i].propertyFlags;
        if ((flags & required) != required) continue;
        if ((flags & preferred) == preferred) return i;
        if (!fallback) fallback = i;
    }
    if (!fallback) throw std::runtime_error("no Vulkan memory type fits the buffer (" + vk::to_string(required) + ")");
    return *fallback;
}

Buffer createBuffer(const VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage,
                    vk::MemoryPropertyFlags properties) {
    Buffer b;
    b.size = std::max<vk::DeviceSize>(size, 16);  // zero-sized buffers are invalid
    try {
        b.buffer = vk::raii::Buffer(ctx.device, vk::BufferCreateInfo{.size = b.size, .usage = usage,
                                                                      .sharingMode = vk::SharingMode::eExclusive});
        auto req = b.buffer.getMemoryRequirements();
        vk::MemoryPropertyFlags preferred = properties;
        if (properties & vk::MemoryPropertyFlagBits::eHostVisible) preferred |= vk::MemoryPropertyFlagBits::eHostCached;
        uint32_t type = findMemoryType(ctx.physicalDevice, req.memoryTypeBits, properties, preferred);
        bool addressed = bool(usage & vk::BufferUsageFlagBits::eShaderDeviceAddress);
        vk::MemoryAllocateFlagsInfo flags{.flags = vk::MemoryAllocateFlagBits::eDeviceAddress};
        b.memory = vk::raii::DeviceMemory(ctx.device, vk::MemoryAllocateInfo{.pNext = addressed ? &flags : nullptr,
                                                                             .allocationSize = req.size,
                                                                             .memoryTypeIndex = type});
        b.buffer.bindMemory(*b.memory, 0);
        if (properties & vk::MemoryPropertyFlagBits::eHostVisible) {
            b.mapped = b.memory.mapMemory(0, VK_WHOLE_SIZE);
            // lavapipe (Mesa 25.0) reports success and maps to MAP_FAILED
            // when its mmap of the allocation fails (seen under ulimit -v).
            if (!b.mapped || b.mapped == reinterpret_cast<void*>(intptr_t(-1)))
                throw vk::OutOfHostMemoryError("vkMapMemory returned no mapping");
        }
        if (addressed) b.address = ctx.device.getBufferAddress({.buffer = *b.buffer});
    } catch (const vk::OutOfDeviceMemoryError& e) {
        throw std::runtime_error("out of device memory for a buffer of " + std::to_string(b.size) + " bytes (" +
                                 std::to_string(b.size >> 20) + " MiB): " + e.what());
    } catch (const vk::OutOfHostMemoryError& e) {
        throw std::runtime_error("out of host memory for a buffer of " + std::to_string(b.size) + " bytes (" +
                                 std::to_string(b.size >> 20) + " MiB): " + e.what());
    }
    return b;
}

Buffer createDeviceBuffer(VulkanContext& ctx, const void* data, vk::DeviceSize size, vk::BufferUsageFlags usage) {
    // A device that works in host memory (lavapipe, an integrated GPU) is
    // written directly: a staging copy would hold the data twice (640 MB more
    // for a 10M-triangle mesh).
    auto shared = vk::MemoryPropertyFlagBits::eDeviceLocal | vk::MemoryPropertyFlagBits::eHostVisible |
                  vk::MemoryPropertyFlagBits::eHostCoherent;
    vk::PhysicalDeviceType type = ctx.physicalDevice.getProperties().deviceType;
    auto memoryTypes = ctx.physicalDevice.getMemoryProperties().memoryTypes;
    bool unified = (type == vk::PhysicalDeviceType::eCpu || type == vk::PhysicalDeviceType::eIntegratedGpu) &&
                   std::any_of(memoryTypes.begin(), memoryTypes.end(),
                               [&](const vk::MemoryType& t) { return (t.propertyFlags & shared) == shared; });
    if (data && size > 0 && unified) {
        Buffer direct = createBuffer(ctx, size, usage, shared);
        std::memcpy(direct.mapped, data, size);
        return direct;
    }
    Buffer device = createBuffer(ctx, size, usage | vk::BufferUsageFlagBits::eTransferDst,
                                 vk::MemoryPropertyFlagBits::eDeviceLocal);
    if (data && size > 0) {
        Buffer staging = createBuffer(ctx, size, vk::BufferUsageFlagBits::eTransferSrc,
                                      vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent);
        std::memcpy(staging.mapped, data, size);
        ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
            cmd.copyBuffer(*staging.buffer, *device.buffer, vk::BufferCopy{0, 0, size});
        });
    } else {
        ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) { cmd.fillBuffer(*device.buffer, 0, VK_WHOLE_SIZE, 0); });
    }
    return device;
}

void readBuffer(VulkanContext& ctx, const Buffer& source, void* destination, vk::DeviceSize size) {
    Buffer staging = createBuffer(ctx, size, vk::BufferUsageFlagBits::eTransferDst,
                                  vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent);
    ctx.submitAndWait([&](vk::raii::CommandBuffer& cmd) {
        // Earlier shader or transfer writes to the source come first.
        vk::MemoryBarrier fromWriters{.srcAccessMask = vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
                                      .dstAccessMask = vk::AccessFlagBits::eTransferRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer,
                            vk::PipelineStageFlagBits::eTransfer, {}, fromWriters, nullptr, nullptr);
        cmd.copyBuffer(*source.buffer, *staging.buffer, vk::BufferCopy{0, 0, size});
        // Make the copy visible to host reads after the fence.
        vk::MemoryBarrier toHost{.srcAccessMask = vk::AccessFlagBits::eTransferWrite,
                                 .dstAccessMask = vk::AccessFlagBits::eHostRead};
        cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eHost, {}, toHost,
                            nullptr, nullptr);
    });
    std::memcpy(destination, staging.mapped, size);
}

}  // namespace whitted

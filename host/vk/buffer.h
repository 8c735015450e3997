// Buffers and their memory: device-local storage with staged upload and
// read-back, and host-visible staging memory.
#pragma once

#include "vk/context.h"

namespace whitted {

struct Buffer {
    vk::raii::Buffer buffer{nullptr};
    vk::raii::DeviceMemory memory{nullptr};
    vk::DeviceSize size = 0;
    void* mapped = nullptr;  // non-null for host-visible buffers
    vk::DeviceAddress address = 0;  // for shaders, when made with eShaderDeviceAddress usage
};

// First memory type allowed by `typeBits` that has all of `required`,
// preferring one that also has `preferred`; throws if none.
uint32_t findMemoryType(const vk::raii::PhysicalDevice& physical, uint32_t typeBits,
                        vk::MemoryPropertyFlags required, vk::MemoryPropertyFlags preferred);

// A buffer in memory with `properties`; host-visible memory is mapped. With
// eShaderDeviceAddress usage its memory is allocated for device addresses
// and `address` is set. Running out of device or host memory throws a
// runtime_error that names the size asked for.
Buffer createBuffer(const VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage,
                    vk::MemoryPropertyFlags properties);

// A device-local buffer filled with `size` bytes of `data` through a staging
// buffer (data may be null for a zero-filled buffer).
Buffer createDeviceBuffer(VulkanContext& ctx, const void* data, vk::DeviceSize size, vk::BufferUsageFlags usage);

// Copies `size` bytes of a device buffer back into host memory.
void readBuffer(VulkanContext& ctx, const Buffer& source, void* destination, vk::DeviceSize size);

}  // namespace whitted

// Buffers and their memory (vk/memory.h): device-local storage with staged
// upload and read-back, host-visible staging memory, and buffers both the
// shader and the host use (MirroredBuffer).
#pragma once

#include "vk/context.h"
#include "vk/memory.h"

namespace whitted {

// The buffer is destroyed before its memory is given back (declared after
// it; a buffer assigned over drops its old buffer first).
struct Buffer {
    Buffer() = default;
    Buffer(Buffer&&) noexcept = default;
    Buffer& operator=(Buffer&& other) noexcept {
        buffer = std::move(other.buffer);
        allocation = std::move(other.allocation);
        size = std::exchange(other.size, 0);
        mapped = std::exchange(other.mapped, nullptr);
        address = std::exchange(other.address, 0);
        return *this;
    }

    Allocation allocation;
    vk::raii::Buffer buffer{nullptr};
    vk::DeviceSize size = 0;
    void* mapped = nullptr;  // non-null for memory the host maps
    vk::DeviceAddress address = 0;  // for shaders, when made with eShaderDeviceAddress usage
};

// A buffer in memory for `use`, from the context's allocator; mapped
// memory is mapped. With eShaderDeviceAddress usage `address` is set.
// Running out of device or host memory throws DeviceFailure.
Buffer createBuffer(const VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage, MemoryUse use);

// A device-local buffer filled with `size` bytes of `data` (data may be
// null for a zero-filled buffer): through a staging buffer, or on a device
// with unified memory written in place (Shared memory, mapped).
Buffer createDeviceBuffer(VulkanContext& ctx, const void* data, vk::DeviceSize size, vk::BufferUsageFlags usage);

// Copies `size` bytes of a device buffer back into host memory.
void readBuffer(VulkanContext& ctx, const Buffer& source, void* destination, vk::DeviceSize size);

// A buffer the shader reads or writes at every sample and the host reads or
// writes between submissions (the adaptive pass's pixel list, guide and
// statistics, the ray counters, the ray-tree record, cast rays). On a
// device with unified memory it is one Shared buffer the host maps; else a
// device-local buffer and a host-visible twin, and the host's side reaches
// the device by the copies recorded with recordUpload and recordDownload.
class MirroredBuffer {
public:
    MirroredBuffer() = default;
    // Zero-filled on both sides. `usage` is the device side's (storage, addresses).
    MirroredBuffer(VulkanContext& ctx, vk::DeviceSize size, vk::BufferUsageFlags usage);

    const Buffer& device() const { return device_; }
    void* host() const { return device_.mapped ? device_.mapped : host_.mapped; }
    vk::DeviceSize size() const { return device_.size; }
    bool staged() const { return bool(*host_.buffer); }

    // The host's first `bytes` copied to the device, with the barrier that
    // makes them visible to the shader (recorded before the dispatches that
    // read them; nothing when unified).
    void recordUpload(const vk::raii::CommandBuffer& cmd, vk::DeviceSize bytes) const;
    // The shader's first `bytes` copied to the host's side, after the
    // dispatches, and made visible to the host (which reads them once the
    // submission is done).
    void recordDownload(const vk::raii::CommandBuffer& cmd, vk::DeviceSize bytes) const;
    // Both sides zeroed: on the host, and (when staged) a fill recorded.
    void recordZero(const vk::raii::CommandBuffer& cmd) const;

private:
    Buffer device_;
    Buffer host_;  // empty when unified
};

}  // namespace whitted

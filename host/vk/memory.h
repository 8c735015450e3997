// Device memory: a few large blocks per memory type and use, sub-allocated
// first fit, so that a scene's many buffers cost a few vkAllocateMemory
// calls (drivers allow as few as 4096 allocations, and a GPU pages memory
// in by allocation), each with its priority (VK_EXT_memory_priority). The
// layout follows AMD's Vulkan Memory Allocator (VMA) in its simplest form:
// blocks that grow from 1/8 of the preferred size, requests of half a block
// or more in a block of their own, an empty block kept for the next use.
#pragma once

#include <vulkan/vulkan_raii.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace whitted {

class DeviceEvents;

// What the memory is for; each use has blocks of its own.
enum class MemoryUse : uint8_t {
    Device,    // read and written by shaders only: device-local, never mapped
    Shared,    // device-local and mapped: only on a unified-memory device (lavapipe, an integrated GPU)
    Upload,    // written by the host and copied to the device (staging, uniform parameters)
    Readback,  // copied from the device and read by the host
};
inline constexpr size_t kMemoryUseCount = 4;
const char* memoryUseName(MemoryUse use);

struct MemoryBlock;
class MemoryAllocator;

// A range of one block, given back when destroyed. A buffer or image bound
// to it must be destroyed first (declare the Allocation before it).
class Allocation {
public:
    Allocation() = default;
    Allocation(Allocation&& other) noexcept { *this = std::move(other); }
    Allocation& operator=(Allocation&& other) noexcept;
    ~Allocation() { release(); }

    vk::DeviceMemory memory() const;
    vk::DeviceSize offset() const { return offset_; }
    void* mapped() const;  // null unless the use is mapped
    explicit operator bool() const { return block_ != nullptr; }

private:
    friend class MemoryAllocator;
    void release();

    MemoryAllocator* owner_ = nullptr;
    MemoryBlock* block_ = nullptr;
    vk::DeviceSize offset_ = 0, size_ = 0;
};

// What the allocator holds and has done, for tests and the render record.
struct MemoryStats {
    uint32_t blocks = 0;              // live vkAllocateMemory allocations
    uint32_t allocationCalls = 0;     // vkAllocateMemory calls so far
    uint64_t bytes[kMemoryUseCount] = {};  // bytes in blocks, per use
    uint64_t requested[kMemoryUseCount] = {};  // ranges handed out so far, per use (bytes)
};

struct MemoryOptions {
    // The device works in host memory: per-sample buffers may be Shared.
    bool unified = false;
    // VK_EXT_memory_priority is enabled: each block says its priority.
    bool priorities = false;
    // VK_EXT_pageable_device_local_memory is enabled too: each block's
    // priority is also set after allocation (vkSetDeviceMemoryPriorityEXT).
    bool pageable = false;
    vk::DeviceSize preferredBlockSize = vk::DeviceSize(64) << 20;
};

class MemoryAllocator {
public:
    MemoryAllocator(const vk::raii::PhysicalDevice& physical, const vk::raii::Device& device, MemoryOptions options,
                    DeviceEvents* events = nullptr);
    MemoryAllocator(const MemoryAllocator&) = delete;
    MemoryAllocator& operator=(const MemoryAllocator&) = delete;
    ~MemoryAllocator();

    // Memory for a buffer or an image (`image`: optimal tiling, kept in
    // blocks apart from buffers, so bufferImageGranularity never applies).
    // Running out of device or host memory throws DeviceFailure (naming
    // what `events` says the device is doing).
    Allocation allocate(const vk::MemoryRequirements& requirements, MemoryUse use, bool image = false);
    bool unified() const { return options_.unified; }
    MemoryStats stats() const;

private:
    friend class Allocation;
    struct Key {
        uint32_t type;
        MemoryUse use;
        bool image;
        auto operator<=>(const Key&) const = default;
    };
    uint32_t memoryType(uint32_t typeBits, MemoryUse use) const;
    MemoryBlock& newBlock(const Key& key, vk::DeviceSize size, bool dedicated);
    void free(MemoryBlock* block, vk::DeviceSize offset, vk::DeviceSize size);

    const vk::raii::Device& device_;
    vk::PhysicalDeviceMemoryProperties properties_;
    MemoryOptions options_;
    DeviceEvents* events_;
    mutable std::mutex mutex_;
    std::map<Key, std::vector<std::unique_ptr<MemoryBlock>>> blocks_;
    MemoryStats stats_;
};

}  // namespace whitted

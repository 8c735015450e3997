// Vulkan instance, device choice, logical device and compute queue.
#pragma once

#include "vk/device_events.h"
#include "vk/device_info.h"
#include "vk/memory.h"
#include "vk/pipeline_cache.h"

#include <vulkan/vulkan_raii.hpp>

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>


namespace whitted {


// WHITTED_VALIDATION=1 (anything but empty or 0) turns the validation layer
// on, as `whitted render --validate` does (the commands and the Python module).
bool validationFromEnvironment();

struct ContextOptions {
    bool validation = false;        // enable VK_LAYER_KHRONOS_validation
    std::string deviceName;         // substring or index; empty = best
    // Windowed use (`whitted view`): extra instance extensions (the window
    // system's surface ones), VK_KHR_swapchain on the device, and a queue
    // family that also does graphics (blits) and can present, as told by
    // `canPresent`. Headless when `canPresent` is empty.
    std::vector<std::string> instanceExtensions{};
    std::function<bool(VkInstance, VkPhysicalDevice, uint32_t family)> canPresent{};
    // The folder of the pipeline cache files (vk/pipeline_cache.h); an empty
    // path keeps the cache in memory only. Unset: from the environment.
    std::optional<std::filesystem::path> pipelineCacheFolder{};
    // Memory as on a discrete GPU even on a device that works in host
    // memory (lavapipe): nothing Shared, every upload and read-back through
    // staging copies (vk/memory.h). Unset: WHITTED_DISCRETE_MEMORY=1 in a
    // test build (WHITTED_TEST_HOOKS), else off.
    std::optional<bool> discreteMemory{};
};

// WHITTED_DISCRETE_MEMORY (test builds only): anything but empty or 0.
bool discreteMemoryFromEnvironment();

// Owns the Vulkan objects every renderer needs. Validation messages (when
// enabled) are printed to stderr and counted so that tests and `render`
// can fail on them.
class VulkanContext {
public:
    explicit VulkanContext(const ContextOptions& options);
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    static std::vector<DeviceInfo> listDevices();

    const DeviceInfo& deviceInfo() const { return info_; }
    uint32_t validationMessageCount() const { return validationMessages_->load(); }

    vk::raii::Context context;
    vk::raii::Instance instance{nullptr};
    vk::raii::DebugUtilsMessengerEXT messenger{nullptr};
    vk::raii::PhysicalDevice physicalDevice{nullptr};
    vk::raii::Device device{nullptr};
    vk::raii::Queue queue{nullptr};
    uint32_t queueFamily = 0;
    vk::raii::CommandPool commandPool{nullptr};
    // Every pipeline is created through it and saved into it
    // (createComputePipeline); a pointer so that a const context can save.
    std::unique_ptr<PipelineCache> pipelineCache;
    // Counts submissions and allocations, knows what the device is doing
    // (DeviceActivity), turns a lost device or exhausted memory into a
    // DeviceFailure; a pointer so that a const context can count.
    std::unique_ptr<DeviceEvents> events;
    // Every buffer's and image's memory (vk/memory.h); goes before the device.
    std::unique_ptr<MemoryAllocator> memory;

    // Every queue submission goes through these two: a lost device (or an
    // injected fault) throws DeviceFailure.
    void submit(const vk::SubmitInfo& info, vk::Fence fence) const;
    void waitForFence(vk::Fence fence) const;

    // Runs `record` on a one-time command buffer, submits it and waits.
    template <typename F>
    void submitAndWait(F&& record) {
        vk::raii::CommandBuffers buffers(device, {.commandPool = *commandPool,
                                                  .level = vk::CommandBufferLevel::ePrimary,
                                                  .commandBufferCount = 1});
        vk::raii::CommandBuffer& cmd = buffers.front();
        cmd.begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
        record(cmd);
        cmd.end();
        vk::raii::Fence fence(device, vk::FenceCreateInfo{});
        vk::CommandBuffer raw = *cmd;
        submit(vk::SubmitInfo{.commandBufferCount = 1, .pCommandBuffers = &raw}, *fence);
        waitForFence(*fence);
    }

private:
    DeviceInfo info_;
    // Heap-allocated so the debug callback's user pointer stays valid.
    std::unique_ptr<std::atomic<uint32_t>> validationMessages_ =
        std::make_unique<std::atomic<uint32_t>>(0);
};

}  // namespace whitted

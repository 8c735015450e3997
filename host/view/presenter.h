// Shows the renderer's accumulation buffer in a window: a swapchain, the
// display compute pass (shaders/display.comp) into a packed RGBA8 buffer, a
// copy and blit of that into the swapchain image, then the ImGui overlay on
// top. One frame in flight: endFrame() waits for the GPU, which keeps the
// progressive renderer's uniform updates simple and its frame times honest.
#pragma once

#include <cstdint>
#include <vector>

#include "display_types.h"
#include "vk/buffer.h"
#include "vk/compute_pipeline.h"
#include "vk/context.h"

struct GLFWwindow;
struct ImDrawData;

namespace whitted {

// An 8-bit RGBA image, rows from the top.
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> pixels;
};

class Presenter {
public:
    // `source` is the renderer's output buffer (sums of imageWidth x imageHeight pixels).
    Presenter(VulkanContext& ctx, GLFWwindow* window, const Buffer& source, int imageWidth, int imageHeight);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    // Acquires a swapchain image and begins the frame's command buffer;
    // false when the swapchain had to be rebuilt (skip this frame).
    bool beginFrame();
    // Records the display pass and the blit into the acquired image.
    void recordDisplay(const gpu::DisplayParams& display);
    // Records ImGui's draw lists over the image; `captureWindow` also copies
    // the finished swapchain image back (see windowPixels()).
    void recordOverlay(ImDrawData* drawData, bool captureWindow);
    // Submits, presents and waits until the GPU is done; returns the seconds
    // the GPU took (submit to fence).
    double endFrame();

    // The image shown, without the overlay, as the last frame left it.
    Rgba8Image displayPixels() const;
    // The whole window with its overlay, as captured by recordOverlay.
    Rgba8Image windowPixels() const;

    // For ImGui's Vulkan back end.
    vk::RenderPass renderPass() const { return *renderPass_; }
    uint32_t imageCount() const { return uint32_t(swapImages_.size()); }
    uint32_t minImageCount() const { return minImageCount_; }
    // Runs `record` on a one-time command buffer and waits (font upload).
    template <typename F>
    void immediate(F&& record) {
        ctx_.submitAndWait(std::forward<F>(record));
    }

private:
    void createSwapchain();

    VulkanContext& ctx_;
    GLFWwindow* window_;
    int width_, height_;
    vk::raii::SurfaceKHR surface_{nullptr};
    vk::SurfaceFormatKHR surfaceFormat_{};
    vk::Extent2D extent_{};
    uint32_t minImageCount_ = 2;
    vk::raii::SwapchainKHR swapchain_{nullptr};
    std::vector<vk::Image> swapImages_;
    std::vector<vk::raii::ImageView> swapViews_;
    std::vector<vk::raii::Framebuffer> framebuffers_;
    std::vector<vk::raii::Semaphore> renderDone_;  // one per swapchain image
    vk::raii::RenderPass renderPass_{nullptr};

    ComputePipeline pipeline_;
    vk::raii::DescriptorPool descriptorPool_{nullptr};
    vk::raii::DescriptorSet descriptorSet_{nullptr};
    Buffer displayBuffer_;  // host-visible packed RGBA8, the screenshot source
    Buffer windowBuffer_;   // host-visible copy of the swapchain image
    Rgba8Image windowCapture_;
    bool windowCaptured_ = false;
    Allocation displayMemory_;  // declared first: outlives the image bound to it
    vk::raii::Image displayImage_{nullptr};

    vk::raii::CommandPool commandPool_{nullptr};  // the frame's own: reset whole each frame
    vk::raii::CommandBuffer cmd_{nullptr};
    vk::raii::Semaphore imageAcquired_{nullptr};
    vk::raii::Fence frameDone_{nullptr};
    uint32_t imageIndex_ = 0;
    bool frameOpen_ = false;
};

}  // namespace whitted

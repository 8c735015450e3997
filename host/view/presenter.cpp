#include "view/presenter.h"

#include "display_comp.h"  // kDisplayCompSpv, generated from shaders/display.comp

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui/backends/imgui_impl_vulkan.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace whitted {
namespace {

// The swapchain format: plain 8-bit BGRA/RGBA; the display pass encodes
// sRGB itself, so a UNORM format shows its bytes as they are.
vk::SurfaceFormatKHR chooseFormat(const std::vector<vk::SurfaceFormatKHR>& formats) {
    for (vk::Format wanted : {vk::Format::eB8G8R8A8Unorm, vk::Format::eR8G8B8A8Unorm})
        for (const auto& f : formats)
            if (f.format == wanted) return f;
    for (vk::Format wanted : {vk::Format::eB8G8R8A8Srgb, vk::Format::eR8G8B8A8Srgb})
        for (const auto& f : formats)
            if (f.format == wanted) return f;
    throw std::runtime_error("the window surface offers no 8-bit RGBA or BGRA format");
}

bool isSrgb(vk::Format f) {
    return f == vk::Format::eB8G8R8A8Srgb || f == vk::Format::eR8G8B8A8Srgb;
}

void imageBarrier(const vk::raii::CommandBuffer& cmd, vk::Image image, vk::ImageLayout from, vk::ImageLayout to,
                  vk::PipelineStageFlags srcStage, vk::AccessFlags srcAccess, vk::PipelineStageFlags dstStage,
                  vk::AccessFlags dstAccess) {
    vk::ImageMemoryBarrier b{.srcAccessMask = srcAccess,
                             .dstAccessMask = dstAccess,
                             .oldLayout = from,
                             .newLayout = to,
                             .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                             .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                             .image = image,
                             .subresourceRange = {vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1}};
    cmd.pipelineBarrier(srcStage, dstStage, {}, nullptr, nullptr, b);
}

}  // namespace

Presenter::Presenter(VulkanContext& ctx, GLFWwindow* window, const Buffer& source, int imageWidth, int imageHeight)
    : ctx_(ctx), window_(window), width_(imageWidth), height_(imageHeight) {
    VkSurfaceKHR raw = VK_NULL_HANDLE;
    if (VkResult r = glfwCreateWindowSurface(*ctx.instance, window, nullptr, &raw); r != VK_SUCCESS)
        throw std::runtime_error("glfwCreateWindowSurface: " + vk::to_string(vk::Result(r)));
    surface_ = vk::raii::SurfaceKHR(ctx.instance, raw);
    if (!ctx.physicalDevice.getSurfaceSupportKHR(ctx.queueFamily, *surface_))
        throw std::runtime_error("the chosen queue cannot present to this window");
    surfaceFormat_ = chooseFormat(ctx.physicalDevice.getSurfaceFormatsKHR(*surface_));

    // ImGui draws over the blitted image: load, don't clear.
    vk::AttachmentDescription color{.format = surfaceFormat_.format,
                                    .samples = vk::SampleCountFlagBits::e1,
                                    .loadOp = vk::AttachmentLoadOp::eLoad,
                                    .storeOp = vk::AttachmentStoreOp::eStore,
                                    .stencilLoadOp = vk::AttachmentLoadOp::eDontCare,
                                    .stencilStoreOp = vk::AttachmentStoreOp::eDontCare,
                                    .initialLayout = vk::ImageLayout::eColorAttachmentOptimal,
                                    .finalLayout = vk::ImageLayout::ePresentSrcKHR};
    vk::AttachmentReference colorRef{0, vk::ImageLayout::eColorAttachmentOptimal};
    vk::SubpassDescription subpass{.pipelineBindPoint = vk::PipelineBindPoint::eGraphics,
                                   .colorAttachmentCount = 1,
                                   .pColorAttachments = &colorRef};
    vk::SubpassDependency dependency{
        .srcSubpass = VK_SUBPASS_EXTERNAL,
        .dstSubpass = 0,
        .srcStageMask = vk::PipelineStageFlagBits::eColorAttachmentOutput,
        .dstStageMask = vk::PipelineStageFlagBits::eColorAttachmentOutput,
        .srcAccessMask = vk::AccessFlagBits::eColorAttachmentWrite,
        .dstAccessMask = vk::AccessFlagBits::eColorAttachmentRead | vk::AccessFlagBits::eColorAttachmentWrite};
    renderPass_ = vk::raii::RenderPass(ctx.device, vk::RenderPassCreateInfo{.attachmentCount = 1,
                                                                            .pAttachments = &color,
                                                                            .subpassCount = 1,
                                                                            .pSubpasses = &subpass,
                                                                            .dependencyCount = 1,
                                                                            .pDependencies = &dependency});
    createSwapchain();

    // The display pass.
    const vk::DescriptorType bindings[] = {vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer};
    pipeline_ = createComputePipeline(ctx, kDisplayCompSpv, bindings, sizeof(gpu::DisplayParams));
    vk::DeviceSize bytes = vk::DeviceSize(width_) * height_ * 4;
    displayBuffer_ = createBuffer(ctx, bytes,
                                  vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferSrc,
                                  MemoryUse::Readback);
    std::memset(displayBuffer_.mapped, 0, bytes);
    vk::DescriptorPoolSize poolSize{vk::DescriptorType::eStorageBuffer, 2};
    descriptorPool_ = vk::raii::DescriptorPool(
        ctx.device, vk::DescriptorPoolCreateInfo{.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                 .maxSets = 1,
                                                 .poolSizeCount = 1,
                                                 .pPoolSizes = &poolSize});
    vk::DescriptorSetLayout setLayout = *pipeline_.setLayout;
    descriptorSet_ = std::move(
        vk::raii::DescriptorSets(
            ctx.device, {.descriptorPool = *descriptorPool_, .descriptorSetCount = 1, .pSetLayouts = &setLayout})
            .front());
    vk::DescriptorBufferInfo infos[] = {{*source.buffer, 0, VK_WHOLE_SIZE}, {*displayBuffer_.buffer, 0, VK_WHOLE_SIZE}};
    vk::WriteDescriptorSet writes[] = {{.dstSet = *descriptorSet_,
                                        .dstBinding = gpu::kBindingDisplayInput,
                                        .descriptorCount = 1,
                                        .descriptorType = vk::DescriptorType::eStorageBuffer,
                                        .pBufferInfo = &infos[0]},
                                       {.dstSet = *descriptorSet_,
                                        .dstBinding = gpu::kBindingDisplayOutput,
                                        .descriptorCount = 1,
                                        .descriptorType = vk::DescriptorType::eStorageBuffer,
                                        .pBufferInfo = &infos[1]}};
    ctx.device.updateDescriptorSets(writes, nullptr);

    // The image the packed pixels are copied into and blitted from; sRGB
    // when the swapchain is, so that the blit passes the bytes through.
    vk::Format displayFormat = isSrgb(surfaceFormat_.format) ? vk::Format::eR8G8B8A8Srgb : vk::Format::eR8G8B8A8Unorm;
    displayImage_ = vk::raii::Image(ctx.device, vk::ImageCreateInfo{.imageType = vk::ImageType::e2D,
                                                                    .format = displayFormat,
                                                                    .extent = {uint32_t(width_), uint32_t(height_), 1},
                                                                    .mipLevels = 1,
                                                                    .arrayLayers = 1,
                                                                    .samples = vk::SampleCountFlagBits::e1,
                                                                    .tiling = vk::ImageTiling::eOptimal,
                                                                    .usage = vk::ImageUsageFlagBits::eTransferDst |
                                                                             vk::ImageUsageFlagBits::eTransferSrc,
                                                                    .sharingMode = vk::SharingMode::eExclusive,
                                                                    .initialLayout = vk::ImageLayout::eUndefined});
    auto req = displayImage_.getMemoryRequirements();
    displayMemory_ = ctx.memory->allocate(req, MemoryUse::Device, true);
    displayImage_.bindMemory(displayMemory_.memory(), displayMemory_.offset());

    commandPool_ = vk::raii::CommandPool(ctx.device, vk::CommandPoolCreateInfo{.queueFamilyIndex = ctx.queueFamily});
    cmd_ = std::move(vk::raii::CommandBuffers(ctx.device, {.commandPool = *commandPool_,
                                                           .level = vk::CommandBufferLevel::ePrimary,
                                                           .commandBufferCount = 1})
                         .front());
    imageAcquired_ = vk::raii::Semaphore(ctx.device, vk::SemaphoreCreateInfo{});
    frameDone_ = vk::raii::Fence(ctx.device, vk::FenceCreateInfo{});
}

Presenter::~Presenter() {
    try {
        ctx_.device.waitIdle();
    } catch (...) {
    }
}

void Presenter::createSwapchain() {
    auto caps = ctx_.physicalDevice.getSurfaceCapabilitiesKHR(*surface_);
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window_, &fbWidth, &fbHeight);
    if (caps.currentExtent.width != UINT32_MAX) {
        extent_ = caps.currentExtent;
    } else {
        extent_.width =
            std::clamp(uint32_t(std::max(fbWidth, 1)), caps.minImageExtent.width, caps.maxImageExtent.width);
        extent_.height =
            std::clamp(uint32_t(std::max(fbHeight, 1)), caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    auto usage = vk::ImageUsageFlagBits::eColorAttachment | vk::ImageUsageFlagBits::eTransferDst |
                 vk::ImageUsageFlagBits::eTransferSrc;
    if ((caps.supportedUsageFlags & usage) != usage)
        throw std::runtime_error("the window's swapchain images cannot be blitted to and copied from");
    minImageCount_ = std::max(2u, caps.minImageCount);
    uint32_t count = caps.maxImageCount ? std::min(caps.minImageCount + 1, caps.maxImageCount) : caps.minImageCount + 1;

    // Mailbox or immediate keep a slow frame from waiting on vertical sync.
    auto modes = ctx_.physicalDevice.getSurfacePresentModesKHR(*surface_);
    vk::PresentModeKHR mode = vk::PresentModeKHR::eFifo;
    for (vk::PresentModeKHR wanted : {vk::PresentModeKHR::eImmediate, vk::PresentModeKHR::eMailbox})
        if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) mode = wanted;

    vk::SwapchainKHR old = *swapchain_;
    vk::raii::SwapchainKHR fresh(ctx_.device,
                                 vk::SwapchainCreateInfoKHR{.surface = *surface_,
                                                            .minImageCount = count,
                                                            .imageFormat = surfaceFormat_.format,
                                                            .imageColorSpace = surfaceFormat_.colorSpace,
                                                            .imageExtent = extent_,
                                                            .imageArrayLayers = 1,
                                                            .imageUsage = usage,
                                                            .imageSharingMode = vk::SharingMode::eExclusive,
                                                            .preTransform = caps.currentTransform,
                                                            .compositeAlpha = vk::CompositeAlphaFlagBitsKHR::eOpaque,
                                                            .presentMode = mode,
                                                            .clipped = VK_TRUE,
                                                            .oldSwapchain = old});
    framebuffers_.clear();
    swapViews_.clear();
    swapchain_ = std::move(fresh);
    swapImages_ = swapchain_.getImages();
    renderDone_.clear();
    for (vk::Image image : swapImages_) {
        swapViews_.emplace_back(
            ctx_.device, vk::ImageViewCreateInfo{.image = image,
                                                 .viewType = vk::ImageViewType::e2D,
                                                 .format = surfaceFormat_.format,
                                                 .subresourceRange = {vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1}});
        vk::ImageView view = *swapViews_.back();
        framebuffers_.emplace_back(ctx_.device, vk::FramebufferCreateInfo{.renderPass = *renderPass_,
                                                                          .attachmentCount = 1,
                                                                          .pAttachments = &view,
                                                                          .width = extent_.width,
                                                                          .height = extent_.height,
                                                                          .layers = 1});
        renderDone_.emplace_back(ctx_.device, vk::SemaphoreCreateInfo{});
    }
    windowBuffer_ =
        createBuffer(ctx_, vk::DeviceSize(extent_.width) * extent_.height * 4, vk::BufferUsageFlagBits::eTransferDst,
                     MemoryUse::Readback);
}

bool Presenter::beginFrame() {
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window_, &fbWidth, &fbHeight);
    if (fbWidth == 0 || fbHeight == 0) return false;  // minimised
    vk::Result result;
    try {
        std::tie(result, imageIndex_) = swapchain_.acquireNextImage(UINT64_MAX, *imageAcquired_, nullptr);
    } catch (const vk::OutOfDateKHRError&) {
        result = vk::Result::eErrorOutOfDateKHR;
    }
    if (result == vk::Result::eErrorOutOfDateKHR) {
        ctx_.device.waitIdle();
        createSwapchain();
        return false;
    }
    commandPool_.reset();
    cmd_.begin({.flags = vk::CommandBufferUsageFlagBits::eOneTimeSubmit});
    frameOpen_ = true;
    windowCaptured_ = false;
    return true;
}

void Presenter::recordDisplay(const gpu::DisplayParams& display) {
    using Stage = vk::PipelineStageFlagBits;
    using Access = vk::AccessFlagBits;
    // Sums written by the tracer -> display pass.
    vk::MemoryBarrier sums{.srcAccessMask = Access::eShaderWrite | Access::eTransferWrite,
                           .dstAccessMask = Access::eShaderRead};
    cmd_.pipelineBarrier(Stage::eComputeShader | Stage::eTransfer, Stage::eComputeShader, {}, sums, nullptr, nullptr);
    cmd_.bindPipeline(vk::PipelineBindPoint::eCompute, *pipeline_.pipeline);
    cmd_.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *pipeline_.layout, 0, *descriptorSet_, nullptr);
    cmd_.pushConstants<gpu::DisplayParams>(*pipeline_.layout, vk::ShaderStageFlagBits::eCompute, 0, display);
    cmd_.dispatch((width_ + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize,
                  (height_ + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1);

    // Packed pixels -> display image -> swapchain image (scaled to the window).
    vk::MemoryBarrier packed{.srcAccessMask = Access::eShaderWrite,
                             .dstAccessMask = Access::eTransferRead | Access::eHostRead};
    cmd_.pipelineBarrier(Stage::eComputeShader, Stage::eTransfer | Stage::eHost, {}, packed, nullptr, nullptr);
    imageBarrier(cmd_, *displayImage_, vk::ImageLayout::eUndefined, vk::ImageLayout::eTransferDstOptimal,
                 Stage::eTopOfPipe, {}, Stage::eTransfer, Access::eTransferWrite);
    vk::BufferImageCopy copy{.bufferOffset = 0,
                             .imageSubresource = {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
                             .imageExtent = {uint32_t(width_), uint32_t(height_), 1}};
    cmd_.copyBufferToImage(*displayBuffer_.buffer, *displayImage_, vk::ImageLayout::eTransferDstOptimal, copy);
    imageBarrier(cmd_, *displayImage_, vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::eTransferSrcOptimal,
                 Stage::eTransfer, Access::eTransferWrite, Stage::eTransfer, Access::eTransferRead);
    vk::Image target = swapImages_[imageIndex_];
    imageBarrier(cmd_, target, vk::ImageLayout::eUndefined, vk::ImageLayout::eTransferDstOptimal, Stage::eTransfer, {},
                 Stage::eTransfer, Access::eTransferWrite);
    vk::ImageBlit blit{
        .srcSubresource = {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
        .srcOffsets = std::array<vk::Offset3D, 2>{vk::Offset3D{0, 0, 0}, vk::Offset3D{width_, height_, 1}},
        .dstSubresource = {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
        .dstOffsets = std::array<vk::Offset3D, 2>{vk::Offset3D{0, 0, 0},
                                                  vk::Offset3D{int32_t(extent_.width), int32_t(extent_.height), 1}}};
    cmd_.blitImage(*displayImage_, vk::ImageLayout::eTransferSrcOptimal, target, vk::ImageLayout::eTransferDstOptimal,
                   blit, vk::Filter::eNearest);
    imageBarrier(cmd_, target, vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::eColorAttachmentOptimal,
                 Stage::eTransfer, Access::eTransferWrite, Stage::eColorAttachmentOutput,
                 Access::eColorAttachmentRead | Access::eColorAttachmentWrite);
}

void Presenter::recordOverlay(ImDrawData* drawData, bool captureWindow) {
    using Stage = vk::PipelineStageFlagBits;
    using Access = vk::AccessFlagBits;
    cmd_.beginRenderPass(
        vk::RenderPassBeginInfo{
            .renderPass = *renderPass_, .framebuffer = *framebuffers_[imageIndex_], .renderArea = {{0, 0}, extent_}},
        vk::SubpassContents::eInline);
    if (drawData) ImGui_ImplVulkan_RenderDrawData(drawData, *cmd_);
    cmd_.endRenderPass();
    if (captureWindow) {
        vk::Image image = swapImages_[imageIndex_];
        imageBarrier(cmd_, image, vk::ImageLayout::ePresentSrcKHR, vk::ImageLayout::eTransferSrcOptimal,
                     Stage::eColorAttachmentOutput, Access::eColorAttachmentWrite, Stage::eTransfer,
                     Access::eTransferRead);
        vk::BufferImageCopy copy{.bufferOffset = 0,
                                 .imageSubresource = {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
                                 .imageExtent = {extent_.width, extent_.height, 1}};
        cmd_.copyImageToBuffer(image, vk::ImageLayout::eTransferSrcOptimal, *windowBuffer_.buffer, copy);
        imageBarrier(cmd_, image, vk::ImageLayout::eTransferSrcOptimal, vk::ImageLayout::ePresentSrcKHR,
                     Stage::eTransfer, Access::eTransferRead, Stage::eBottomOfPipe, {});
        vk::MemoryBarrier toHost{.srcAccessMask = Access::eTransferWrite, .dstAccessMask = Access::eHostRead};
        cmd_.pipelineBarrier(Stage::eTransfer, Stage::eHost, {}, toHost, nullptr, nullptr);
        windowCaptured_ = true;
    }
}

double Presenter::endFrame() {
    cmd_.end();
    frameOpen_ = false;
    vk::PipelineStageFlags waitStage = vk::PipelineStageFlagBits::eTransfer;
    vk::CommandBuffer raw = *cmd_;
    vk::Semaphore acquired = *imageAcquired_;
    vk::Semaphore done = *renderDone_[imageIndex_];
    auto start = std::chrono::steady_clock::now();
    ctx_.submit(vk::SubmitInfo{.waitSemaphoreCount = 1,
                               .pWaitSemaphores = &acquired,
                               .pWaitDstStageMask = &waitStage,
                               .commandBufferCount = 1,
                               .pCommandBuffers = &raw,
                               .signalSemaphoreCount = 1,
                               .pSignalSemaphores = &done},
                *frameDone_);
    vk::SwapchainKHR swapchain = *swapchain_;
    vk::Result presented;
    try {
        presented = ctx_.queue.presentKHR(vk::PresentInfoKHR{.waitSemaphoreCount = 1,
                                                             .pWaitSemaphores = &done,
                                                             .swapchainCount = 1,
                                                             .pSwapchains = &swapchain,
                                                             .pImageIndices = &imageIndex_});
    } catch (const vk::OutOfDateKHRError&) {
        presented = vk::Result::eErrorOutOfDateKHR;
    }
    ctx_.waitForFence(*frameDone_);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ctx_.device.resetFences(*frameDone_);
    if (windowCaptured_) {
        windowCapture_.width = int(extent_.width);
        windowCapture_.height = int(extent_.height);
        windowCapture_.pixels.resize(size_t(extent_.width) * extent_.height * 4);
        std::memcpy(windowCapture_.pixels.data(), windowBuffer_.mapped, windowCapture_.pixels.size());
        bool bgra =
            surfaceFormat_.format == vk::Format::eB8G8R8A8Unorm || surfaceFormat_.format == vk::Format::eB8G8R8A8Srgb;
        if (bgra)
            for (size_t i = 0; i < windowCapture_.pixels.size(); i += 4)
                std::swap(windowCapture_.pixels[i], windowCapture_.pixels[i + 2]);
    }
    if (presented == vk::Result::eErrorOutOfDateKHR || presented == vk::Result::eSuboptimalKHR) {
        ctx_.device.waitIdle();
        createSwapchain();
    }
    return seconds;
}

Rgba8Image Presenter::displayPixels() const {
    Rgba8Image image{width_, height_, std::vector<uint8_t>(size_t(width_) * height_ * 4)};
    std::memcpy(image.pixels.data(), displayBuffer_.mapped, image.pixels.size());
    return image;
}

Rgba8Image Presenter::windowPixels() const {
    return windowCapture_;
}

}  // namespace whitted

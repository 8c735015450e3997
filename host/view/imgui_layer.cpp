#include "view/imgui_layer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui/backends/imgui_impl_glfw.h>
#include <imgui/backends/imgui_impl_vulkan.h>
#include <imgui/imgui.h>

#include <stdexcept>
#include <string>

namespace whitted {
namespace {

void checkVk(VkResult r) {
    if (r < 0) throw std::runtime_error("ImGui Vulkan back end: " + vk::to_string(vk::Result(r)));
}

}  // namespace

ImGuiLayer::ImGuiLayer(VulkanContext& ctx, GLFWwindow* window, Presenter& presenter) {
    // The back end allocates one descriptor set, for the font texture.
    vk::DescriptorPoolSize size{vk::DescriptorType::eCombinedImageSampler, 4};
    pool_ = vk::raii::DescriptorPool(
        ctx.device, vk::DescriptorPoolCreateInfo{.flags = vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                 .maxSets = 4,
                                                 .poolSizeCount = 1,
                                                 .pPoolSizes = &size});
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForVulkan(window, false);  // our Window forwards the events
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = *ctx.instance;
    info.PhysicalDevice = *ctx.physicalDevice;
    info.Device = *ctx.device;
    info.QueueFamily = ctx.queueFamily;
    info.Queue = *ctx.queue;
    info.DescriptorPool = *pool_;
    info.MinImageCount = presenter.minImageCount();
    info.ImageCount = std::max(presenter.imageCount(), presenter.minImageCount());
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.PipelineCache = *ctx.pipelineCache->cache();  // its graphics pipeline, kept like ours
    info.CheckVkResultFn = checkVk;
    if (!ImGui_ImplVulkan_Init(&info, presenter.renderPass())) throw std::runtime_error("ImGui_ImplVulkan_Init failed");
    ctx.pipelineCache->save();
    presenter.immediate([](vk::raii::CommandBuffer& cmd) { ImGui_ImplVulkan_CreateFontsTexture(*cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

ImGuiLayer::~ImGuiLayer() {
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void ImGuiLayer::newFrame() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

ImDrawData* ImGuiLayer::render() {
    ImGui::Render();
    return ImGui::GetDrawData();
}

}  // namespace whitted

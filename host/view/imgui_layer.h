// Dear ImGui (Debian's 1.86) on the window: its context, the GLFW and
// Vulkan back ends (compiled from the package's example sources) and the
// font upload. One per window; destroyed before the presenter.
#pragma once

#include "view/presenter.h"
#include "vk/context.h"

struct GLFWwindow;
struct ImDrawData;

namespace whitted {

class ImGuiLayer {
public:
    ImGuiLayer(VulkanContext& ctx, GLFWwindow* window, Presenter& presenter);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    void newFrame();
    ImDrawData* render();  // ends the frame; the draw lists for Presenter::recordOverlay

private:
    vk::raii::DescriptorPool pool_{nullptr};
};

}  // namespace whitted

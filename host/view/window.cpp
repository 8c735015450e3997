#include "view/window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui/backends/imgui_impl_glfw.h>
#include <imgui/imgui.h>

#include <stdexcept>

namespace whitted {
namespace {

std::string glfwError() {
    const char* description = nullptr;
    int code = glfwGetError(&description);
    return code == GLFW_NO_ERROR ? "no error reported" : std::string(description ? description : "unknown error");
}

Window* owner(GLFWwindow* w) {
    return static_cast<Window*>(glfwGetWindowUserPointer(w));
}

}  // namespace

Window::Window(int width, int height, const std::string& title) {
    if (!glfwInit()) throw std::runtime_error("cannot open a window: glfwInit: " + glfwError() + " (is DISPLAY set?)");
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        throw std::runtime_error("cannot open a window: GLFW finds no Vulkan loader");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        std::string error = glfwError();
        glfwTerminate();
        throw std::runtime_error("cannot open a window: " + error);
    }
    // Without a window manager (Xvfb) nobody gives the window the focus,
    // and ImGui's GLFW back end reads the mouse only in a focused window.
    glfwFocusWindow(window_);
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, keyCallback);
    glfwSetCharCallback(window_, charCallback);
    glfwSetMouseButtonCallback(window_, mouseButtonCallback);
    glfwSetCursorPosCallback(window_, cursorCallback);
    glfwSetScrollCallback(window_, scrollCallback);
}

Window::~Window() {
    glfwDestroyWindow(window_);
    glfwTerminate();
}

bool Window::shouldClose() const {
    return glfwWindowShouldClose(window_);
}

std::vector<std::string> Window::requiredInstanceExtensions() {
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw std::runtime_error("cannot open a window: " + glfwError());
    return std::vector<std::string>(names, names + count);
}

// ImGui sees every event first (its GLFW back end is initialised without
// callbacks of its own); what it wants to capture goes no further.
void Window::keyCallback(GLFWwindow* w, int key, int scancode, int action, int mods) {
    if (ImGui::GetCurrentContext()) {
        ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
        if (ImGui::GetIO().WantCaptureKeyboard && action != GLFW_RELEASE) return;
    }
    if (Window* self = owner(w); self && self->sink_) self->sink_->onKey(key, action, mods);
}

void Window::charCallback(GLFWwindow* w, unsigned int c) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_CharCallback(w, c);
}

void Window::mouseButtonCallback(GLFWwindow* w, int button, int action, int mods) {
    if (ImGui::GetCurrentContext()) {
        ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods);
        if (ImGui::GetIO().WantCaptureMouse && action == GLFW_PRESS) return;
    }
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    if (Window* self = owner(w); self && self->sink_) self->sink_->onMouseButton(button, action, x, y);
}

void Window::cursorCallback(GLFWwindow* w, double x, double y) {
    if (Window* self = owner(w); self && self->sink_) self->sink_->onCursor(x, y);
}

void Window::scrollCallback(GLFWwindow* w, double dx, double dy) {
    if (ImGui::GetCurrentContext()) {
        ImGui_ImplGlfw_ScrollCallback(w, dx, dy);
        if (ImGui::GetIO().WantCaptureMouse) return;
    }
    if (Window* self = owner(w); self && self->sink_) self->sink_->onScroll(dy);
}

}  // namespace whitted

// The GLFW window (no OpenGL context: Vulkan presents into it) and its input
// callbacks, handed on to an InputSink. GLFW is initialised per Window and
// terminated with it; the window's user pointer finds the Window again in the
// callbacks, so there is no global state of our own.
#pragma once

#include <string>
#include <vector>

struct GLFWwindow;

namespace whitted {

class InputSink {
public:
    virtual ~InputSink() = default;
    virtual void onKey(int key, int action, int mods) = 0;
    virtual void onMouseButton(int button, int action, double x, double y) = 0;
    virtual void onCursor(double x, double y) = 0;
    virtual void onScroll(double steps) = 0;
};

class Window {
public:
    Window(int width, int height, const std::string& title);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    GLFWwindow* handle() const { return window_; }
    void setInputSink(InputSink* sink) { sink_ = sink; }
    bool shouldClose() const;

    // The instance extensions Vulkan needs to present here.
    static std::vector<std::string> requiredInstanceExtensions();

private:
    static void keyCallback(GLFWwindow* w, int key, int scancode, int action, int mods);
    static void charCallback(GLFWwindow* w, unsigned int c);
    static void mouseButtonCallback(GLFWwindow* w, int button, int action, int mods);
    static void cursorCallback(GLFWwindow* w, double x, double y);
    static void scrollCallback(GLFWwindow* w, double dx, double dy);

    GLFWwindow* window_ = nullptr;
    InputSink* sink_ = nullptr;
};

}  // namespace whitted

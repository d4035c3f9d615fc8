// The GLFW window with an OpenGL 3.3 core context and, when asked, Dear ImGui on top.
// Batch runs that only read back offscreen targets use a hidden window.
#pragma once

#include <string>
#include <vector>

struct GLFWwindow;

namespace firelook::viewer {

class Window {
  public:
    // Throws ViewerError if GLFW cannot start (no X server: run under xvfb-run) or the context is
    // not OpenGL 3.3 core.
    Window(int width, int height, bool visible, bool with_imgui, bool vsync);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    bool shouldClose() const;
    void pollEvents();
    void beginUi();  // ImGui new frame
    // Renders the UI (if any) over a cleared framebuffer; `capture` (if not null) gets the result
    // (RGBA8, bottom row first) before the swap.
    void present(std::vector<unsigned char>* capture, int* capture_width, int* capture_height);
    void framebufferSize(int& width, int& height) const;
    std::string renderer() const;

  private:
    GLFWwindow* window_ = nullptr;
    bool imgui_ = false;
};

}  // namespace firelook::viewer

#include "viewer/gl_window.h"

#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>
// epoxy must come first: GLFW would otherwise pull in the system GL header.
#include <GLFW/glfw3.h>

// From GLFW's glfw3native.h, which with GLFW_EXPOSE_NATIVE_X11 also wants the Xrandr headers; an
// X11 Window is an XID, an unsigned long.
extern "C" unsigned long glfwGetX11Window(GLFWwindow* window);

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

namespace bt::gl {

namespace {
std::string lastGlfwError() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}
// The display gets three tries, 100 ms apart: in session 14's CI run the window tests' Xvfb
// refused one connection ("Failed to open display") between two windows, and took the next
// test's. A display that is not there costs 0.2 s more before the error.
bool initGlfw() {
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (glfwInit()) return true;
  }
  return false;
}
} // namespace

GlWindow::GlWindow(int width, int height, const std::string& title) {
  if (!initGlfw()) throw GlError("cannot open a window: " + lastGlfwError());
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#ifndef NDEBUG
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    std::string why = lastGlfwError();
    glfwTerminate();
    throw GlError("cannot open a GL 4.5 core window: " + why);
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(0); // progressive refinement wants every frame it can get
  context_ = GlContext::adoptCurrent("glfw");
}

unsigned long GlWindow::x11Window() const {
  return glfwGetX11Window(window_);
}

std::vector<uint8_t> GlWindow::readBackBuffer(int& width, int& height) const {
  glfwGetFramebufferSize(window_, &width, &height);
  std::vector<uint8_t> rgba(size_t(width) * height * 4);
  BT_GL(glReadBuffer(GL_BACK));
  BT_GL(glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data()));
  for (int y = 0; y < height / 2; ++y) // GL's rows go up
    std::swap_ranges(rgba.begin() + size_t(y) * width * 4, rgba.begin() + size_t(y + 1) * width * 4,
                     rgba.begin() + size_t(height - 1 - y) * width * 4);
  return rgba;
}

GlWindow::~GlWindow() {
  context_.reset(); // GL objects go before the context that owns them
  glfwDestroyWindow(window_);
  glfwTerminate();
}

} // namespace bt::gl

#include "viewer/gl_window.h"

#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>
// epoxy must come first: GLFW would otherwise pull in the system GL header.
#include <GLFW/glfw3.h>

// From GLFW's glfw3native.h, which with GLFW_EXPOSE_NATIVE_X11 also wants the Xrandr headers; an
// X11 Window is an XID, an unsigned long.
extern "C" unsigned long glfwGetX11Window(GLFWwindow* window);

#include <string>

namespace bt::gl {

namespace {
std::string lastGlfwError() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}
} // namespace

GlWindow::GlWindow(int width, int height, const std::string& title) {
  if (!glfwInit()) throw GlError("cannot open a window: " + lastGlfwError());
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

GlWindow::~GlWindow() {
  context_.reset(); // GL objects go before the context that owns them
  glfwDestroyWindow(window_);
  glfwTerminate();
}

} // namespace bt::gl

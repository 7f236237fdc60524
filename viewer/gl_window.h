// A GLFW window with a GL 4.5 core context, for the live viewer. GLFW cannot run headless
// (it needs an X11 or Wayland display), so renders without a display use
// GlContext::createHeadless instead.
#pragma once

#include "renderer/gl/gl_context.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

struct GLFWwindow;

namespace bt::gl {

class GlWindow {
public:
  // Opens the window and makes its context current. Throws GlError saying why (no display,
  // no GL 4.5 core).
  GlWindow(int width, int height, const std::string& title);
  ~GlWindow();
  GlWindow(const GlWindow&) = delete;
  GlWindow& operator=(const GlWindow&) = delete;

  GLFWwindow* handle() const { return window_; }
  unsigned long x11Window() const; // the X11 window's id (tests send it key events)
  GlContext& context() { return *context_; }
  // The back buffer as RGBA8, rows top to bottom (what the next swap shows): for tests.
  std::vector<uint8_t> readBackBuffer(int& width, int& height) const;

private:
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<GlContext> context_;
};

} // namespace bt::gl

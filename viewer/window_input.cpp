#include "viewer/window_input.h"

#include <GLFW/glfw3.h>

#include <utility>

namespace bt {

namespace {
WindowInput& inputOf(GLFWwindow* window) {
  return *static_cast<WindowInput*>(glfwGetWindowUserPointer(window));
}
} // namespace

void WindowInput::install(GLFWwindow* window) {
  window_ = window;
  glfwSetWindowUserPointer(window, this);
  // GLFW calls these from glfwPollEvents on this thread, so the queue needs no lock.
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action == GLFW_PRESS) inputOf(w).push(Press{Press::Device::Key, key, mods});
  });
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
    if (action != GLFW_PRESS) return;
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(w, &x, &y);
    inputOf(w).push(Press{Press::Device::MouseButton, button, mods, x, y});
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) { inputOf(w).wheel_ += dy; });
}

void WindowInput::uninstall() {
  if (!window_) return;
  glfwSetKeyCallback(window_, nullptr);
  glfwSetMouseButtonCallback(window_, nullptr);
  glfwSetScrollCallback(window_, nullptr);
  glfwSetWindowUserPointer(window_, nullptr);
  window_ = nullptr;
}

std::vector<Press> WindowInput::takePresses() {
  return std::exchange(presses_, {});
}

double WindowInput::takeWheel() {
  return std::exchange(wheel_, 0.0);
}

FlyInput WindowInput::flyInput(bool keyboard, bool mouse) {
  GLFWwindow* w = window_;
  auto held = [w](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
  FlyInput in;
  if (keyboard) {
    in.forward = held(GLFW_KEY_W);
    in.back = held(GLFW_KEY_S);
    in.left = held(GLFW_KEY_A);
    in.right = held(GLFW_KEY_D);
    in.down = held(GLFW_KEY_Q) || held(GLFW_KEY_C);
    in.up = held(GLFW_KEY_E) || held(GLFW_KEY_SPACE);
    in.fast = held(GLFW_KEY_LEFT_SHIFT) || held(GLFW_KEY_RIGHT_SHIFT);
    // Ctrl+C copies the camera: its C is no step down.
    if (held(GLFW_KEY_LEFT_CONTROL) || held(GLFW_KEY_RIGHT_CONTROL)) in.down = held(GLFW_KEY_Q);
  }
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(w, &x, &y);
  in.looking = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  if (in.looking) {
    in.mouseDx = x - lastX_;
    in.mouseDy = y - lastY_;
  }
  lastX_ = x;
  lastY_ = y;
  const double wheel = takeWheel();
  if (mouse) in.wheel = wheel;
  return in;
}

} // namespace bt

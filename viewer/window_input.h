// Every key and mouse-button press the window receives, queued by GLFW's callbacks as it
// delivers them, so that a frame acts on each one. Polling the key state once per frame loses a
// tap shorter than a frame (on llvmpipe a frame took seconds: F12 or 1-7 had to be held).
// Held keys (WASD, the look button) are still read as state: they act for as long as they are down.
#pragma once

#include "viewer/fly_camera.h"

#include <vector>

struct GLFWwindow;

namespace bt {

struct Press {
  enum class Device { Key, MouseButton };
  Device device = Device::Key;
  int code = 0;            // GLFW_KEY_* or GLFW_MOUSE_BUTTON_*
  int mods = 0;            // GLFW_MOD_* held at the press
  double x = 0.0, y = 0.0; // the cursor, in window coordinates, at the press
};

// The window's input between two frames. Owned by the viewer; GLFW's callbacks reach it through
// the window's user pointer, so it must outlive the callbacks' installation (uninstall() first).
class WindowInput {
public:
  // Installs the key, mouse-button and scroll callbacks. Call before ImGui's GLFW backend is
  // initialised with install_callbacks = true, which then chains to these.
  void install(GLFWwindow* window);
  void uninstall();

  // The presses since the last call, in order, and the scroll notches.
  std::vector<Press> takePresses();
  double takeWheel();
  // The held keys and the look drag as the fly camera reads them (the wheel taken); keys and
  // mouse count only where the overlay does not want them.
  FlyInput flyInput(bool keyboard, bool mouse);

  void push(const Press& press) { presses_.push_back(press); }

private:
  GLFWwindow* window_ = nullptr;
  std::vector<Press> presses_;
  double wheel_ = 0.0;
  double lastX_ = 0.0, lastY_ = 0.0;
};

} // namespace bt

// Keys as a user presses them: X events sent to the viewer's window (XSendEvent), so they go
// through GLFW's event processing and the viewer's callbacks; nothing is injected behind GLFW.
#pragma once

#include "viewer/viewer.h"

#include <X11/Xlib.h>
#include <X11/keysym.h>
#include <gtest/gtest.h>

namespace bt::viewer_test {

// A press and its release, both delivered before the viewer's next frame: a tap shorter than a
// frame, which polling the key state once per frame never sees.
inline void tap(const Viewer& viewer, KeySym key, unsigned int state = 0) {
  Display* display = XOpenDisplay(nullptr);
  ASSERT_NE(display, nullptr);
  XKeyEvent event{};
  event.display = display;
  event.window = viewer.x11Window();
  event.root = DefaultRootWindow(display);
  event.time = CurrentTime;
  event.same_screen = True;
  event.keycode = XKeysymToKeycode(display, key);
  event.state = state;
  event.type = KeyPress;
  XSendEvent(display, event.window, True, KeyPressMask, reinterpret_cast<XEvent*>(&event));
  event.type = KeyRelease;
  XSendEvent(display, event.window, True, KeyReleaseMask, reinterpret_cast<XEvent*>(&event));
  XSync(display, False); // both are in the viewer's queue when this returns
  XCloseDisplay(display);
}

} // namespace bt::viewer_test

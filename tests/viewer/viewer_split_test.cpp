// The GL window on a GL too slow for a whole pass a frame (Mesa's llvmpipe, as under Xvfb): it
// draws a piece of the pass a frame (renderer/gl/gl_progressive.h PieceSizer) and serves the
// keys between pieces, as the CPU tracer's window does (viewer_cpu_test.cpp).
#include "tests/viewer/viewer_test_fixture.h"
#include "tests/viewer/x_keys.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <string>

namespace bt {
namespace {

using namespace viewer_test;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The room at 1280x720 in physical light with 8 bounces: a pass of the GL tracer takes several
// seconds on llvmpipe on a 2-core machine even when nothing else runs (at 640x360 it took 3-6 s
// under load but under 1.5 s alone, and the pass ended before the tap was checked). One second
// into the pass, with its rows drawn so far on screen, F1 is tapped: the overlay is gone from
// the window within half a second, the pass still under way.
TEST_F(ViewerWindowTest, AGlWindowWhosePassTakesSecondsServesATapWithinHalfASecond) {
  ViewerOptions o = options();
  o.width = 1280; // ctest's Xvfb screen is 1280x1024 (tests/viewer/CMakeLists.txt)
  o.height = 720;
  o.lighting = LightingMode::Physical;
  o.bounces = 8;
  o.denoise = false; // the image on screen is the GPU's, not a read-back denoised on the CPU
  Viewer viewer(o);
  const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (renderer.find("llvmpipe") == std::string::npos) GTEST_SKIP() << "the GL is " << renderer << ": a pass here is not slow";

  ASSERT_TRUE(viewer.frame()); // the first dispatch compiles the path tracer (llvmpipe compiles there)
  const auto passStart = Clock::now();
  int frames = 0;
  for (; secondsSince(passStart) < 1.0; ++frames) ASSERT_TRUE(viewer.frame());
  EXPECT_EQ(viewer.samples(), 0) << "a pass was done within a second: drawn whole, or the view is too light to show anything";
  EXPECT_GE(frames, 5) << "the window drew under five frames in a second";

  const Viewer::DisplayImage shown = viewer.displayed();
  ASSERT_EQ(shown.width, o.width);
  double topRow = 0.0;
  for (int x = 0; x < shown.width; ++x) topRow += shown.rgba[4 * size_t(x)] + shown.rgba[4 * size_t(x) + 1];
  EXPECT_GT(topRow, 0.0) << "the rows the pass has drawn are not on screen";

  const std::vector<uint8_t> withOverlay = viewer.window().rgba;
  tap(viewer, XK_F1);
  const auto tapped = Clock::now();
  ASSERT_TRUE(frameUntil(
      viewer, [&] { return !viewer.overlayShown(); }, 20.0))
      << "the F1 tap was lost";
  const double served = secondsSince(tapped);
  EXPECT_LT(served, 0.5) << "the overlay went after " << served << " s";
  EXPECT_EQ(viewer.samples(), 0) << "the tap was served only after the pass";
  EXPECT_NE(viewer.window().rgba, withOverlay) << "the window did not change";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

} // namespace
} // namespace bt

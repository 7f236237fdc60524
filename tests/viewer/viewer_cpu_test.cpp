// The CPU tracer's window (where the window's GL is software, or --backend cpu): what it draws is
// what `render --backend cpu` writes for the same camera and sample count, every pixel.
#include "tests/app/run_command.h"
#include "tests/test_data.h"
#include "tests/viewer/viewer_test_fixture.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

namespace bt {
namespace {

using namespace viewer_test;

// `render --backend cpu` of the viewer's level from its camera at `spp`, into `png`.
void renderOnCpu(const Viewer& viewer, const ViewerOptions& o, int spp, const fs::path& png) {
  const test::CommandResult r = test::brushtrace(fmt::format("render '{}' --backend cpu --camera '{}' --size {}x{} --spp {} -o '{}'", o.map,
                                                             formatCameraPose(viewer.camera()), o.width, o.height, spp, png.string()));
  ASSERT_EQ(r.exitCode, 0) << r.err;
}

TEST_F(ViewerWindowTest, TheCpuWindowDrawsWhatRenderBackendCpuWrites) {
  ViewerOptions o = options();
  o.backend = ViewerBackend::Cpu;
  o.maxSamples = 5; // refinement stops there: every row then has exactly 5 samples
  Viewer viewer(o);
  EXPECT_TRUE(viewer.cpuTracer());
  EXPECT_NE(viewer.cpuReason().find("--backend cpu"), std::string::npos) << viewer.cpuReason();
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.luxelsBaked() && viewer.samples() == o.maxSamples; })) << "no refinement";
  ASSERT_TRUE(viewer.frame());
  const Viewer::DisplayImage shown = viewer.displayed();

  const fs::path png = dir_ / "render-cpu.png";
  renderOnCpu(viewer, o, o.maxSamples, png);
  EXPECT_GT(meanPixel(png), 5.0) << "the room rendered black";
  EXPECT_EQ(largestDifference(png, shown), 0) << "the CPU window does not draw render --backend cpu's image";
  EXPECT_EQ(largestDifference(viewer.screenshot(), shown), 0) << "the screen and the screenshot differ";

  // The comparison can tell: one sample fewer is another image.
  renderOnCpu(viewer, o, o.maxSamples - 1, png);
  EXPECT_GT(largestDifference(png, shown), 0) << "4 and 5 samples look the same: the test cannot tell";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

// A save reloads the CPU window's level as it does the GL window's (the import on a worker thread,
// the luxels baked again, refinement restarted), keeping the camera: the window then draws what
// render --backend cpu writes of the saved level.
TEST_F(ViewerWindowTest, TheCpuWindowReloadsOnSave) {
  ViewerOptions o = options();
  o.backend = ViewerBackend::Cpu;
  o.maxSamples = 3;
  Viewer viewer(o);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.luxelsBaked() && viewer.samples() == o.maxSamples; }));
  save(roomMap(900, 64));
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.reloads() == 1; })) << "the save was not noticed";
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.luxelsBaked() && viewer.samples() == o.maxSamples; }));
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(viewer.error().empty()) << viewer.error();
  EXPECT_EQ(viewer.camera().origin, glm::vec3(-96, 0, -42)) << "the reload moved the camera";
  const fs::path png = dir_ / "render-cpu.png";
  renderOnCpu(viewer, o, o.maxSamples, png);
  EXPECT_EQ(largestDifference(png, viewer.displayed()), 0) << "the CPU window does not show the saved level as render does";
}

// Under Xvfb the window's GL is llvmpipe: without --backend the CPU tracer draws, and says why.
TEST_F(ViewerWindowTest, ASoftwareGlWindowDrawsWithTheCpuTracerAndSaysWhy) {
  ViewerOptions o = options();
  o.backend = ViewerBackend::Auto;
  Viewer viewer(o);
  if (!viewer.cpuTracer()) GTEST_SKIP() << "the window's GL is hardware here: the automatic choice is the GL tracer";
  EXPECT_NE(viewer.cpuReason().find("software"), std::string::npos) << viewer.cpuReason();
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));
  EXPECT_GT(meanPixel(viewer.screenshot()), 5.0);
}

} // namespace
} // namespace bt

namespace bt {
namespace {

// Not a test: each tracer's frame times on a LibreQuake level on this machine's GL (llvmpipe under
// Xvfb), for the notes. Run by hand: viewer_window_tests --gtest_also_run_disabled_tests
// --gtest_filter='*FrameTimes*' under xvfb-run.
TEST_F(ViewerWindowTest, DISABLED_FrameTimesOnALibreQuakeLevel) {
  BT_REQUIRE_SHARED(shared);
  for (const ViewerBackend backend : {ViewerBackend::Gl, ViewerBackend::Cpu}) {
    ViewerOptions o = options();
    o.map = (shared / "maps/librequake/lq1/maps/src/dm/lqdm8.map").string();
    o.width = 640;
    o.height = 360;
    o.luxels = false;
    o.backend = backend;
    const auto opened = std::chrono::steady_clock::now();
    Viewer viewer(o);
    const double openSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - opened).count();
    std::vector<double> frames;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < end && frames.size() < 60) {
      const auto t0 = std::chrono::steady_clock::now();
      ASSERT_TRUE(viewer.frame());
      frames.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::vector<double> later(frames.begin() + 1, frames.end()); // the first compiles the GL programs
    std::sort(later.begin(), later.end());
    std::printf("%s: open %.2f s, first frame %.0f ms, then %zu frames: median %.0f ms, max %.0f ms, %d spp\n",
                backend == ViewerBackend::Gl ? "GL tracer (llvmpipe)" : "CPU tracer", openSeconds, frames.front(), later.size(),
                later[later.size() / 2], later.back(), viewer.samples());
  }
}

// Not a test: how long a light-style slider takes to show on a LibreQuake level (lqdm8: 96 lights,
// one of style 11) in each window at 640x360, beside what a reload costs (the import and the
// bake: the open and the bake). Run by hand as the frame times above.
TEST_F(ViewerWindowTest, DISABLED_StyleSliderTimesOnALibreQuakeLevel) {
  BT_REQUIRE_SHARED(shared);
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  for (const ViewerBackend backend : {ViewerBackend::Cpu, ViewerBackend::Gl}) {
    ViewerOptions o = options();
    o.map = (shared / "maps/librequake/lq1/maps/src/dm/lqdm8.map").string();
    o.width = 640;
    o.height = 360;
    o.backend = backend;
    const auto opened = Clock::now();
    Viewer viewer(o);
    const double openSeconds = since(opened);
    const auto baking = Clock::now();
    ASSERT_TRUE(frameUntil(
        viewer, [&] { return viewer.luxelsBaked() && viewer.samples() >= 1; }, 300.0));
    const double bakeSeconds = since(baking);
    ASSERT_EQ(viewer.lightStyles(), std::vector<int>{11});
    const auto moved = Clock::now();
    viewer.setStyleScale(11, 0.25f);
    const double sumSeconds = since(moved);
    ASSERT_TRUE(viewer.frame());
    const double frameSeconds = since(moved);
    ASSERT_TRUE(frameUntil(
        viewer, [&] { return viewer.samples() >= 1; }, 300.0));
    std::printf("%s window: open %.2f s, bake and first pass %.2f s; slider: re-sum %.1f ms, first frame %.0f ms, whole pass %.2f s; "
                "imports %d, bakes %d\n",
                viewer.cpuTracer() ? "CPU" : "GL", openSeconds, bakeSeconds, 1e3 * sumSeconds, 1e3 * frameSeconds, since(moved),
                viewer.imports(), viewer.bakes());
  }
}

} // namespace
} // namespace bt

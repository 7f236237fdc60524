// The viewer's state (viewer.h's Viewer::Impl), shared by the files that implement it:
// viewer.cpp (the window, the level and its reloads, the lighting modes), viewer_input.cpp (keys,
// clicks, clipboard, screenshots) and viewer_display.cpp (what each view mode puts on screen, the
// overlay). Internal to viewer/.
#pragma once

#include "viewer/viewer.h"
#include "lighting/compiled_lightmaps.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/difference.h"
#include "renderer/exposure.h"
#include "renderer/image_output.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_bake.h"
#include "renderer/gl/gl_denoise.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_level.h"
#include "renderer/gl/gl_progressive.h"
#include "renderer/gl/gl_tracer.h"
#include "viewer/gl_window.h"
#include "scene/color.h"
#include "viewer/fly_camera.h"
#include "viewer/cpu_view.h"
#include "viewer/overlay.h"
#include "viewer/pending_level.h"
#include "viewer/bookmarks.h"
#include "viewer/markers.h"
#include "viewer/picking.h"
#include "viewer/view_images.h"
#include "viewer/watcher_thread.h"
#include "viewer/window_input.h"
#include <epoxy/gl.h>
// epoxy before GLFW, so that GLFW does not include the system GL header.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <algorithm>
#include <chrono>

namespace bt {

using ViewerClock = std::chrono::steady_clock;

struct Viewer::Impl {
  ViewerOptions options;
  gl::GlWindow window;
  std::shared_ptr<gl::TracerPrograms> programs;
  WindowInput input; // every press between two frames (GLFW's callbacks)
  WatcherThread watcher;
  std::unique_ptr<gl::GlLevel> level; // null while no level has loaded (a broken map at start-up)
  std::unique_ptr<PendingLevel> pending;
  // Faithful mode's luxels, baked on the GPU a little every frame from the second on (gl_bake.h);
  // reads level->render, so it goes before the level does.
  std::unique_ptr<gl::ProgressiveLevelBake> bake;
  // Without hardware GL (or --backend cpu) the CPU tracer draws the window, a band of rows per
  // frame (cpu_view.h); the level then has no GL tracer, and its luxels bake on a worker thread.
  bool cpu = false;
  std::string cpuReason;
  std::unique_ptr<CpuProgressive> cpuFull, cpuPreview;
  std::unique_ptr<CpuLuxelBake> cpuBake;                   // reads level->render, so it goes before the level does
  std::vector<std::unique_ptr<CpuLuxelBake>> retiredBakes; // of replaced levels, each holding its level
  FlyCamera camera;
  bool cameraPlaced = false; // at the level's render camera, or --camera
  ViewMode mode = ViewMode::Beauty;
  LightingMode lighting;

  // Progressive accumulation at full size, on the GPU; restarted whenever the view changes.
  // While the camera moves, each frame is one sample of a half-size preview instead.
  std::unique_ptr<gl::ProgressiveImage> full;
  std::unique_ptr<gl::ProgressiveImage> preview;
  std::unique_ptr<gl::TonemapPass> tonemap;
  std::unique_ptr<gl::PieceSizer> pieces;    // how much of a pass the GL tracer draws a frame
  std::unique_ptr<gl::DenoisePass> denoiser; // the GL window's, made at its first use
  ExposureSmoother autoExposure;             // physical mode's exposure, followed from frame to frame
  bool moving = false;
  RenderImage aovs; // of the current view, for the albedo/normal modes and screenshots
  bool aovsCurrent = false;
  RenderImage previewAovs;        // of the half-size preview, while the camera moves
  bool denoise = options.denoise; // key N
  // The light-style sliders: each style's scale (1: as faithful mode shows it). A level loads with
  // its lights as the map gives them (baseColors); faithful mode's luxels of a styled level are
  // baked from those, one set per style, and shown summed with styleScale as weights; the lights
  // themselves (physical mode, the view at each pixel's point) carry lightScale, brought to
  // styleScale between frames whenever no CPU bake is reading them (followStyleSliders).
  std::array<float, 256> styleScale = CpuLuxelBake::kUnitStyleWeights;
  std::array<float, 256> lightScale = CpuLuxelBake::kUnitStyleWeights;
  std::vector<glm::vec3> baseColors;        // per level->render.lights
  std::vector<glm::vec3> baseSurfaceColors; // per level->render.surfaceLights (physical mode's emitters)
  StyledLuxels styled;
  int imports = 0, bakes = 0, gpuBakes = 0;
  std::unique_ptr<gl::GlTexture2D> display; // RGBA8, what is on screen (scaled to the window)

  std::string error;    // why the level on screen is not the files' (or why none is)
  std::string notice;   // why the compiled view could not be shown
  std::string note;     // why the viewer opened in a mode not asked for
  OverlayMessage flash; // for a few seconds: the last screenshot's path or why it failed, the camera copied
  ViewerClock::time_point flashUntil{};
  PickedFace picked;   // the face last clicked
  MarkerLayer markers; // light and entity markers (key L)
  Bookmarks bookmarks{options.bookmarksFile, std::filesystem::absolute(options.map).lexically_normal().string()};
  bool overlayShown = true; // F1
  bool opened = false;      // the constructor is done: a level loaded from now on is a reload
  bool compiled = false;
  // Key 7: faithful light accumulates in `full` while the compiled picture of the view, drawn
  // once when the camera stops, waits in compiledPixels (display bytes; empty: not drawn yet).
  bool difference = false;
  std::vector<uint32_t> compiledPacked;
  std::vector<uint8_t> compiledPixels;
  int reloads = 0;
  ViewerClock::time_point lastFrame = ViewerClock::now();
  double samplesPerSecond = 0.0;
  double samplesThisFrame = 0.0; // pixel samples the last frame drew

  explicit Impl(ViewerOptions o);

  ~Impl();

  void chooseTracer();

  // The level of a finished import: uploaded for the GL tracer, or as it is for the CPU's.
  // Rethrows the import's error.
  std::unique_ptr<gl::GlLevel> finishLoading(PendingLevel& loading);

  void placeCamera(const CameraPose& pose);

  // A level that loaded, at start-up or on a save: shown from where the camera is (the first
  // one from its render camera), in the view that was on screen.
  void installLevel(std::unique_ptr<gl::GlLevel> next, const std::vector<std::string>& missingFiles);

  void startBake();

  // Faithful mode shows the compiler's luxels once they are baked; until then the light at each
  // pixel's point. A frame's share of the bake keeps frames coming while it runs.
  void bakeSome();

  CameraPose pose() const;

  void restart();

  // Every press since the last frame, in order: a tap shorter than a frame counts.
  void handlePresses();

  void actOnKey(int key);

  // A left click: the face under the cursor (window coordinates, the image scaled to the window).
  void pick(double x, double y);

  void showFor(std::chrono::seconds duration, OverlayMessage message);

  // Ctrl+C: the camera as --camera and Quake's setpos take it; Ctrl+Shift+C: the picked face's file:line, for the editor.
  void copyToClipboard(bool pickedFace);

  // F12: the screenshot's path on screen for a few seconds, or why it could not be written (a
  // folder removed or made read-only since the start); the viewer goes on either way.
  void screenshotWithFeedback();

  void setMode(ViewMode m);

  void setLighting(LightingMode m);

  // The compiled view is faithful mode's tracer reading the level's own luxels instead of
  // evaluating the light (lighting/compiled_lightmaps.h).
  bool showCompiled();

  // The compiled view against faithful light, as render --lighting difference shows it.
  bool showDifference();
  // The difference view's compiled side weighed by the sliders again (compiledPacked).
  void weighCompiledAgain();

  // The compiled picture of the current view: a few samples with the compiled luxels uploaded.
  void drawCompiledPicture();

  RenderImage meanImage(const gl::ProgressiveImage& image) const;
  OutputSettings displayOutput() const;

  void showDifferenceImage();

  // Every file the level was read from (Scene::inputFiles: the map, prefabs, WADs, palettes,
  // shader scripts, images and companion maps), and every image it looked for in vain (a
  // texture that appears reloads the level).
  void watchLevelFiles(const std::vector<std::string>& missingFiles);

  // A save starts the import on a worker thread; the frames go on with the current level until
  // it is done, then it is uploaded here. A save during an import reloads again after it.
  void reloadIfSaved();

  gl::CameraBasis basis(int width, int height) const;

  void renderAovsIfNeeded();

  gl::BeautySettings beautySettings() const;

  // One sample: of a half-size preview while the camera moves, else one more full-size sample
  // into the accumulation. Either is tonemapped on the GPU into the display image.
  void renderSample();

  const gl::GlTexture2D& displayOfSize(int width, int height);

  void showSum(const gl::ProgressiveImage& image);
  // The light-only view and physical mode's young image are made on the CPU from the mean and the
  // AOVs (view_modes.h): whether the current view at `spp` is one of them, and its image.
  bool shownOnCpu(int spp) const;
  float denoiserShare(int spp) const; // 0 when the denoiser is off or the view is not physical
  const RenderImage& aovsOfSize(int width, int height);
  RenderImage shownImage(RenderImage mean, int spp);
  void showImage(const RenderImage& image);
  std::vector<int> lightStyles() const; // the styles of the level's lights, 0 left out
  void setStyleScale(int style, float scale);
  // Faithful mode's luxels again from the styled sets at the sliders' weights, into both tracers.
  void sumStyledLuxels();
  bool slidersAtOne() const; // every style of the level's lights at its compiled weight
  // The level's lights at `scale` of their colours as loaded, with their grid (physical mode's
  // light tree weighs their power), into both tracers; the image restarts.
  void scaleLights(const std::array<float, 256>& scale);
  void followStyleSliders();
  std::unique_ptr<PendingLevel> startImport();

  // Physical mode is exposed as `render` exposes it (renderer/exposure.h), from a read-back of
  // the image a few times a second, smoothed so the picture does not pump.
  float exposureOf(const gl::ProgressiveImage& image);
  float displayExposure() const { return lighting == LightingMode::Physical ? autoExposure.ev() : options.exposureEv; }

  // Display bytes made on the CPU (the albedo and normal views, the heat map, the CPU tracer's image).
  void showRgba(int width, int height, const std::vector<uint8_t>& rgba);

  // The CPU tracer's frame: rows for about kCpuFrameBudget of a half-size preview while the camera
  // moves, else of the full image; the image so far shown through render's own tonemap.
  void refineOnCpu();

  OverlayContent overlayContent() const;

  void drawWindow();

  bool frame();

  int samples() const { return cpu ? cpuFull->samples() : full->samples(); }

  std::filesystem::path takeScreenshot();
};

} // namespace bt

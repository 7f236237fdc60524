#include "viewer/viewer.h"

#include "lighting/compiled_lightmaps.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/difference.h"
#include "renderer/exposure.h"
#include "renderer/image_output.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_bake.h"
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

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// GPU time a frame gives faithful mode's bake while it runs.
constexpr double kBakeMillisecondsPerFrame = 30.0;
// How long the overlay shows a screenshot's path, and why one failed.
constexpr std::chrono::seconds kScreenshotShown(4);
constexpr std::chrono::seconds kScreenshotErrorShown(10);
// The CPU tracer's share of a frame: with the image's upload and the overlay (~20-40 ms on
// llvmpipe) the window answers input and reloads about ten times a second.
constexpr std::chrono::milliseconds kCpuFrameBudget(80);

namespace {

// The render command's choice per lighting mode: faithful lighting is Quake's, clamped at the
// display's white; physical lighting is open-ended radiance.
Tonemap tonemapFor(LightingMode lighting) {
  return lighting == LightingMode::Faithful ? Tonemap::Faithful : Tonemap::Aces;
}

} // namespace

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
  ExposureSmoother autoExposure; // physical mode's exposure, followed from frame to frame
  bool moving = false;
  RenderImage aovs; // of the current view, for the albedo/normal modes and screenshots
  bool aovsCurrent = false;
  std::unique_ptr<gl::GlTexture2D> display; // RGBA8, what is on screen (scaled to the window)

  std::string error;    // why the level on screen is not the files' (or why none is)
  std::string notice;   // why the compiled view could not be shown
  std::string note;     // why the viewer opened in a mode not asked for
  OverlayMessage flash; // for a few seconds: the last screenshot's path or why it failed, the camera copied
  Clock::time_point flashUntil{};
  PickedFace picked;   // the face last clicked
  MarkerLayer markers; // light and entity markers (key L)
  Bookmarks bookmarks{options.bookmarksFile, fs::absolute(options.map).lexically_normal().string()};
  bool overlayShown = true; // F1
  bool opened = false;      // the constructor is done: a level loaded from now on is a reload
  bool compiled = false;
  // Key 7: faithful light accumulates in `full` while the compiled picture of the view, drawn
  // once when the camera stops, waits in compiledPixels (display bytes; empty: not drawn yet).
  bool difference = false;
  std::vector<uint32_t> compiledPacked;
  std::vector<uint8_t> compiledPixels;
  int reloads = 0;
  Clock::time_point lastFrame = Clock::now();
  double samplesPerSecond = 0.0;
  double samplesThisFrame = 0.0; // pixel samples the last frame drew

  explicit Impl(ViewerOptions o)
      : options(std::move(o)), window(options.width, options.height, "brushtrace — " + options.map), lighting(options.lighting) {
    // The path tracer compiles (on the driver's threads, where it has them) while the level
    // loads, from when its lights say which program it needs (gl::loadGlLevel).
    chooseTracer();
    if (!cpu) programs = std::make_shared<gl::TracerPrograms>(window.context(), options.textures);
    full = std::make_unique<gl::ProgressiveImage>(options.width, options.height);
    cpuFull = std::make_unique<CpuProgressive>(options.width, options.height);
    cpuPreview = std::make_unique<CpuProgressive>(std::max(1, options.width / 2), std::max(1, options.height / 2));
    preview = std::make_unique<gl::ProgressiveImage>(std::max(1, options.width / 2), std::max(1, options.height / 2));
    tonemap = std::make_unique<gl::TonemapPass>();
    if (options.camera) placeCamera(*options.camera);
    // A level that does not load opens the window with the error; the next good save loads it.
    try {
      PendingLevel first(options);
      installLevel(finishLoading(first), *first.missingFiles);
    } catch (const gl::GlError&) {
      throw; // no window worth keeping
    } catch (const std::exception& e) {
      error = e.what();
      watcher.watch({levelFileOf(options.map)});
    }
    const bool quake3Default = level && !options.lightingGiven && level->scene.format == "ibsp46";
    if (quake3Default) note = "a compiled Quake 3 level keeps no lights; showing its lightmaps (--lighting compiled)";
    if (options.compiled || quake3Default) showCompiled();

    // Before ImGui's backend, which chains to these callbacks (and restores them on shutdown).
    input.install(window.handle());
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini littering the user's folder
    ImGui_ImplGlfw_InitForOpenGL(window.handle(), true);
    ImGui_ImplOpenGL3_Init("#version 450");
    opened = true;
  }

  ~Impl() {
    // GL objects before the window's context.
    display.reset();
    tonemap.reset();
    preview.reset();
    full.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    input.uninstall();
    pending.reset(); // waits for its import
    cpuBake.reset();
    retiredBakes.clear();
    bake.reset();
    level.reset(); // GL objects before the window's context
  }

  void chooseTracer() {
    const gl::GlContextInfo& info = window.context().info();
    if (options.backend == ViewerBackend::Cpu) cpuReason = "drawing with the CPU tracer (--backend cpu)";
    if (options.backend == ViewerBackend::Auto && info.softwareRenderer)
      cpuReason = fmt::format("the window's GL is software ({}): drawing with the CPU tracer, several times faster there "
                              "(--backend gl forces the GL tracer)",
                              info.renderer);
    cpu = !cpuReason.empty();
  }

  // The level of a finished import: uploaded for the GL tracer, or as it is for the CPU's.
  // Rethrows the import's error.
  std::unique_ptr<gl::GlLevel> finishLoading(PendingLevel& loading) {
    if (cpu)
      loading.preparation->wait();
    else
      gl::loadGlLevel(*loading.level, *loading.preparation, window.context(), programs, lighting == LightingMode::Physical);
    return std::move(loading.level);
  }

  void placeCamera(const CameraPose& pose) {
    camera = FlyCamera(glm::dvec3(pose.origin), pose.pitch, pose.yaw);
    cameraPlaced = true;
  }

  // A level that loaded, at start-up or on a save: shown from where the camera is (the first
  // one from its render camera), in the view that was on screen.
  void installLevel(std::unique_ptr<gl::GlLevel> next, const std::vector<std::string>& missingFiles) {
    if (cpuBake && !cpuBake->ready()) { // it reads the level replaced: both go when it ends
      cpuBake->holdUntilDone(std::shared_ptr<const gl::GlLevel>(std::move(level)));
      retiredBakes.push_back(std::move(cpuBake));
    }
    cpuBake.reset();
    bake.reset();
    level = std::move(next);
    markers.setLevel(level->render);
    startBake();
    error.clear();
    if (opened) ++reloads;
    if (!cameraPlaced) placeCamera(defaultCameraPose(level->scene));
    if (compiled || difference) {
      const bool wasDifference = difference;
      compiled = difference = false;
      if (showCompiled() && wasDifference) showDifference();
    }
    restart();
    watchLevelFiles(missingFiles);
  }

  void startBake() {
    // A CPU bake still running is this level's: its luxels are taken when it is done. (The
    // compiled view replaces only render.lightmaps, which the bake does not read.)
    if (cpu && cpuBake && !cpuBake->done()) return;
    cpuBake.reset();
    bake.reset();
    if (!options.luxels) return;
    if (cpu)
      cpuBake = std::make_unique<CpuLuxelBake>(level->render, options.bake);
    else
      bake = std::make_unique<gl::ProgressiveLevelBake>(level->render, options.bake);
  }

  // Faithful mode shows the compiler's luxels once they are baked; until then the light at each
  // pixel's point. A frame's share of the bake keeps frames coming while it runs.
  void bakeSome() {
    std::erase_if(retiredBakes, [](const std::unique_ptr<CpuLuxelBake>& b) { return b->ready(); });
    if (cpuBake && lighting == LightingMode::Faithful && !compiled && !difference && cpuBake->takeInto(level->render)) restart();
    if (!level || !bake || bake->done() || lighting != LightingMode::Faithful || compiled || difference || full->samples() == 0) return;
    if (bake->step(*level->tracer, kBakeMillisecondsPerFrame)) restart();
  }

  CameraPose pose() const {
    return CameraPose{glm::vec3(camera.position), static_cast<float>(camera.pitch), static_cast<float>(camera.yaw), 0.0f, "view"};
  }

  void restart() {
    full->restart();
    cpuFull->restart();
    aovsCurrent = false;
    compiledPixels.clear();
  }

  // Every press since the last frame, in order: a tap shorter than a frame counts.
  void handlePresses() {
    for (const Press& press : input.takePresses()) {
      if (press.device == Press::Device::MouseButton) {
        if (press.code == GLFW_MOUSE_BUTTON_LEFT && level && !ImGui::GetIO().WantCaptureMouse) pick(press.x, press.y);
        continue;
      }
      if (press.code == GLFW_KEY_F1) {
        overlayShown = !overlayShown;
        continue;
      }
      if (press.code == GLFW_KEY_C && (press.mods & GLFW_MOD_CONTROL)) {
        copyToClipboard(press.mods & GLFW_MOD_SHIFT);
        continue;
      }
      if (press.code >= GLFW_KEY_0 && press.code <= GLFW_KEY_9 && (press.mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT))) {
        std::optional<CameraPose> goTo;
        showFor(kScreenshotShown, bookmarks.press(press.code - GLFW_KEY_0, press.mods & GLFW_MOD_CONTROL, pose(), goTo));
        if (goTo) placeCamera(*goTo), restart();
        continue;
      }
      if (!ImGui::GetIO().WantCaptureKeyboard) actOnKey(press.code);
    }
  }

  void actOnKey(int key) {
    if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(window.handle(), GLFW_TRUE);
    if (key == GLFW_KEY_F12) screenshotWithFeedback();
    if (!level) return; // the keys below change the view of a level
    if (key == GLFW_KEY_1) setMode(ViewMode::Beauty);
    if (key == GLFW_KEY_2) setMode(ViewMode::Albedo);
    if (key == GLFW_KEY_3) setMode(ViewMode::Normal);
    if (key == GLFW_KEY_4) setLighting(LightingMode::Faithful);
    if (key == GLFW_KEY_5) setLighting(LightingMode::Physical);
    if (key == GLFW_KEY_6) showCompiled();
    if (key == GLFW_KEY_7) showDifference();
    if (key == GLFW_KEY_L) markers.toggle();
  }

  // A left click: the face under the cursor (window coordinates, the image scaled to the window).
  void pick(double x, double y) {
    int width = 0, height = 0;
    glfwGetWindowSize(window.handle(), &width, &height);
    const float px = float(x * options.width / std::max(width, 1)), py = float(y * options.height / std::max(height, 1));
    picked = pickFace(level->render, pose(), options.width, options.height, px, py);
  }

  void showFor(std::chrono::seconds duration, OverlayMessage message) {
    flash = std::move(message);
    flashUntil = Clock::now() + duration;
  }

  // Ctrl+C: the camera as --camera and Quake's setpos take it; Ctrl+Shift+C: the picked face's file:line, for the editor.
  void copyToClipboard(bool pickedFace) {
    const CameraPose p = pose();
    const std::string text = pickedFace ? picked.fileLine
                                        : fmt::format("--camera '{}'\nsetpos {:g} {:g} {:g} {:g} {:g} {:g}\n", formatCameraPose(p),
                                                      p.origin.x, p.origin.y, p.origin.z, p.pitch, p.yaw, p.roll);
    if (text.empty()) return;
    glfwSetClipboardString(window.handle(), text.c_str());
    showFor(kScreenshotShown, {OverlayMessage::Kind::Info, pickedFace ? "copied " + text : "copied the camera: " + formatCameraPose(p)});
  }

  // F12: the screenshot's path on screen for a few seconds, or why it could not be written (a
  // folder removed or made read-only since the start); the viewer goes on either way.
  void screenshotWithFeedback() {
    try {
      showFor(kScreenshotShown, {OverlayMessage::Kind::Info, "screenshot " + takeScreenshot().string()});
    } catch (const std::exception& e) {
      showFor(kScreenshotErrorShown, {OverlayMessage::Kind::Error, std::string("screenshot failed: ") + e.what()});
    }
  }

  void setMode(ViewMode m) {
    if (mode != m) mode = m;
  }

  void setLighting(LightingMode m) {
    if (!level) {
      lighting = m;
      return;
    }
    if (lighting == m && !compiled && !difference) return;
    const bool leftCompiledView = compiled || difference; // which replaced the baked luxels
    if (compiled) {
      level->render.lightmaps = {};
      if (!cpu) level->tracer->setLightmaps({});
      compiled = false;
    }
    difference = false;
    lighting = m;
    if (leftCompiledView) startBake();
    restart();
  }

  // The compiled view is faithful mode's tracer reading the level's own luxels instead of
  // evaluating the light (lighting/compiled_lightmaps.h).
  bool showCompiled() {
    if (!level) return false;
    const std::string why = showCompiledLightmaps(level->scene, level->render, options.import.textures.game.game);
    notice = why.empty() ? std::string() : why + "; showing faithful lighting";
    if (!why.empty()) return false;
    if (!cpu) {
      compiledPacked = packLightmaps(level->render.lightmaps);
      level->tracer->setLightmaps(compiledPacked);
    }
    compiled = true;
    difference = false;
    lighting = LightingMode::Faithful;
    restart();
    return true;
  }

  // The compiled view against faithful light, as render --lighting difference shows it.
  bool showDifference() {
    if (cpu) {
      notice = "the compiled-against-faithful view needs the GL tracer; showing faithful lighting";
      return false;
    }
    if (!compiled && !showCompiled()) return false;
    level->render.lightmaps = {};
    level->tracer->setLightmaps({});
    compiled = false;
    difference = true;
    restart();
    return true;
  }

  // The compiled picture of the current view: a few samples with the compiled luxels uploaded.
  void drawCompiledPicture() {
    gl::ProgressiveImage image(options.width, options.height);
    level->tracer->setLightmaps(compiledPacked);
    for (int i = 0; i < 4; ++i) image.addSample(*level->tracer, basis(image.width(), image.height()), beautySettings());
    level->tracer->setLightmaps({});
    compiledPixels = displayPixels(meanImage(image), displayOutput());
  }

  RenderImage meanImage(const gl::ProgressiveImage& image) const {
    RenderImage out;
    out.width = image.width();
    out.height = image.height();
    out.beauty = image.readMean();
    return out;
  }
  OutputSettings displayOutput() const {
    OutputSettings output;
    output.tonemap = tonemapFor(lighting);
    output.exposureEv = displayExposure();
    return output;
  }

  void showDifferenceImage() {
    const std::vector<uint8_t> heat = differencePixels(compiledPixels, displayPixels(meanImage(*full), displayOutput()));
    showRgba(full->width(), full->height(), rgbToRgba(heat));
  }

  // Every file the level was read from (Scene::inputFiles: the map, prefabs, WADs, palettes,
  // shader scripts, images and companion maps), and every image it looked for in vain (a
  // texture that appears reloads the level).
  void watchLevelFiles(const std::vector<std::string>& missingFiles) {
    std::vector<fs::path> files(level->scene.inputFiles.begin(), level->scene.inputFiles.end());
    files.insert(files.end(), missingFiles.begin(), missingFiles.end());
    watcher.watch(files);
  }

  // A save starts the import on a worker thread; the frames go on with the current level until
  // it is done, then it is uploaded here. A save during an import reloads again after it.
  void reloadIfSaved() {
    if (!pending) {
      if (watcher.takeChange()) pending = std::make_unique<PendingLevel>(options);
      return;
    }
    if (!pending->preparation->ready()) return;
    try {
      installLevel(finishLoading(*pending), *pending->missingFiles);
    } catch (const std::exception& e) {
      // Keep showing the last good level; the error stays on screen until a save fixes it.
      error = e.what();
    }
    pending.reset();
  }

  gl::CameraBasis basis(int width, int height) const {
    return gl::CameraBasis::fromQuakeAngles(glm::vec3(camera.position), static_cast<float>(camera.pitch), static_cast<float>(camera.yaw),
                                            0.0f, width, height);
  }

  void renderAovsIfNeeded() {
    if (aovsCurrent) return;
    aovs = cpu ? renderAovsCpu(level->render, Camera(pose(), options.width, options.height), options.width, options.height)
               : aovImage(level->tracer->renderAovs(basis(options.width, options.height), options.width, options.height));
    aovsCurrent = true;
  }

  gl::BeautySettings beautySettings() const {
    return gl::BeautySettings{
        .physical = lighting == LightingMode::Physical, .bounces = options.bounces, .clampIndirect = options.clampIndirect};
  }

  // One sample: of a half-size preview while the camera moves, else one more full-size sample
  // into the accumulation. Either is tonemapped on the GPU into the display image.
  void renderSample() {
    if (!level) {
      display.reset(); // nothing to show but the error
      return;
    }
    if (mode != ViewMode::Beauty) {
      renderAovsIfNeeded();
      showRgba(aovs.width, aovs.height, aovRgba(aovs, mode));
      return;
    }
    if (!moving) bakeSome();
    if (cpu) return refineOnCpu();
    if (difference && !moving && compiledPixels.empty()) drawCompiledPicture();
    gl::ProgressiveImage& image = moving ? *preview : *full;
    if (moving) preview->restart();
    if (image.samples() < options.maxSamples) {
      const int before = image.samples();
      image.addSample(*level->tracer, basis(image.width(), image.height()), beautySettings());
      // The first image is up: the other lighting mode compiles in the background, so that
      // switching to it (keys 4/5) does not stall.
      if (!moving && before == 0) programs->startPathTracer(lighting != LightingMode::Physical, level->tracer->faithfulFeatures());
      samplesThisFrame = double(image.width()) * image.height();
    }
    if (difference && !moving)
      showDifferenceImage();
    else
      showSum(image);
  }

  const gl::GlTexture2D& displayOfSize(int width, int height) {
    if (!display || display->width() != width || display->height() != height)
      display = std::make_unique<gl::GlTexture2D>(GL_RGBA8, width, height);
    return *display;
  }

  void showSum(const gl::ProgressiveImage& image) {
    tonemap->run(image.sum(), image.samples(), displayOfSize(image.width(), image.height()), tonemapFor(lighting), exposureOf(image));
  }

  // Physical mode is exposed as `render` exposes it (renderer/exposure.h), from a read-back of
  // the image a few times a second, smoothed so the picture does not pump.
  float exposureOf(const gl::ProgressiveImage& image) {
    const double now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    if (lighting == LightingMode::Physical && image.samples() > 0 && autoExposure.due(now))
      autoExposure.update(autoExposureEv(image.readMean(), image.width(), image.height()), now);
    return displayExposure();
  }
  float displayExposure() const { return lighting == LightingMode::Physical ? autoExposure.ev() : options.exposureEv; }

  // Display bytes made on the CPU (the albedo and normal views, the heat map, the CPU tracer's image).
  void showRgba(int width, int height, const std::vector<uint8_t>& rgba) {
    const gl::GlTexture2D& target = displayOfSize(width, height);
    BT_GL(glPixelStorei(GL_UNPACK_ALIGNMENT, 1));
    BT_GL(glTextureSubImage2D(target.id(), 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data()));
  }

  // The CPU tracer's frame: rows for about kCpuFrameBudget of a half-size preview while the camera
  // moves, else of the full image; the image so far shown through render's own tonemap.
  void refineOnCpu() {
    CpuProgressive& image = moving ? *cpuPreview : *cpuFull;
    if (moving) cpuPreview->restart();
    const Camera view(pose(), image.width(), image.height());
    IntegratorSettings integrator;
    integrator.mode = lighting;
    integrator.bounces = options.bounces;
    integrator.clampIndirect = options.clampIndirect;
    samplesThisFrame = double(image.refine(level->render, view, integrator, kCpuFrameBudget, moving ? 1 : options.maxSamples));
    showRgba(image.width(), image.height(), rgbToRgba(displayPixels(image.mean(), displayOutput())));
  }

  OverlayContent overlayContent() const {
    OverlayContent c;
    if (level) {
      const char* modeName = mode == ViewMode::Beauty ? "beauty" : mode == ViewMode::Albedo ? "albedo" : "normal";
      const char* lightingName = difference    ? "compiled vs faithful (black 0, blue 8, green 16, yellow 24, red 32+ levels)"
          : compiled                           ? "compiled"
          : lighting == LightingMode::Faithful ? "faithful"
                                               : "physical";
      const char* tracer = cpu ? "CPU tracer" : gl::toString(level->tracer->textureMode());
      c.status.push_back(fmt::format("{} | {} lighting | {}", modeName, lightingName, tracer));
      c.status.push_back(fmt::format("spp {} | {:.2f} Msamples/s", samples(), samplesPerSecond * 1e-6));
      if (cpuBake && lighting == LightingMode::Faithful && !cpuBake->done()) c.status.push_back("baking luxels on the CPU");
      if (bake && lighting == LightingMode::Faithful && !bake->done())
        c.status.push_back(fmt::format("baking luxels: pass {} of {}", bake->passesDone(), std::max(bake->passes(), 1)));
      c.status.push_back("camera " + formatCameraPose(pose()));
      c.picked = picked.lines;
      for (const Diagnostic& d : level->scene.diagnostics)
        if (d.severity != Severity::Note) c.warnings.push_back(format(d));
    }
    if (pending) c.status.push_back("reloading " + options.map + " ...");
    if (!level) c.picked.clear();
    if (cpu) c.status.insert(c.status.begin(), cpuReason);
    c.hints.push_back(fmt::format("RMB look, WASD move, Q/E down/up, wheel fwd, RMB+wheel speed ({:.0f})", camera.speed));
    c.hints.push_back("1 beauty 2 albedo 3 normal | 4 faithful 5 physical 6 compiled 7 difference | F12 screenshot | click: face | Ctrl+C "
                      "copy camera, Ctrl+Shift+C its file:line | L markers | Ctrl/Alt+0-9 bookmarks | F1 overlay");
    if (!notice.empty()) c.messages.push_back({OverlayMessage::Kind::Warning, notice});
    if (!error.empty())
      c.messages.push_back({OverlayMessage::Kind::Error, (level ? "reload failed: " : "cannot load the level (save a fix): ") + error});
    if (Clock::now() < flashUntil) c.messages.push_back(flash);
    return c;
  }

  void drawWindow() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window.handle(), &fbWidth, &fbHeight);
    if (display)
      ImGui::GetBackgroundDrawList()->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(display->id())), ImVec2(0, 0),
                                               ImVec2(float(fbWidth), float(fbHeight)));
    if (level) markers.draw(Camera(pose(), options.width, options.height), options.width, options.height);
    if (overlayShown) drawOverlay(overlayContent());
    ImGui::Render();
    BT_GL(glViewport(0, 0, fbWidth, fbHeight));
    BT_GL(glClearColor(0, 0, 0, 1));
    BT_GL(glClear(GL_COLOR_BUFFER_BIT));
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }

  bool frame() {
    glfwPollEvents();
    if (glfwWindowShouldClose(window.handle())) return false;
    const auto now = Clock::now();
    const double frameSeconds = std::chrono::duration<double>(now - lastFrame).count();
    const double dt = std::min(0.25, frameSeconds);
    lastFrame = now;
    // Samples are no longer waited for one by one (nothing is read back), so the rate is the
    // last frame's samples over the whole frame's time, the swap's wait for the GPU included.
    samplesPerSecond = frameSeconds > 0.0 ? samplesThisFrame / frameSeconds : 0.0;
    samplesThisFrame = 0.0;

    handlePresses();
    if (glfwWindowShouldClose(window.handle())) return false; // Escape
    moving = camera.update(input.flyInput(!ImGui::GetIO().WantCaptureKeyboard, !ImGui::GetIO().WantCaptureMouse), dt);
    if (moving) restart();
    reloadIfSaved();
    renderSample();
    drawWindow();
    glfwSwapBuffers(window.handle());
    return true;
  }

  int samples() const { return cpu ? cpuFull->samples() : full->samples(); }

  fs::path takeScreenshot() {
    if (!level) throw std::runtime_error("no level is loaded");
    renderAovsIfNeeded();
    RenderImage image = aovs;
    image.samples = std::max(samples(), 1);
    image.beauty = cpu ? cpuFull->mean().beauty : full->readMean(); // black before the first sample
    OutputSettings output = displayOutput();
    output.aov = mode == ViewMode::Beauty ? Aov::Beauty : mode == ViewMode::Albedo ? Aov::Albedo : Aov::Normal;
    return writeScreenshot(options.screenshotDir, fs::path(options.map).stem().string(), image, output);
  }
};

Viewer::Viewer(ViewerOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Viewer::~Viewer() = default;
bool Viewer::frame() {
  return impl_->frame();
}
void Viewer::setMode(ViewMode mode) {
  impl_->setMode(mode);
}
void Viewer::setLighting(LightingMode mode) {
  impl_->setLighting(mode);
}
bool Viewer::showCompiled() {
  return impl_->showCompiled();
}
bool Viewer::showDifference() {
  return impl_->showDifference();
}
const std::string& Viewer::notice() const {
  return impl_->notice;
}
const std::string& Viewer::note() const {
  return impl_->note;
}
fs::path Viewer::screenshot() {
  return impl_->takeScreenshot();
}
int Viewer::samples() const {
  return impl_->samples();
}
bool Viewer::cpuTracer() const {
  return impl_->cpu;
}
const std::string& Viewer::cpuReason() const {
  return impl_->cpuReason;
}
int Viewer::reloads() const {
  return impl_->reloads;
}
bool Viewer::luxelsBaked() const {
  return (!impl_->bake || impl_->bake->done()) && (!impl_->cpuBake || impl_->cpuBake->done());
}
int Viewer::glDebugErrors() const {
  return impl_->window.context().debugErrorCount();
}
const std::string& Viewer::error() const {
  return impl_->error;
}
CameraPose Viewer::camera() const {
  return impl_->pose();
}
const PickedFace& Viewer::picked() const {
  return impl_->picked;
}
bool Viewer::reloading() const {
  return impl_->pending != nullptr;
}
bool Viewer::hasLevel() const {
  return impl_->level != nullptr;
}
ViewMode Viewer::mode() const {
  return impl_->mode;
}
LightingMode Viewer::lighting() const {
  return impl_->lighting;
}
bool Viewer::overlayShown() const {
  return impl_->overlayShown;
}
std::vector<OverlayMessage> Viewer::messages() const {
  return impl_->overlayContent().messages;
}
std::vector<std::string> Viewer::warnings() const {
  return impl_->overlayContent().warnings;
}
unsigned long Viewer::x11Window() const {
  return impl_->window.x11Window();
}
bool Viewer::markersShown() const {
  return impl_->markers.shown();
}
Viewer::DisplayImage Viewer::window() {
  impl_->drawWindow(); // the back buffer, as the next swap would show it
  DisplayImage image;
  image.rgba = impl_->window.readBackBuffer(image.width, image.height);
  return image;
}
Viewer::DisplayImage Viewer::displayed() const {
  if (!impl_->display) return {};
  return {impl_->display->width(), impl_->display->height(), gl::readRgba8(*impl_->display)};
}

} // namespace bt

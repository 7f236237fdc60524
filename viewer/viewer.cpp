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
#include "viewer/file_watcher.h"
#include "viewer/fly_camera.h"

#include <epoxy/gl.h>
// epoxy before GLFW, so that GLFW does not include the system GL header.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

namespace bt {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// GPU time a frame gives faithful mode's bake while it runs.
constexpr double kBakeMillisecondsPerFrame = 30.0;

namespace {

// The level as the tracers see it, rebuilt whole on every reload, so a failed reload leaves the
// previous one untouched. `programs` outlive it: a reload uploads the new level and keeps the
// compiled programs. `physical`: the lighting the first images are for (gl::loadGlLevel waits
// for those kernels).
std::unique_ptr<gl::GlLevel> loadLevel(const ViewerOptions& options, gl::GlContext& context,
                                       const std::shared_ptr<gl::TracerPrograms>& programs, bool physical) {
  auto level = std::make_unique<gl::GlLevel>();
  gl::loadGlLevel(*level, context, programs, physical,
                  [&](const gl::EntitiesRead& entitiesRead) { return importScene(options.map, options.import, entitiesRead); });
  return level;
}

uint8_t toByte(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

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
  FileWatcher watcher;
  std::unique_ptr<gl::GlLevel> level;
  // Faithful mode's luxels, baked on the GPU a little every frame from the second on (gl_bake.h);
  // reads level->render, so it goes before the level does.
  std::unique_ptr<gl::ProgressiveLevelBake> bake;
  FlyCamera camera;
  ViewMode mode = ViewMode::Beauty;
  LightingMode lighting;

  // Progressive accumulation at full size, on the GPU; restarted whenever the view changes.
  // While the camera moves, each frame is one sample of a half-size preview instead.
  std::unique_ptr<gl::ProgressiveImage> full;
  std::unique_ptr<gl::ProgressiveImage> preview;
  std::unique_ptr<gl::TonemapPass> tonemap;
  ExposureSmoother autoExposure; // physical mode's exposure, followed from frame to frame
  bool moving = false;
  gl::AovImages aovs; // of the current view, for the albedo/normal modes and screenshots
  bool aovsCurrent = false;
  std::unique_ptr<gl::GlTexture2D> display; // RGBA8, what is on screen (scaled to the window)

  std::string error;
  std::string notice; // why the compiled view could not be shown
  std::string note;   // why the viewer opened in a mode not asked for
  bool compiled = false;
  // Key 7: faithful light accumulates in `full` while the compiled picture of the view, drawn
  // once when the camera stops, waits in compiledPixels (display bytes; empty: not drawn yet).
  bool difference = false;
  std::vector<uint32_t> compiledPacked;
  std::vector<uint8_t> compiledPixels;
  int reloads = 0;
  double wheel = 0.0; // scroll notches since the last frame
  double lastX = 0.0, lastY = 0.0;
  Clock::time_point lastFrame = Clock::now();
  double samplesPerSecond = 0.0;
  double samplesThisFrame = 0.0; // pixel samples the last frame drew
  std::set<int> keysDown;        // for edge-triggered keys

  explicit Impl(ViewerOptions o)
      : options(std::move(o)), window(options.width, options.height, "brushtrace — " + options.map), lighting(options.lighting) {
    // The path tracer compiles (on the driver's threads, where it has them) while the level
    // loads, from when its lights say which program it needs (gl::loadGlLevel).
    programs = std::make_shared<gl::TracerPrograms>(window.context(), options.textures);
    level = loadLevel(options, window.context(), programs, lighting == LightingMode::Physical);
    startBake();
    watchLevelFiles();
    const CameraPose pose = options.camera ? *options.camera : defaultCameraPose(level->scene);
    camera = FlyCamera(glm::dvec3(pose.origin), pose.pitch, pose.yaw);
    // Before ImGui's context, which only the destructor ends: a throw here leaves nothing behind.
    full = std::make_unique<gl::ProgressiveImage>(options.width, options.height);
    preview = std::make_unique<gl::ProgressiveImage>(std::max(1, options.width / 2), std::max(1, options.height / 2));
    tonemap = std::make_unique<gl::TonemapPass>();
    // After the images: switching views restarts them.
    const bool quake3Default = !options.lightingGiven && level->scene.format == "ibsp46";
    if (quake3Default) note = "a compiled Quake 3 level keeps no lights; showing its lightmaps (--lighting compiled)";
    if (options.compiled || quake3Default) showCompiled();

    glfwSetWindowUserPointer(window.handle(), this);
    glfwSetScrollCallback(window.handle(),
                          [](GLFWwindow* w, double, double dy) { static_cast<Impl*>(glfwGetWindowUserPointer(w))->wheel += dy; });
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;                // no imgui.ini littering the user's folder
    ImGui_ImplGlfw_InitForOpenGL(window.handle(), true); // chains to the scroll callback above
    ImGui_ImplOpenGL3_Init("#version 450");
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
    bake.reset();
    level.reset(); // GL objects before the window's context
  }

  void startBake() {
    bake.reset();
    if (options.luxels) bake = std::make_unique<gl::ProgressiveLevelBake>(level->render, options.bake);
  }

  // Faithful mode shows the compiler's luxels once they are baked; until then the light at each
  // pixel's point. A frame's share of the bake keeps frames coming while it runs.
  void bakeSome() {
    if (!bake || bake->done() || lighting != LightingMode::Faithful || compiled || difference || full->samples() == 0) return;
    if (bake->step(*level->tracer, kBakeMillisecondsPerFrame)) restart();
  }

  CameraPose pose() const {
    return CameraPose{glm::vec3(camera.position), static_cast<float>(camera.pitch), static_cast<float>(camera.yaw), 0.0f, "view"};
  }

  void restart() {
    full->restart();
    aovsCurrent = false;
    compiledPixels.clear();
  }

  bool pressedOnce(int key) {
    const bool down = glfwGetKey(window.handle(), key) == GLFW_PRESS;
    const bool was = keysDown.count(key) > 0;
    if (down)
      keysDown.insert(key);
    else
      keysDown.erase(key);
    return down && !was;
  }

  FlyInput readInput() {
    GLFWwindow* w = window.handle();
    auto held = [w](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
    FlyInput in;
    const bool typing = ImGui::GetIO().WantCaptureKeyboard;
    if (!typing) {
      in.forward = held(GLFW_KEY_W);
      in.back = held(GLFW_KEY_S);
      in.left = held(GLFW_KEY_A);
      in.right = held(GLFW_KEY_D);
      in.down = held(GLFW_KEY_Q) || held(GLFW_KEY_C);
      in.up = held(GLFW_KEY_E) || held(GLFW_KEY_SPACE);
      in.fast = held(GLFW_KEY_LEFT_SHIFT) || held(GLFW_KEY_RIGHT_SHIFT);
    }
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(w, &x, &y);
    in.looking = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (in.looking) {
      in.mouseDx = x - lastX;
      in.mouseDy = y - lastY;
    }
    lastX = x;
    lastY = y;
    if (!ImGui::GetIO().WantCaptureMouse) in.wheel = wheel;
    wheel = 0.0;
    return in;
  }

  void handleKeys() {
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    if (pressedOnce(GLFW_KEY_1)) setMode(ViewMode::Beauty);
    if (pressedOnce(GLFW_KEY_2)) setMode(ViewMode::Albedo);
    if (pressedOnce(GLFW_KEY_3)) setMode(ViewMode::Normal);
    if (pressedOnce(GLFW_KEY_4)) setLighting(LightingMode::Faithful);
    if (pressedOnce(GLFW_KEY_5)) setLighting(LightingMode::Physical);
    if (pressedOnce(GLFW_KEY_6)) showCompiled();
    if (pressedOnce(GLFW_KEY_7)) showDifference();
    if (pressedOnce(GLFW_KEY_F12)) takeScreenshot();
    if (pressedOnce(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(window.handle(), GLFW_TRUE);
  }

  void setMode(ViewMode m) {
    if (mode != m) mode = m;
  }

  void setLighting(LightingMode m) {
    if (lighting == m && !compiled && !difference) return;
    const bool leftCompiledView = compiled || difference; // which replaced the baked luxels
    if (compiled) {
      level->render.lightmaps = {};
      level->tracer->setLightmaps({});
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
    const std::string why = showCompiledLightmaps(level->scene, level->render, options.import.textures.game.game);
    notice = why.empty() ? std::string() : why + "; showing faithful lighting";
    if (!why.empty()) return false;
    compiledPacked = packLightmaps(level->render.lightmaps);
    level->tracer->setLightmaps(compiledPacked);
    compiled = true;
    difference = false;
    lighting = LightingMode::Faithful;
    restart();
    return true;
  }

  // The compiled view against faithful light, as render --lighting difference shows it.
  bool showDifference() {
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
    std::vector<uint8_t> rgba(heat.size() / 3 * 4, 255);
    for (size_t i = 0; i < heat.size() / 3; ++i) std::copy_n(&heat[i * 3], 3, &rgba[i * 4]);
    const gl::GlTexture2D& target = displayOfSize(full->width(), full->height());
    BT_GL(glPixelStorei(GL_UNPACK_ALIGNMENT, 1));
    BT_GL(glTextureSubImage2D(target.id(), 0, 0, 0, full->width(), full->height(), GL_RGBA, GL_UNSIGNED_BYTE, rgba.data()));
  }

  // Every file the level was read from (Scene::inputFiles: the map, prefabs, WADs, palettes,
  // shader scripts, images and companion maps).
  void watchLevelFiles() { watcher.watch({level->scene.inputFiles.begin(), level->scene.inputFiles.end()}); }

  void reloadIfSaved() {
    if (watcher.poll().empty()) return;
    try {
      std::unique_ptr<gl::GlLevel> next = loadLevel(options, window.context(), programs, lighting == LightingMode::Physical);
      bake.reset();
      level = std::move(next);
      startBake();
      error.clear();
      ++reloads;
      if (compiled || difference) {
        const bool wasDifference = difference;
        compiled = difference = false;
        if (showCompiled() && wasDifference) showDifference();
      }
      restart();
    } catch (const std::exception& e) {
      // Keep showing the last good level; the error stays on screen until a save fixes it.
      error = e.what();
    }
    watchLevelFiles();
  }

  gl::CameraBasis basis(int width, int height) const {
    return gl::CameraBasis::fromQuakeAngles(glm::vec3(camera.position), static_cast<float>(camera.pitch), static_cast<float>(camera.yaw),
                                            0.0f, width, height);
  }

  void renderAovsIfNeeded() {
    if (aovsCurrent) return;
    aovs = level->tracer->renderAovs(basis(options.width, options.height), options.width, options.height);
    aovsCurrent = true;
  }

  gl::BeautySettings beautySettings() const {
    return gl::BeautySettings{.physical = lighting == LightingMode::Physical, .bounces = options.bounces};
  }

  // One sample: of a half-size preview while the camera moves, else one more full-size sample
  // into the accumulation. Either is tonemapped on the GPU into the display image.
  void renderSample() {
    if (mode != ViewMode::Beauty) {
      renderAovsIfNeeded();
      showAov();
      return;
    }
    if (!moving) bakeSome();
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

  // Physical mode is exposed automatically as `render` exposes it (renderer/exposure.h), from a
  // read-back of the image a few times a second, smoothed so the picture does not pump.
  float exposureOf(const gl::ProgressiveImage& image) {
    if (lighting != LightingMode::Physical || image.samples() == 0) return displayExposure();
    const double now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    if (autoExposure.due(now)) autoExposure.update(autoExposureEv(image.readMean(), image.width(), image.height()), now);
    return autoExposure.ev();
  }
  float displayExposure() const { return lighting == LightingMode::Physical ? autoExposure.ev() : options.exposureEv; }

  // The albedo and normal views are one deterministic sample each, converted here as the
  // render command's PNGs are.
  void showAov() {
    const int width = aovs.width, height = aovs.height;
    std::vector<uint8_t> rgba(static_cast<size_t>(width) * height * 4);
    for (size_t i = 0; i < aovs.albedo.size(); ++i) {
      glm::vec3 c = mode == ViewMode::Albedo ? linearToSrgb(glm::vec3(aovs.albedo[i])) : aovs.normal[i] * 0.5f + 0.5f;
      if (mode == ViewMode::Normal && aovs.face[i] == gl::AovImages::kNothingHit) c = glm::vec3(0.0f);
      rgba[i * 4 + 0] = toByte(c.r);
      rgba[i * 4 + 1] = toByte(c.g);
      rgba[i * 4 + 2] = toByte(c.b);
      rgba[i * 4 + 3] = 255;
    }
    const gl::GlTexture2D& target = displayOfSize(width, height);
    BT_GL(glPixelStorei(GL_UNPACK_ALIGNMENT, 1));
    BT_GL(glTextureSubImage2D(target.id(), 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data()));
  }

  void drawOverlay() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window.handle(), &fbWidth, &fbHeight);
    if (display)
      ImGui::GetBackgroundDrawList()->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(display->id())), ImVec2(0, 0),
                                               ImVec2(float(fbWidth), float(fbHeight)));

    ImGui::SetNextWindowPos(ImVec2(8, 8));
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("brushtrace", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                     ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
    const char* modeName = mode == ViewMode::Beauty ? "beauty" : mode == ViewMode::Albedo ? "albedo" : "normal";
    const char* lightingName = difference    ? "compiled vs faithful (black 0, blue 8, green 16, yellow 24, red 32+ levels)"
        : compiled                           ? "compiled"
        : lighting == LightingMode::Faithful ? "faithful"
                                             : "physical";
    ImGui::Text("%s | %s lighting | %s", modeName, lightingName, gl::toString(level->tracer->textureMode()));
    ImGui::Text("spp %d | %.2f Msamples/s", full->samples(), samplesPerSecond * 1e-6);
    if (bake && lighting == LightingMode::Faithful && !bake->done())
      ImGui::Text("baking luxels: pass %d of %d", bake->passesDone(), std::max(bake->passes(), 1));
    ImGui::Text("camera %s", formatCameraPose(pose()).c_str());
    ImGui::TextDisabled("RMB look, WASD move, Q/E down/up, wheel fwd, RMB+wheel speed (%.0f)", camera.speed);
    ImGui::TextDisabled("1 beauty 2 albedo 3 normal | 4 faithful 5 physical 6 compiled 7 difference | F12 screenshot");
    if (!notice.empty()) ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", notice.c_str());
    if (!error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "reload failed: %s", error.c_str());
    ImGui::End();

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

    handleKeys();
    moving = camera.update(readInput(), dt);
    if (moving) restart();
    reloadIfSaved();
    renderSample();
    drawOverlay();
    glfwSwapBuffers(window.handle());
    return true;
  }

  fs::path takeScreenshot() {
    renderAovsIfNeeded();
    RenderImage image;
    image.width = aovs.width;
    image.height = aovs.height;
    image.samples = std::max(full->samples(), 1);
    const size_t n = static_cast<size_t>(image.width) * image.height;
    image.beauty = full->readMean(); // black before the first sample
    image.albedo.resize(n);
    for (size_t i = 0; i < n; ++i) image.albedo[i] = glm::vec3(aovs.albedo[i]);
    image.normal = aovs.normal;
    image.depth = aovs.depth;
    image.face = aovs.face;

    const std::string stem = fs::path(options.map).stem().string();
    fs::path png;
    for (int i = 0;; ++i) {
      png = options.screenshotDir / fmt::format("{}-{:03}.png", stem, i);
      if (!fs::exists(png)) break;
    }
    OutputSettings output;
    output.aov = mode == ViewMode::Beauty ? Aov::Beauty : mode == ViewMode::Albedo ? Aov::Albedo : Aov::Normal;
    output.tonemap = tonemapFor(lighting);
    output.exposureEv = displayExposure();
    writeImage(png.string(), image, output);
    fs::path exr = png;
    exr.replace_extension(".exr");
    writeImage(exr.string(), image, output);
    return png;
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
  return impl_->full->samples();
}
int Viewer::reloads() const {
  return impl_->reloads;
}
bool Viewer::luxelsBaked() const {
  return !impl_->bake || impl_->bake->done();
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
Viewer::DisplayImage Viewer::displayed() const {
  if (!impl_->display) return {};
  return {impl_->display->width(), impl_->display->height(), gl::readRgba8(*impl_->display)};
}

} // namespace bt

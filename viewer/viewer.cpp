#include "viewer/viewer_impl.h"

#include <set>

namespace bt {

namespace fs = std::filesystem;
using Clock = ViewerClock;

// GPU time a frame gives faithful mode's bake while it runs.
constexpr double kBakeMillisecondsPerFrame = 30.0;
// The GL tracer's share of a frame where the GL is slow (llvmpipe takes seconds for a pass at
// 640x360): with the overlay, input and reloads are served about ten times a second, as the CPU
// tracer's window serves them (viewer_display.cpp kCpuFrameBudget).
constexpr std::chrono::milliseconds kGlPieceBudget(80);

Viewer::Impl::Impl(ViewerOptions o)
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
  pieces = std::make_unique<gl::PieceSizer>(kGlPieceBudget);
  if (options.camera) placeCamera(*options.camera);
  // A level that does not load opens the window with the error; the next good save loads it.
  try {
    const std::unique_ptr<PendingLevel> first = startImport();
    installLevel(finishLoading(*first), *first->missingFiles);
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

Viewer::Impl::~Impl() {
  // GL objects before the window's context.
  display.reset();
  denoiser.reset();
  tonemap.reset();
  pieces.reset();
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

void Viewer::Impl::chooseTracer() {
  const gl::GlContextInfo& info = window.context().info();
  if (options.backend == ViewerBackend::Cpu) cpuReason = "drawing with the CPU tracer (--backend cpu)";
  if (options.backend == ViewerBackend::Auto && info.softwareRenderer)
    cpuReason = fmt::format("the window's GL is software ({}): drawing with the CPU tracer, several times faster there "
                            "(--backend gl forces the GL tracer)",
                            info.renderer);
  cpu = !cpuReason.empty();
}

std::unique_ptr<gl::GlLevel> Viewer::Impl::finishLoading(PendingLevel& loading) {
  if (cpu)
    loading.preparation->wait();
  else
    gl::loadGlLevel(*loading.level, *loading.preparation, window.context(), programs, lighting == LightingMode::Physical);
  return std::move(loading.level);
}

std::unique_ptr<PendingLevel> Viewer::Impl::startImport() {
  ++imports;
  return std::make_unique<PendingLevel>(options);
}

void Viewer::Impl::placeCamera(const CameraPose& pose) {
  camera = FlyCamera(glm::dvec3(pose.origin), pose.pitch, pose.yaw);
  cameraPlaced = true;
}

void Viewer::Impl::installLevel(std::unique_ptr<gl::GlLevel> next, const std::vector<std::string>& missingFiles) {
  if (cpuBake && !cpuBake->ready()) { // it reads the level replaced: both go when it ends
    cpuBake->holdUntilDone(std::shared_ptr<const gl::GlLevel>(std::move(level)));
    retiredBakes.push_back(std::move(cpuBake));
  }
  cpuBake.reset();
  bake.reset();
  styled = {};
  level = std::move(next);
  baseColors.clear();
  for (const GpuLight& light : level->render.lights) baseColors.push_back(light.color);
  baseSurfaceColors.clear();
  for (const GpuLight& tmpl : level->render.surfaceLights) baseSurfaceColors.push_back(tmpl.color);
  lightScale = CpuLuxelBake::kUnitStyleWeights;
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

void Viewer::Impl::startBake() {
  // A CPU bake still running is this level's: its luxels are taken when it is done. (The
  // compiled view replaces only render.lightmaps, which the bake does not read.)
  if (cpuBake && !cpuBake->done()) return;
  cpuBake.reset();
  bake.reset();
  styled = {};
  if (!options.luxels) return;
  ++bakes;
  // A level with styled lights bakes one luxel set per style on the CPU for either window (the
  // GPU's bake.comp keeps one), for the sliders. The GL window still bakes on the GPU, styled or
  // not: its first converged picture comes from there (lq_e4m3, 51 styled lights: a tenth of a
  // second on an H100, where the CPU's sets take minutes on a 2-core machine).
  const bool styledLevel = !lightStylesOf(level->render).empty();
  if (styledLevel) scaleLights(CpuLuxelBake::kUnitStyleWeights); // the sets are of the lights as loaded
  if (cpu || styledLevel) cpuBake = std::make_unique<CpuLuxelBake>(level->render, options.bake, styledLevel);
  if (!cpu) bake = std::make_unique<gl::ProgressiveLevelBake>(level->render, options.bake), ++gpuBakes;
}

bool Viewer::Impl::slidersAtOne() const {
  const std::vector<int> styles = lightStyles();
  return std::all_of(styles.begin(), styles.end(), [&](int style) { return styleScale[size_t(style)] == 1.0f; });
}

void Viewer::Impl::bakeSome() {
  std::erase_if(retiredBakes, [](const std::unique_ptr<CpuLuxelBake>& b) { return b->ready(); });
  if (cpuBake && lighting == LightingMode::Faithful && !compiled && cpuBake->takeInto(level->render, styleScale, &styled)) {
    // The GL window's GPU bake, done, already shows the luxels of the sliders at 1; the CPU's
    // sets replace it where a slider moved, or where they came first.
    if (cpu || !bake || !bake->done() || !slidersAtOne()) {
      bake.reset();
      if (!cpu) level->tracer->setLightmaps(packLightmaps(level->render.lightmaps));
      restart();
    }
  }
  if (!level || !bake || bake->done() || lighting != LightingMode::Faithful || compiled || full->samples() == 0) return;
  if (bake->step(*level->tracer, kBakeMillisecondsPerFrame)) restart();
}

CameraPose Viewer::Impl::pose() const {
  return CameraPose{glm::vec3(camera.position), static_cast<float>(camera.pitch), static_cast<float>(camera.yaw), 0.0f, "view"};
}

void Viewer::Impl::restart() {
  full->restart();
  cpuFull->restart();
  aovsCurrent = false;
  compiledPixels.clear();
}

void Viewer::Impl::setMode(ViewMode m) {
  if (mode != m) mode = m;
}

void Viewer::Impl::setLighting(LightingMode m) {
  if (!level) {
    lighting = m;
    return;
  }
  if (lighting == m && !compiled && !difference) return;
  const bool leftCompiledView = compiled; // which replaced the baked luxels (the difference view keeps them)
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

bool Viewer::Impl::showCompiled() {
  if (!level) return false;
  const std::string why = showCompiledLightmaps(level->scene, level->render, options.import.textures.game.game, &styleScale);
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

bool Viewer::Impl::showDifference() {
  if (cpu) {
    notice = "the compiled-against-faithful view needs the GL tracer; showing faithful lighting";
    return false;
  }
  if (!compiled && !showCompiled()) return false;
  // The compiled picture against what the faithful view shows, baked luxels and all (as render
  // --lighting difference compares them): the faithful luxels come back, the compiled ones are
  // kept packed for drawCompiledPicture.
  level->render.lightmaps = {};
  level->tracer->setLightmaps({});
  compiled = false;
  difference = true;
  startBake();
  restart();
  return true;
}

void Viewer::Impl::weighCompiledAgain() {
  Lightmaps faithful = std::exchange(level->render.lightmaps, Lightmaps{});
  showCompiledLightmaps(level->scene, level->render, options.import.textures.game.game, &styleScale);
  compiledPacked = packLightmaps(level->render.lightmaps);
  level->render.lightmaps = std::move(faithful);
}

void Viewer::Impl::watchLevelFiles(const std::vector<std::string>& missingFiles) {
  std::vector<fs::path> files(level->scene.inputFiles.begin(), level->scene.inputFiles.end());
  files.insert(files.end(), missingFiles.begin(), missingFiles.end());
  watcher.watch(files);
}

void Viewer::Impl::reloadIfSaved() {
  if (!pending) {
    // A save: the level again, on the worker thread.
    if (watcher.takeChange()) pending = startImport();
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

bool Viewer::Impl::frame() {
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
  followStyleSliders();
  renderSample();
  drawWindow();
  glfwSwapBuffers(window.handle());
  return true;
}

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
int Viewer::imports() const {
  return impl_->imports;
}
int Viewer::bakes() const {
  return impl_->bakes;
}
int Viewer::gpuBakes() const {
  return impl_->gpuBakes;
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
void Viewer::setDenoise(bool on) {
  impl_->denoise = on;
}
bool Viewer::denoising() const {
  return impl_->denoise;
}
std::vector<int> Viewer::Impl::lightStyles() const {
  std::set<int> styles;
  if (level)
    for (const GpuLight& light : level->render.lights)
      if (lightStyle(light) != 0) styles.insert(int(lightStyle(light)));
  return {styles.begin(), styles.end()};
}

void Viewer::Impl::setStyleScale(int style, float scale) {
  if (style <= 0 || style > 255 || styleScale[size_t(style)] == scale) return;
  styleScale[size_t(style)] = std::clamp(scale, 0.0f, 2.0f);
  // No import, no bake: the luxels re-summed now (else the bake's sum takes the weights when it
  // is done), the lights scaled at the next frame.
  if (level && !styled.styles.empty() && !compiled) sumStyledLuxels();
  if (level && compiled) showCompiled(); // the compiled styles weighed again: a pass over the luxels, no import
  if (level && difference) weighCompiledAgain(), restart();
  followStyleSliders();
}

void Viewer::Impl::sumStyledLuxels() {
  level->render.lightmaps.luxels = sumStyles(styled, styleScale);
  if (!cpu) level->tracer->setLightmaps(packLightmaps(level->render.lightmaps));
  restart();
}

void Viewer::Impl::scaleLights(const std::array<float, 256>& scale) {
  if (scale == lightScale) return;
  RenderScene& rs = level->render;
  // Sliders of styles this level has no light of change nothing (and touch no light a bake reads).
  const auto moved = [&](const GpuLight& light) { return scale[lightStyle(light)] != lightScale[lightStyle(light)]; };
  const bool lightsMove = std::any_of(rs.lights.begin(), rs.lights.end(), moved);
  // A styled `_surface` template's faces are physical mode's area emitters: its slider scales
  // them as it scales the template's points (render --style scales the light before either).
  const bool emittersMove =
      std::any_of(rs.surfaceLights.begin(), rs.surfaceLights.end(), [&](const GpuLight& t) { return t.value > 0.0f && moved(t); });
  lightScale = scale;
  if (!lightsMove && !emittersMove) return;
  if (lightsMove) {
    for (size_t i = 0; i < rs.lights.size(); ++i) rs.lights[i].color = baseColors[i] * scale[lightStyle(rs.lights[i])];
    rs.lightGrid = buildLightGrid(rs.lights, rs.tracer.bounds(), rs.world.scaledist);
    if (!cpu) level->tracer->setLights(rs.lights, rs.lightGrid, rs.world.scaledist);
  }
  if (emittersMove) {
    for (size_t m = 0; m < rs.surfaceLights.size(); ++m)
      rs.surfaceLights[m].color = baseSurfaceColors[m] * scale[lightStyle(rs.surfaceLights[m])];
    if (!cpu) level->tracer->setSurfaceLights(rs.surfaceLights);
  }
  restart();
}

void Viewer::Impl::followStyleSliders() {
  if (level && !(cpuBake && !cpuBake->ready())) scaleLights(styleScale);
}

std::vector<int> Viewer::lightStyles() const {
  return impl_->lightStyles();
}
void Viewer::setStyleScale(int style, float scale) {
  impl_->setStyleScale(style, scale);
}
bool Viewer::stylesApplied() const {
  return impl_->lightScale == impl_->styleScale;
}
float Viewer::styleScale(int style) const {
  return impl_->styleScale[size_t(std::clamp(style, 0, 255))];
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

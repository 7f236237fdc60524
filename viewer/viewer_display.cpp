#include "viewer/viewer_impl.h"

#include "renderer/denoise.h"
#include "renderer/denoise_fade.h"

namespace bt {

namespace fs = std::filesystem;
using Clock = ViewerClock;

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

void Viewer::Impl::drawCompiledPicture() {
  gl::ProgressiveImage image(options.width, options.height);
  // The tracer holds the faithful luxels (the GPU bake's live only there): they go back after.
  const std::vector<uint32_t> faithful = level->tracer->readLightmaps();
  level->tracer->setLightmaps(compiledPacked);
  for (int i = 0; i < 4; ++i) image.addSample(*level->tracer, basis(image.width(), image.height()), beautySettings());
  level->tracer->setLightmaps(faithful);
  compiledPixels = displayPixels(meanImage(image), displayOutput());
}

RenderImage Viewer::Impl::meanImage(const gl::ProgressiveImage& image) const {
  RenderImage out;
  out.width = image.width();
  out.height = image.height();
  out.beauty = image.readMean(&out.luminanceMoment2);
  return out;
}

OutputSettings Viewer::Impl::displayOutput() const {
  OutputSettings output;
  output.tonemap = tonemapFor(lighting);
  output.exposureEv = displayExposure();
  return output;
}

void Viewer::Impl::showDifferenceImage() {
  const std::vector<uint8_t> heat = differencePixels(compiledPixels, displayPixels(meanImage(*full), displayOutput()));
  showRgba(full->width(), full->height(), rgbToRgba(heat));
}

gl::CameraBasis Viewer::Impl::basis(int width, int height) const {
  return gl::CameraBasis::fromQuakeAngles(glm::vec3(camera.position), static_cast<float>(camera.pitch), static_cast<float>(camera.yaw),
                                          0.0f, width, height);
}

void Viewer::Impl::renderAovsIfNeeded() {
  if (aovsCurrent) return;
  aovs = cpu ? renderAovsCpu(level->render, Camera(pose(), options.width, options.height), options.width, options.height)
             : aovImage(level->tracer->renderAovs(basis(options.width, options.height), options.width, options.height));
  aovsCurrent = true;
}

gl::BeautySettings Viewer::Impl::beautySettings() const {
  return gl::BeautySettings{
      .physical = lighting == LightingMode::Physical, .bounces = options.bounces, .clampIndirect = options.clampIndirect};
}

void Viewer::Impl::renderSample() {
  if (!level) {
    display.reset(); // nothing to show but the error
    return;
  }
  if (mode != ViewMode::Beauty && mode != ViewMode::LightOnly) {
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
    // A piece of the pass, sized to the GL's speed: all of it on a GPU, a part on llvmpipe, so
    // that the next frame (its keys, a reload) comes within about kGlPieceBudget.
    const size_t wanted = pieces->nextPixels(size_t(image.width()) * size_t(image.height()));
    const size_t drawn =
        pieces->timed([&] { return image.addPiece(*level->tracer, basis(image.width(), image.height()), beautySettings(), wanted); });
    // The first image is up: the other lighting mode compiles in the background, so that
    // switching to it (keys 4/5) does not stall.
    if (!moving && before == 0 && image.samples() == 1)
      programs->startPathTracer(lighting != LightingMode::Physical, level->tracer->faithfulFeatures());
    samplesThisFrame = double(drawn);
  }
  if (difference && !moving)
    showDifferenceImage();
  else if (shownOnCpu(image.samples())) {
    exposureOf(image); // physical mode's exposure follows the raw image, as render's does
    showImage(shownImage(meanImage(image), image.samples()));
  } else
    showSum(image);
}

bool Viewer::Impl::shownOnCpu(int spp) const {
  return mode == ViewMode::LightOnly || (mode == ViewMode::Beauty && denoiserShare(spp) > 0.0f);
}

float Viewer::Impl::denoiserShare(int spp) const {
  return denoise && lighting == LightingMode::Physical && !compiled && !difference ? denoiseShare(std::max(spp, 1), options.denoiseFade)
                                                                                   : 0.0f;
}

const RenderImage& Viewer::Impl::aovsOfSize(int width, int height) {
  if (width == options.width && height == options.height) {
    renderAovsIfNeeded();
    return aovs;
  }
  // The half-size preview while the camera moves: one ray a pixel, cheap beside its sample.
  previewAovs = cpu ? renderAovsCpu(level->render, Camera(pose(), width, height), width, height)
                    : aovImage(level->tracer->renderAovs(basis(width, height), width, height));
  return previewAovs;
}

RenderImage Viewer::Impl::shownImage(RenderImage mean, int spp) {
  const RenderImage& guide = aovsOfSize(mean.width, mean.height);
  std::vector<glm::vec3> raw = std::move(mean.beauty);
  std::vector<float> moment2 = std::move(mean.luminanceMoment2); // the denoiser's variance
  mean = guide;
  mean.samples = std::max(spp, 1);
  mean.beauty = std::move(raw);
  mean.luminanceMoment2 = std::move(moment2);
  if (mode == ViewMode::LightOnly) {
    mean.beauty = lightAlone(mean, lighting != LightingMode::Physical);
  } else if (mode == ViewMode::Beauty && denoiserShare(spp) > 0.0f) {
    if (!cpu && !denoiser) denoiser = std::make_unique<gl::DenoisePass>();
    const std::vector<glm::vec3> denoised = cpu ? bt::denoise(mean) : gl::denoiseWithGl(mean, *denoiser);
    mean.beauty = displayedBeauty(mean.beauty, denoised, mean.samples, options.denoiseFade); // what the bench measures too
  }
  return mean;
}

void Viewer::Impl::showImage(const RenderImage& image) {
  showRgba(image.width, image.height, rgbToRgba(displayPixels(image, displayOutput())));
}

const gl::GlTexture2D& Viewer::Impl::displayOfSize(int width, int height) {
  if (!display || display->width() != width || display->height() != height)
    display = std::make_unique<gl::GlTexture2D>(GL_RGBA8, width, height);
  return *display;
}

void Viewer::Impl::showSum(const gl::ProgressiveImage& image) {
  // Each pixel by its own count: the whole passes, then the part of the pass under way with one
  // sample more (the pixels it has not reached yet keep what they showed, black after a resize).
  const gl::GlTexture2D& shown = displayOfSize(image.width(), image.height());
  const float ev = exposureOf(image);
  if (image.samples() > 0) tonemap->run(image.sum(), image.samples(), shown, tonemapFor(lighting), ev);
  for (const gl::PixelRect& done : image.donePieces())
    tonemap->run(image.sum(), image.samples() + 1, shown, tonemapFor(lighting), ev, done);
}

float Viewer::Impl::exposureOf(const gl::ProgressiveImage& image) {
  const double now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  if (lighting == LightingMode::Physical && image.samples() > 0 && autoExposure.due(now))
    autoExposure.update(autoExposureEv(image.readMean(), image.width(), image.height()), now);
  return displayExposure();
}

void Viewer::Impl::showRgba(int width, int height, const std::vector<uint8_t>& rgba) {
  const gl::GlTexture2D& target = displayOfSize(width, height);
  BT_GL(glPixelStorei(GL_UNPACK_ALIGNMENT, 1));
  BT_GL(glTextureSubImage2D(target.id(), 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data()));
}

void Viewer::Impl::refineOnCpu() {
  CpuProgressive& image = moving ? *cpuPreview : *cpuFull;
  if (moving) cpuPreview->restart();
  const Camera view(pose(), image.width(), image.height());
  IntegratorSettings integrator;
  integrator.mode = lighting;
  integrator.bounces = options.bounces;
  integrator.clampIndirect = options.clampIndirect;
  samplesThisFrame = double(image.refine(level->render, view, integrator, kCpuFrameBudget, moving ? 1 : options.maxSamples));
  // A pass under way: its rows have one sample more, which the denoiser's strength need not tell.
  const int spp = std::max(image.samples(), 1);
  showImage(shownOnCpu(spp) ? shownImage(image.mean(), spp) : image.mean());
}

OverlayContent Viewer::Impl::overlayContent() const {
  OverlayContent c;
  if (level) {
    const char* lightingName = difference    ? "compiled vs faithful (black 0, blue 8, green 16, yellow 24, red 32+ levels)"
        : compiled                           ? "compiled"
        : lighting == LightingMode::Faithful ? "faithful"
                                             : "physical";
    const char* tracer = cpu ? "CPU tracer" : gl::toString(level->tracer->textureMode());
    c.status.push_back(fmt::format("{} | {} lighting | {}", toString(mode), lightingName, tracer));
    c.status.push_back(fmt::format("spp {} | {:.2f} Msamples/s", samples(), samplesPerSecond * 1e-6));
    if (lighting == LightingMode::Physical && !compiled && !difference)
      c.status.push_back(denoise ? fmt::format("denoiser on: {:.0f} % denoised (full to {} spp, none from {})",
                                               100.0f * denoiserShare(samples()), options.denoiseFade.fullUntil, options.denoiseFade.goneAt)
                                 : std::string("denoiser off (N)"));
    if (cpuBake && lighting == LightingMode::Faithful && !cpuBake->done()) c.status.push_back("baking luxels on the CPU");
    if (bake && lighting == LightingMode::Faithful && !bake->done())
      c.status.push_back(fmt::format("baking luxels: pass {} of {}", bake->passesDone(), std::max(bake->passes(), 1)));
    c.status.push_back("camera " + formatCameraPose(pose()));
    c.picked = picked.lines;
    for (const int style : lightStyles()) c.styles.emplace_back(style, styleScale[size_t(style)]);
    for (const Diagnostic& d : level->scene.diagnostics)
      if (d.severity != Severity::Note) c.warnings.push_back(format(d));
  }
  if (pending) c.status.push_back("reloading " + options.map + " ...");
  if (!level) c.picked.clear();
  if (cpu) c.status.insert(c.status.begin(), cpuReason);
  c.hints.push_back(fmt::format("RMB look, WASD move, Q/E down/up, wheel fwd, RMB+wheel speed ({:.0f})", camera.speed));
  c.hints.push_back(
      "1 lit 2 fullbright 3 normals 8 light only 9 flat | 4 faithful 5 physical 6 compiled 7 difference | N denoiser | F12 "
      "screenshot | click: face | Ctrl+C copy camera, Ctrl+Shift+C its file:line | L markers | Ctrl/Alt+0-9 bookmarks | F1 overlay");
  if (!notice.empty()) c.messages.push_back({OverlayMessage::Kind::Warning, notice});
  if (!error.empty())
    c.messages.push_back({OverlayMessage::Kind::Error, (level ? "reload failed: " : "cannot load the level (save a fix): ") + error});
  if (Clock::now() < flashUntil) c.messages.push_back(flash);
  return c;
}

void Viewer::Impl::drawWindow() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  int fbWidth = 0, fbHeight = 0;
  glfwGetFramebufferSize(window.handle(), &fbWidth, &fbHeight);
  if (display)
    ImGui::GetBackgroundDrawList()->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(display->id())), ImVec2(0, 0),
                                             ImVec2(float(fbWidth), float(fbHeight)));
  if (level) markers.draw(Camera(pose(), options.width, options.height), options.width, options.height);
  if (overlayShown)
    if (const std::optional<StyleMoved> moved = drawOverlay(overlayContent())) setStyleScale(moved->style, moved->scale);
  ImGui::Render();
  BT_GL(glViewport(0, 0, fbWidth, fbHeight));
  BT_GL(glClearColor(0, 0, 0, 1));
  BT_GL(glClear(GL_COLOR_BUFFER_BIT));
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

} // namespace bt

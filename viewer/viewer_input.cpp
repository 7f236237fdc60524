#include "viewer/viewer_impl.h"

namespace bt {

namespace fs = std::filesystem;
using Clock = ViewerClock;

// How long the overlay shows a screenshot's path, and why one failed.
constexpr std::chrono::seconds kScreenshotShown(4);
constexpr std::chrono::seconds kScreenshotErrorShown(10);

void Viewer::Impl::handlePresses() {
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

void Viewer::Impl::actOnKey(int key) {
  if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(window.handle(), GLFW_TRUE);
  if (key == GLFW_KEY_F12) screenshotWithFeedback();
  if (!level) return; // the keys below change the view of a level
  if (key == GLFW_KEY_1) setMode(ViewMode::Beauty);
  if (key == GLFW_KEY_2) setMode(ViewMode::Fullbright);
  if (key == GLFW_KEY_3) setMode(ViewMode::Normal);
  if (key == GLFW_KEY_8) setMode(ViewMode::LightOnly);
  if (key == GLFW_KEY_9) setMode(ViewMode::Flat);
  if (key == GLFW_KEY_N) denoise = !denoise;
  if (key == GLFW_KEY_4) setLighting(LightingMode::Faithful);
  if (key == GLFW_KEY_5) setLighting(LightingMode::Physical);
  if (key == GLFW_KEY_6) showCompiled();
  if (key == GLFW_KEY_7) showDifference();
  if (key == GLFW_KEY_L) markers.toggle();
}

void Viewer::Impl::pick(double x, double y) {
  int width = 0, height = 0;
  glfwGetWindowSize(window.handle(), &width, &height);
  const float px = float(x * options.width / std::max(width, 1)), py = float(y * options.height / std::max(height, 1));
  // The compiled and difference views show baked light: their shares are faithful mode's.
  IntegratorSettings lightingHere;
  lightingHere.mode = compiled || difference ? LightingMode::Faithful : lighting;
  lightingHere.bounces = options.bounces;
  lightingHere.clampIndirect = options.clampIndirect;
  picked = pickFace(level->render, pose(), options.width, options.height, px, py, lightingHere);
}

void Viewer::Impl::showFor(std::chrono::seconds duration, OverlayMessage message) {
  flash = std::move(message);
  flashUntil = Clock::now() + duration;
}

void Viewer::Impl::copyToClipboard(bool pickedFace) {
  const CameraPose p = pose();
  const std::string text = pickedFace ? picked.fileLine
                                      : fmt::format("--camera '{}'\nsetpos {:g} {:g} {:g} {:g} {:g} {:g}\n", formatCameraPose(p),
                                                    p.origin.x, p.origin.y, p.origin.z, p.pitch, p.yaw, p.roll);
  if (text.empty()) return;
  glfwSetClipboardString(window.handle(), text.c_str());
  showFor(kScreenshotShown, {OverlayMessage::Kind::Info, pickedFace ? "copied " + text : "copied the camera: " + formatCameraPose(p)});
}

void Viewer::Impl::screenshotWithFeedback() {
  try {
    showFor(kScreenshotShown, {OverlayMessage::Kind::Info, "screenshot " + takeScreenshot().string()});
  } catch (const std::exception& e) {
    showFor(kScreenshotErrorShown, {OverlayMessage::Kind::Error, std::string("screenshot failed: ") + e.what()});
  }
}

fs::path Viewer::Impl::takeScreenshot() {
  if (!level) throw std::runtime_error("no level is loaded");
  renderAovsIfNeeded();
  RenderImage image = aovs;
  image.samples = std::max(samples(), 1);
  if (cpu) { // black before the first sample
    RenderImage mean = cpuFull->mean();
    image.beauty = std::move(mean.beauty), image.luminanceMoment2 = std::move(mean.luminanceMoment2);
  } else {
    image.beauty = full->readMean(&image.luminanceMoment2);
  }
  // What is on screen: the light alone, or the young physical image denoised (the EXR too).
  if (shownOnCpu(samples())) image = shownImage(std::move(image), samples());
  OutputSettings output = displayOutput();
  output.aov = mode == ViewMode::Fullbright ? Aov::Albedo
      : mode == ViewMode::Normal            ? Aov::Normal
      : mode == ViewMode::Flat              ? Aov::Face
                                            : Aov::Beauty;
  return writeScreenshot(options.screenshotDir, fs::path(options.map).stem().string(), image, output);
}

} // namespace bt

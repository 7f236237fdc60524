// `brushtrace view`: the level in a window, path-traced progressively on the GPU, reloaded
// whenever a file the import read is saved (the map, prefabs, WADs, palettes, shader scripts,
// every texture image and companion map: Scene::inputFiles).
//
// Samples accumulate in one RGBA32F image on the GPU and a compute pass tonemaps it into the
// image the window draws, so nothing is read back per frame (gl_progressive.h).
// One Viewer is one window. frame() runs one iteration of the loop (every key pressed since the
// last frame, camera, a finished reload, one sample, tonemap, overlay, present), so tests drive
// it frame by frame under Xvfb. The files are watched on a thread of their own and a reload's
// import runs on a worker thread, so neither waits for a frame nor holds one up.
#pragma once

#include "importers/import.h"
#include "renderer/camera.h"
#include "renderer/cpu/integrator.h"
#include "lighting/lightmap_bake.h"
#include "renderer/gl/gl_textures.h"
#include "viewer/overlay.h"
#include "viewer/picking.h"
#include "viewer/view_modes.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bt {

// Which tracer draws the window: Auto takes the GL tracer unless the window's GL is emulated on
// the CPU (llvmpipe), where the CPU tracer is several times faster; as `render --backend`.
enum class ViewerBackend { Auto, Gl, Cpu };

struct ViewerOptions {
  std::string map;
  ImportOptions import;
  int width = 1280;
  int height = 720;
  std::optional<CameraPose> camera; // default: the render command's default camera
  gl::TextureMode textures = gl::TextureMode::Auto;
  ViewerBackend backend = ViewerBackend::Auto;
  LightingMode lighting = LightingMode::Faithful;
  bool compiled = false; // --lighting compiled: a .bsp's own lightmaps (key 6), in faithful mode
  // --lighting given; without it a compiled Quake 3 level opens in the compiled view (q3map2
  // leaves no light entities in it, so faithful light would be black), with note() saying so.
  bool lightingGiven = false;
  int bounces = 3;
  float clampIndirect = kClampIndirectDefault; // physical mode's firefly clamp (render's --clamp-indirect)
  std::filesystem::path screenshotDir = ".";
  int maxSamples = 4096;                  // refinement stops here; the window stays responsive
  float exposureEv = 0.0f;                // as render's --exposure: on screen, in screenshots and in the EXR
  bool luxels = true;                     // faithful mode: the compiler's luxels, baked on the GPU (render's --luxels)
  LightmapBakeOptions bake;               // their --extra
  std::filesystem::path bookmarksFile;    // camera bookmarks (viewer/bookmarks.h); empty: this session only
  bool denoise = true;                    // physical mode shows the denoised image while it is young (key N; renderer/denoise_fade.h)
  DenoiseFade denoiseFade = kDenoiseFade; // its fade to the raw image; tests shorten it
};

class Viewer {
public:
  // Opens the window and loads the level. A level that cannot be imported opens the window with
  // the error (error(), hasLevel() false) and loads at the next save that fixes it. Throws when no
  // window can be opened (the message says why).
  explicit Viewer(ViewerOptions options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // One iteration of the loop. Returns false once the window has been asked to close.
  bool frame();

  void setMode(ViewMode mode);
  void setDenoise(bool on); // key N
  // The light-style sliders of the overlay: the styles the level's lights use (styled lights 1-31,
  // switchable lights 32 on; start-off lights are not drawn and have none), and each one's scale
  // of its lights' contribution, 0 (off) to 2, 1 by default as faithful mode shows it. Setting
  // one imports and bakes nothing: faithful mode's luxels of a styled level are baked one set per
  // style and re-summed, as the engine weighs each style's lightmap (lightmap_bake.h sumStyles),
  // and the lights' colours (physical mode, the light at each pixel's point) are scaled in both
  // tracers, with their grid, once no CPU bake reads them (stylesApplied() says when).
  std::vector<int> lightStyles() const;
  void setStyleScale(int style, float scale);
  float styleScale(int style) const;
  bool stylesApplied() const; // the lights carry the sliders' scales
  bool denoising() const;     // physical mode's young image is denoised (renderer/denoise_fade.h denoiseShare)
  void setLighting(LightingMode mode);
  // The level's compiled lightmaps as its engine shows them (key 6); false when it has none
  // (notice() says why and faithful lighting stays).
  bool showCompiled();
  // Key 7: the compiled view against faithful light as a heat map (render --lighting difference's
  // scale); false, as showCompiled, for a level without lightmaps.
  bool showDifference();
  const std::string& notice() const; // the last mode switch that could not be made, and why
  const std::string& note() const;   // a mode the viewer chose by itself, and why (empty: none)
  bool cpuTracer() const;            // the window shows the CPU tracer's image (cpuReason() says why)
  const std::string& cpuReason() const;
  // Writes <map>-NNN.png (tonemapped) and <map>-NNN.exr (linear, with AOV layers) into the
  // screenshot folder and returns the PNG's path; throws when they cannot be written. F12 calls
  // this and shows the path, or the error, in the overlay.
  std::filesystem::path screenshot();

  int samples() const;              // accumulated samples per pixel of the current view
  int reloads() const;              // successful reloads since the window opened
  int imports() const;              // imports started, the first one's included
  int bakes() const;                // faithful luxel bakes started, on either tracer
  int gpuBakes() const;             // ... of them on the GPU (the GL window's first converged picture)
  const PickedFace& picked() const; // the face a left click picked (the overlay's panel shows it)
  bool reloading() const;           // a save's import is running on its worker thread
  bool luxelsBaked() const;         // faithful mode's bake of the current level is done (true without one)
  int glDebugErrors() const;        // GL errors the driver's debug output reported (BT_GL_DEBUG=1)
  const std::string& error() const; // the last reload error, empty when the scene is current
  CameraPose camera() const;
  bool hasLevel() const; // false while a level broken at start-up waits for a fix
  ViewMode mode() const;
  LightingMode lighting() const;
  bool overlayShown() const;                    // F1 toggles it
  std::vector<OverlayMessage> messages() const; // what the overlay shows in colour now (screenshot, errors)
  std::vector<std::string> warnings() const;    // the import's warnings, as the overlay's panel lists them
  unsigned long x11Window() const;              // the X11 window, for tests that send it key events (0 elsewhere)

  // What the window shows, read back from the GPU: the tonemapped display image (RGBA8, rows
  // top to bottom) at its own size, before it is scaled to the window. For tests.
  struct DisplayImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
  };
  DisplayImage displayed() const;
  // The whole window as the next swap shows it (overlay and markers included), drawn again now.
  DisplayImage window();
  bool markersShown() const; // L toggles them

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace bt

// `brushtrace view`: the level in a window, path-traced progressively on the GPU, reloaded
// whenever a file the import read is saved (the map, prefabs, WADs, palettes, shader scripts,
// every texture image and companion map: Scene::inputFiles).
//
// Samples accumulate in one RGBA32F image on the GPU and a compute pass tonemaps it into the
// image the window draws, so nothing is read back per frame (gl_progressive.h).
// One Viewer is one window. frame() runs one iteration of the loop (events, camera, reload,
// one sample, tonemap, overlay, present), so tests drive it frame by frame under Xvfb.
#pragma once

#include "importers/import.h"
#include "renderer/camera.h"
#include "renderer/cpu/integrator.h"
#include "lighting/lightmap_bake.h"
#include "renderer/gl/gl_textures.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bt {

enum class ViewMode { Beauty, Albedo, Normal };

struct ViewerOptions {
  std::string map;
  ImportOptions import;
  int width = 1280;
  int height = 720;
  std::optional<CameraPose> camera; // default: the render command's default camera
  gl::TextureMode textures = gl::TextureMode::Auto;
  LightingMode lighting = LightingMode::Faithful;
  bool compiled = false; // --lighting compiled: a .bsp's own lightmaps (key 6), in faithful mode
  // --lighting given; without it a compiled Quake 3 level opens in the compiled view (q3map2
  // leaves no light entities in it, so faithful light would be black), with note() saying so.
  bool lightingGiven = false;
  int bounces = 3;
  std::filesystem::path screenshotDir = ".";
  int maxSamples = 4096;    // refinement stops here; the window stays responsive
  float exposureEv = 0.0f;  // as render's --exposure: on screen, in screenshots and in the EXR
  bool luxels = true;       // faithful mode: the compiler's luxels, baked on the GPU (render's --luxels)
  LightmapBakeOptions bake; // their --extra
};

class Viewer {
public:
  // Opens the window and loads the level. Throws on a level that cannot be imported or when
  // no window can be opened (the message says which).
  explicit Viewer(ViewerOptions options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // One iteration of the loop. Returns false once the window has been asked to close.
  bool frame();

  void setMode(ViewMode mode);
  void setLighting(LightingMode mode);
  // The level's compiled lightmaps as its engine shows them (key 6); false when it has none
  // (notice() says why and faithful lighting stays).
  bool showCompiled();
  // Key 7: the compiled view against faithful light as a heat map (render --lighting difference's
  // scale); false, as showCompiled, for a level without lightmaps.
  bool showDifference();
  const std::string& notice() const; // the last mode switch that could not be made, and why
  const std::string& note() const;   // a mode the viewer chose by itself, and why (empty: none)
  // Writes <map>-NNN.png (tonemapped) and <map>-NNN.exr (linear, with AOV layers) into the
  // screenshot folder and returns the PNG's path. F12 calls this.
  std::filesystem::path screenshot();

  int samples() const;              // accumulated samples per pixel of the current view
  int reloads() const;              // successful reloads since the window opened
  bool luxelsBaked() const;         // faithful mode's bake of the current level is done (true without one)
  int glDebugErrors() const;        // GL errors the driver's debug output reported (BT_GL_DEBUG=1)
  const std::string& error() const; // the last reload error, empty when the scene is current
  CameraPose camera() const;

  // What the window shows, read back from the GPU: the tonemapped display image (RGBA8, rows
  // top to bottom) at its own size, before it is scaled to the window. For tests.
  struct DisplayImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
  };
  DisplayImage displayed() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace bt

// `brushtrace view`: the level in a window, path-traced progressively on the GPU, reloaded
// whenever the map or a texture it uses is saved.
//
// One Viewer is one window. frame() runs one iteration of the loop (events, camera, reload,
// one sample, overlay, present), so tests drive it frame by frame under Xvfb.
#pragma once

#include "importers/import.h"
#include "renderer/cpu/camera.h"
#include "renderer/cpu/integrator.h"
#include "renderer/gl/gl_textures.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

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
  int bounces = 3;
  std::filesystem::path screenshotDir = ".";
  int maxSamples = 4096; // refinement stops here; the window stays responsive
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
  // Writes <map>-NNN.png (tonemapped) and <map>-NNN.exr (linear, with AOV layers) into the
  // screenshot folder and returns the PNG's path. F12 calls this.
  std::filesystem::path screenshot();

  int samples() const;         // accumulated samples per pixel of the current view
  int reloads() const;         // successful reloads since the window opened
  const std::string& error() const; // the last reload error, empty when the scene is current
  CameraPose camera() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace bt

// `render`'s options and its whole job, shared by the `render` command and `batch`'s renders.
#pragma once

#include "app/commands.h"
#include "renderer/camera.h"
#include "renderer/render.h"

#include <optional>
#include <string>
#include <vector>

namespace bt::app {

struct RenderOptions {
  std::string map;
  std::string output;
  int spp = 64; // 0: --time alone bounds the render
  double timeLimit = 0.0;
  ImageSize size{960, 540};
  std::optional<CameraPose> camera;
  std::string backend = "auto";
  std::string glTextures = "auto";
  std::string aov = "beauty";
  // --exposure EV; without it physical lighting is exposed automatically (renderer/exposure.h)
  // and faithful lighting at 0 EV, the game's own brightness.
  std::optional<float> exposure;
  bool denoise = false; // --denoise: the PNG shows the denoised beauty, the EXR gains its layer
  std::string tonemap;  // empty: faithful for --lighting faithful, aces for physical
  std::string lighting = "faithful";
  bool lightingGiven = false; // --lighting on the command line (a Quake 3 .bsp defaults to compiled)
  int bounces = 3;
  float clampIndirect = kClampIndirectDefault; // physical mode's firefly clamp, units (0: off)
  int threads = 0;
  uint32_t seed = 0;
  bool quiet = false;
  bool showHidden = false;
  std::string luxels = "on";
  int extra = 1;
  // --style N=SCALE: the lights of style N (1-255) times SCALE, as the viewer's style sliders show
  // them (LightOptions::styleScale); the luxels bake with them.
  std::vector<std::string> styles;
  ImportOptions import;
};

// What a finished render used, for callers that record it (batch's per-level results).
struct RenderOutcome {
  CameraPose pose;
  int samples = 0;
  std::string device;      // "cpu" or "gl <renderer>"
  float exposureEv = 0.0f; // the exposure the image was written with
};

// Imports o.map and renders it to o.output: 0 when the image was written, 1 when the level has
// nothing to draw. Throws on a level that cannot be imported or an image that cannot be written.
int runRender(const RenderOptions& o, RenderOutcome* outcome = nullptr);

} // namespace bt::app

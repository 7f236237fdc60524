// What a render asks for and what it gives back, the same for both tracers: the settings, the
// image with its AOVs, progress, and the 8-bit pixels an output file holds.
#pragma once

#include "lighting/visibility.h" // LightingMode
#include "renderer/tonemap.h"
#include "shaders/light_constants.glsl"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace bt {

struct IntegratorSettings {
  LightingMode mode = LightingMode::Faithful;
  int bounces = 3; // physical: indirect bounces after the first hit (faithful mode bounces as the
                   // level's `_bounce` asks, through bounce lights: bounce.h)
  // true: the light grid's lists (faithful) and one selected point light per hit (physical);
  // false: every light at every hit, the reference both converge to (tests, benchmarks).
  bool lightSelection = true;
  // Physical mode's pick of one point light per hit (with lightSelection): the light grid's near
  // lists (both tracers), or the light tree (lighting/light_tree.h, CPU only), measured noisier
  // on the shared levels and kept to measure against (tests, bench_light_selection).
  enum class PhysicalPick { NearList, Tree };
  PhysicalPick physicalPick = PhysicalPick::NearList;
  // Physical mode's firefly clamp (`--clamp-indirect`, lighting/README.md "Fireflies"): at every
  // surface a path meets after the camera's, a point light counts as at least this many units
  // away, so a wall a few units from a light does not light the floor it bounces to hundreds of
  // times brighter than the light's tuning intends. 0: off, the unbiased estimate (the default
  // here, for tests against references); the commands default to kClampIndirectDefault.
  float clampIndirect = 0.0f;
  // Physical mode's random numbers for its main decisions (the camera's subpixel, the light pick
  // and point, the emitter point, the BSDF's direction, roulette): the pixel's scrambled Sobol
  // sequence (lighting/sampling.h pixelSampler), fewer samples' noise than the PCG stream
  // (bench/README.md, issue 18 session 24); false: PCG for all, as before, to measure against.
  // The GL tracer has the Sobol sequence only.
  bool lowDiscrepancy = true;
};

inline constexpr float kClampIndirectDefault = BT_CLAMP_INDIRECT_DEFAULT;

struct RenderSettings {
  int width = 640;
  int height = 360;
  int spp = 64;           // samples per pixel (upper bound when timeLimit is set)
  double timeLimit = 0.0; // seconds; 0 = none. Stops after the pass that crosses it.
  int threads = 0;        // 0 = every hardware thread
  uint32_t seed = 0;
  IntegratorSettings integrator;
};

// A rendered frame. beauty is the mean linear radiance; the AOVs come from one ray through
// each pixel centre, so they are exact and deterministic.
struct RenderImage {
  int width = 0;
  int height = 0;
  int samples = 0;
  std::vector<glm::vec3> beauty;
  // The mean of the samples' squared Rec. 709 luminance per pixel (the second moment beside the
  // beauty's first), so that the denoiser knows each pixel's noise; empty where none was kept.
  std::vector<float> luminanceMoment2;
  std::vector<glm::vec3> albedo;   // linear base colour of the visible face
  std::vector<glm::vec3> normal;   // world-space face normal, 0 where nothing is hit
  std::vector<float> depth;        // distance along the ray, +inf where nothing is hit
  std::vector<uint32_t> face;      // scene face index + 1, 0 where nothing is hit
  std::vector<glm::vec3> denoised; // the beauty denoised (renderer/denoise.h), empty if not asked for
};

struct RenderProgress {
  int samplesDone = 0;
  int samplesTotal = 0; // spp, or 0 when only a time limit bounds the render
  double elapsed = 0.0;
  double estimatedRemaining = 0.0;
};

// Image outputs.
enum class Aov { Beauty, Albedo, Normal, Depth, Face };

struct OutputSettings {
  Aov aov = Aov::Beauty;
  float exposureEv = 0.0f;
  bool exposureAuto = false; // exposureEv was measured (renderer/exposure.h), not given; EXR metadata
  Tonemap tonemap = Tonemap::Faithful;
};

// The 8-bit sRGB pixels a PNG of `image` holds (RGB, rows top to bottom); the beauty AOV shows
// image.denoised where there is one.
std::vector<uint8_t> displayPixels(const RenderImage& image, const OutputSettings& output);

} // namespace bt

// The GL tracer's benchmark (`brushtrace bench`, and bench/gl_bench for machines that cannot
// carry the importers' image libraries): ray rates, full samples per second, time to first image.
#pragma once

#include "renderer/gl/gl_level.h"
#include "renderer/gl/gl_textures.h"
#include "renderer/render.h"
#include "scene/scene.h"

#include <functional>
#include <string>
#include <vector>

namespace bt::gl {

struct GlBenchSettings {
  int width = 1280;
  int height = 720;
  int bounces = 4;
  double seconds = 5.0; // time budget of the measurements
  TextureMode textures = TextureMode::Auto;
  bool physical = true; // lighting of the full samples
  // Measure only the time to converged (renderer/time_to_converged.h), against a render of
  // this many spp: physical light, denoiser off and on.
  bool timeToConverged = false;
  int referenceSpp = 4096;
  // Measure only the ray rates after the cold first image (with the level's curves and, where it
  // has any, without them).
  bool raysOnly = false;
  // Physical mode's firefly clamp (IntegratorSettings::clampIndirect), the commands' default.
  float clampIndirect = kClampIndirectDefault;
  // With timeToConverged: also the measure's floor, two references' difference (ConvergeRun).
  bool referenceFloor = false;
  // With timeToConverged: given each image the measure renders (ConvergeRun::keep), e.g. to write
  // it as an EXR (gl_bench's `dump DIR`), which this library does not link.
  std::function<void(const RenderImage&, const std::string& name)> keep;
  // With raysOnly: the rays timed with a variant of the benchmark's program (issue 20's
  // measurements of parts of the walk; gl_tracer.h RayBenchVariant). Last, as `brushtrace bench`
  // fills the fields above in order.
  std::vector<std::string> rayBenchDefines;
  std::string rayBenchBinary;
};

// Prints the measurements to stdout; a level with Quake 3 curves gets its ray rates a second
// time with the curves left out (issue 16: with its curves at >= 80 % of that rate per ray); returns the exit status (1 if GL reported errors).
// `importLevel` imports the level: it is timed as part of the first image, which is measured
// the way `brushtrace render` gets there (gl::LevelPreparation and gl::loadGlLevel: the import
// started, the context, the path tracer's compile started once the lights are read, the
// preparation, upload, the compile's end, one sample).
int runGlBench(const LevelImport& importLevel, const GlBenchSettings& settings);

} // namespace bt::gl

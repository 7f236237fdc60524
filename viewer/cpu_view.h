// The viewer's image where the window has no hardware GL (Mesa's llvmpipe: the CPU tracer is
// several times faster than compute shaders emulated on the CPU; or --backend cpu): the CPU
// tracer's progressive image, a band of rows at a time so that a frame stays near its budget
// (~100 ms) however large the window, input and reloads served in between.
//
// Each pixel sums its samples in index order in double, drawing pixelRng's stream n for its
// sample n, as renderCpu does: after n full passes the image is render --backend cpu's at n spp.
#pragma once

#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "renderer/camera.h"
#include "renderer/render.h"

#include <array>
#include <chrono>
#include <future>
#include <memory>
#include <span>
#include <vector>

namespace bt {

class CpuProgressive {
public:
  CpuProgressive(int width, int height);

  // Starts over for a new view (camera, lighting, level).
  void restart();
  // Traces rows of the current pass, a band at a time on every core, until the next band would end
  // past `budget` (one band at least) or `maxSamples` full passes are done. Returns the pixel
  // samples traced.
  size_t refine(const RenderScene& scene, const Camera& camera, const IntegratorSettings& integrator, std::chrono::duration<double> budget,
                int maxSamples);

  int samples() const { return passes_; } // full passes
  int width() const { return width_; }
  int height() const { return height_; }
  // The mean of each pixel's samples and of their squared luminance (its row's count: rows of the
  // current pass have one more), black where none yet.
  RenderImage mean() const;

private:
  int width_, height_;
  std::vector<glm::dvec3> sum_;
  std::vector<double> moment2_; // each sample's luminance squared: the denoiser's variance
  std::vector<int> rowSamples_;
  int passes_ = 0;
  int nextRow_ = 0;            // of the current pass
  double secondsPerRow_ = 0.0; // the last band's, to size the next
};

// Faithful mode's luxels for the CPU window: every lit face of the level laid out and baked on a
// worker thread (the level is read only meanwhile), taken into the RenderScene between frames.
// `styled` (a level with lights of styles other than 0, in either window): one luxel set per
// style (lightmap_bake.h bakeStyledLuxels), which the style sliders re-sum without a bake.
class CpuLuxelBake {
public:
  CpuLuxelBake(const RenderScene& scene, LightmapBakeOptions options, bool styled = false);
  ~CpuLuxelBake(); // waits for the worker
  // Moves the baked luxels into scene.lightmaps once they are ready; true then (once). A styled
  // bake's luxels are its sets summed with `styleWeights`, and its sets move into `styled`.
  bool takeInto(RenderScene& scene, std::span<const float, 256> styleWeights = kUnitStyleWeights, StyledLuxels* styled = nullptr);
  bool done() const { return taken_; }
  bool ready() const; // the worker has finished
  // Keeps `level` (what the bake reads) alive until this bake is destroyed: a reload replaces a
  // level whose bake still runs without waiting for it (there is no stopping it halfway).
  void holdUntilDone(std::shared_ptr<const void> level) { level_ = std::move(level); }

  // Every style at its compiled weight (1).
  static constexpr std::array<float, 256> kUnitStyleWeights = [] {
    std::array<float, 256> all{};
    for (float& w : all) w = 1.0f;
    return all;
  }();

private:
  struct Baked {
    Lightmaps lightmaps;
    StyledLuxels styled; // empty unless styled
  };
  std::shared_ptr<const void> level_; // destroyed after the destructor has waited for the worker
  std::future<Baked> baking_;
  bool taken_ = false;
};

} // namespace bt

// Faithful mode's light compiler on the GPU (shaders/bake.comp): the CPU reference's bake
// (lighting/lightmap_bake.h bakeLightmaps), pass by pass, into the tracer's lightmap buffer,
// so the path tracer shows the luxels as they sharpen. The CPU finds the sample points
// (LuxelBakeJob); the GPU lights them.
#pragma once

#include "lighting/lightmap_bake.h"
#include "renderer/gl/gl_tracer.h"

#include <future>
#include <memory>

namespace bt::gl {

class GlLightmapBake {
public:
  // `tracer` holds the job's layout already (GlLighting::lightmaps, or setLightmaps with
  // packLightmaps of it); its luxels are overwritten. The tracer's context must be current.
  GlLightmapBake(GlTracer& tracer, const LuxelBakeJob& job);
  ~GlLightmapBake();
  GlLightmapBake(const GlLightmapBake&) = delete;
  GlLightmapBake& operator=(const GlLightmapBake&) = delete;

  // Runs up to `passes` more passes over every sample, then stores the luxels they give so far.
  // The first run computes the lights' visapprox boxes first where the job leaves them to the GPU.
  void run(int passes);
  // The lights' visapprox boxes as the bake reads them (LuxelBakeJob::lightBoxes' order), computed
  // now where they were not yet; waits for the GPU. For tests and benchmarks.
  std::vector<GpuVisBox> lightBoxes();
  // Every pass at once, then waits for the GPU.
  void finish();
  int passesDone() const { return done_; }
  bool done() const { return done_ >= passes_; }

private:
  void dispatch(int firstPass, int passCount, uint32_t items);
  void bind();
  // shaders/bake.comp visBoxPass over the boxes still to compute, one workgroup each.
  void computeLightBoxes();

  GlTracer& tracer_;
  FaithfulFeatures features_;
  unsigned samples_ = 0, sums_ = 0, dome_ = 0;
  uint32_t sampleCount_ = 0, luxelCount_ = 0, samplesPerLuxel_ = 1;
  int softSamples_ = 1, passes_ = 1, done_ = 0;
  int domeSuns_ = 0;            // the dome's directions, before the penumbra suns' in the same buffer
  int lightBoxes_ = 0;          // where the lights' visapprox boxes begin in that buffer (vec4 rows)
  int receiverBoxes_ = -1;      // where the compiled faces' begin; -1: the level culls no light
  int visRays_ = 0;             // where the visapprox rays' directions begin, where the GPU computes the lights' boxes
  uint32_t boxesToCompute_ = 0; // the lights' boxes the GPU has yet to compute (their rows hold the lights' origins)
  uint32_t lightBoxCount_ = 0;
  uint32_t seed_ = 0;
};

// A whole level's bake for an interactive front end (the viewer): the CPU's layout and sample
// points on a worker thread, so the first frames come at once (lit at each pixel's point), then
// the GPU's passes a few each frame, the luxels sharpening as they come.
class ProgressiveLevelBake {
public:
  // Starts the worker on `rs`, which must outlive this object and stay unchanged.
  ProgressiveLevelBake(const RenderScene& rs, LightmapBakeOptions options = {});
  ~ProgressiveLevelBake(); // waits for the worker
  ProgressiveLevelBake(const ProgressiveLevelBake&) = delete;
  ProgressiveLevelBake& operator=(const ProgressiveLevelBake&) = delete;

  // One frame's share, about `milliseconds` of GPU work (at least one pass): once the worker is
  // done, uploads the layout into `tracer` and runs passes. True when the luxels `tracer` shows
  // changed, so the caller restarts its accumulation.
  bool step(GlTracer& tracer, double milliseconds);
  bool done() const { return bake_ && bake_->done(); }
  int passesDone() const { return bake_ ? bake_->passesDone() : 0; }
  int passes() const { return passes_; }

private:
  struct Work {
    Lightmaps layout;
    LuxelBakeJob job;
  };
  std::future<Work> worker_;
  std::unique_ptr<GlLightmapBake> bake_;
  int passes_ = 0;
};

} // namespace bt::gl

#include "renderer/gl/gl_level.h"

#include "renderer/gl/gl_lighting.h"

#include <optional>

namespace bt::gl {

LevelPreparation::LevelPreparation(Scene& scene, RenderScene& render, LevelImport importLevel, RenderSceneOptions options,
                                   Diagnostics* lightDiagnostics)
    : kinds_(kindsPromise_.get_future().share()) {
  done_ = std::async(std::launch::async, [this, &scene, &render, importLevel = std::move(importLevel),
                                          options = std::move(options), lightDiagnostics] {
    std::optional<SceneLights> lights;
    Diagnostics collectDiagnostics;
    // The lights need the entities only, so they are collected as soon as the importer has them.
    auto collect = [&](const Scene& read) {
      if (lights) return;
      lights = collectLights(read, options.lights, collectDiagnostics);
      lightsCollected = Clock::now();
      kindsPromise_.set_value(bt::lightKinds(*lights, options.bounceLights));
    };
    try {
      started = Clock::now();
      scene = importLevel(collect);
      collect(scene); // an importer that did not say when it had the entities
      Diagnostics& diagnostics = lightDiagnostics ? *lightDiagnostics : scene.diagnostics;
      diagnostics.insert(diagnostics.end(), collectDiagnostics.begin(), collectDiagnostics.end());
      render = buildRenderScene(scene, std::move(*lights), options, diagnostics);
      prepared = Clock::now();
    } catch (...) {
      if (!lights) kindsPromise_.set_exception(std::current_exception());
      throw;
    }
  });
}

// std::async's future joins the worker in its destructor; an exception nobody asked for is dropped.
LevelPreparation::~LevelPreparation() = default;

LightKinds LevelPreparation::lightKinds() { return kinds_.get(); }

void LevelPreparation::wait() {
  if (done_.valid()) done_.get();
}

std::unique_ptr<LevelPreparation> prepareGlLevel(GlLevel& level, LevelImport importLevel) {
  return std::make_unique<LevelPreparation>(level.scene, level.render, std::move(importLevel));
}

void loadGlLevel(GlLevel& level, LevelPreparation& preparation, GlContext& context,
                 const std::shared_ptr<TracerPrograms>& programs, bool physical, GlLevelTimes* times) {
  using Clock = GlLevelTimes::Clock;
  GlLevelTimes local;
  GlLevelTimes& t = times ? *times : local;
  programs->startTraceKernel();
  // Physical programs have every part; a faithful one waits for the lights to know its parts.
  const FaithfulFeatures features = physical ? FaithfulFeatures{} : faithfulFeatures(preparation.lightKinds());
  programs->startPathTracer(physical, features);
  t.programsStarted = Clock::now();
  const bool wavefront = programs->wavefrontState(physical, features).started;
  if (wavefront) {
    programs->wavefrontTrace();
    t.traceLinked = Clock::now();
  }
  preparation.wait();
  t.lightsCollected = preparation.lightsCollected;
  t.prepared = preparation.prepared;
  // The upload goes between the two waits: the trace kernel links well before the shade kernel,
  // and the preparation is done by then, so the upload costs the first image nothing (H100,
  // lq_e4m3, cold: 10 ms less than uploading after both waits, the shade kernel's link no later).
  t.uploadStarted = Clock::now();
  level.tracer = std::make_unique<GlTracer>(context, level.scene, level.render.tracer, programs, lightingFor(level.render));
  t.uploaded = Clock::now();
  if (wavefront) programs->wavefront(physical, features);
  t.shadeLinked = Clock::now();
  if (!wavefront) t.traceLinked = t.shadeLinked;
}

void loadGlLevel(GlLevel& level, GlContext& context, const std::shared_ptr<TracerPrograms>& programs, bool physical,
                 const LevelImport& importLevel, GlLevelTimes* times) {
  const std::unique_ptr<LevelPreparation> preparation = prepareGlLevel(level, importLevel);
  loadGlLevel(level, *preparation, context, programs, physical, times);
}

} // namespace bt::gl

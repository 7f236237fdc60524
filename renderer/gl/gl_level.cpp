#include "renderer/gl/gl_level.h"

#include "renderer/gl/gl_lighting.h"

namespace bt::gl {

LevelPreparation::LevelPreparation(Scene& scene, RenderScene& render, LevelImport importLevel, RenderSceneOptions options,
                                   Diagnostics* lightDiagnostics)
    : told_(toldPromise_.get_future().share()) {
  done_ = std::async(std::launch::async,
                     [this, &scene, &render, importLevel = std::move(importLevel), options = std::move(options), lightDiagnostics] {
                       bool kindsSet = false;
                       // The kinds need the entities, the parts the faces, so they are told before the textures are
                       // loaded. The lights are collected again from the finished scene, which may have more keys.
                       auto tell = [&](const Scene& read) {
                         if (kindsSet) return;
                         Diagnostics ignored; // the collection below reports them
                         const LightKinds kinds = bt::lightKinds(read, collectLights(read, options.lights, ignored), options.bounceLights);
                         const LevelParts parts = bt::levelParts(read, options);
                         lightsCollected = Clock::now();
                         toldPromise_.set_value({kinds, parts});
                         kindsSet = true;
                       };
                       try {
                         started = Clock::now();
                         scene = importLevel(tell);
                         tell(scene); // an importer that did not say when it had the entities
                         Diagnostics& diagnostics = lightDiagnostics ? *lightDiagnostics : scene.diagnostics;
                         render = buildRenderScene(scene, options, diagnostics);
                         prepared = Clock::now();
                       } catch (...) {
                         if (!kindsSet) toldPromise_.set_exception(std::current_exception());
                         throw;
                       }
                     });
}

// std::async's future joins the worker in its destructor; an exception nobody asked for is dropped.
LevelPreparation::~LevelPreparation() = default;

LightKinds LevelPreparation::lightKinds() {
  return told_.get().kinds;
}

LevelParts LevelPreparation::levelParts() {
  return told_.get().parts;
}

void LevelPreparation::wait() {
  if (done_.valid()) done_.get();
}

bool LevelPreparation::ready() const {
  return !done_.valid() || done_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

bool LevelPreparation::kindsKnown() const {
  return told_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

RenderSceneOptions glSceneOptions() {
  RenderSceneOptions options;
  options.visApproxBoxes = RenderSceneOptions::VisBoxes::Gpu;
  return options;
}

std::unique_ptr<LevelPreparation> prepareGlLevel(GlLevel& level, LevelImport importLevel, RenderSceneOptions options) {
  return std::make_unique<LevelPreparation>(level.scene, level.render, std::move(importLevel), std::move(options));
}

FaithfulFeatures startPathTracerFor(TracerPrograms& programs, LevelPreparation& preparation, bool physical, bool luxels) {
  // A compile's start costs this thread the driver's calls (bench/README.md, first14h): the trace
  // kernel's fills a wait for the lights, or else follows the shade kernel's (startPathTracer).
  if (!preparation.kindsKnown()) programs.startTraceKernel();
  // Only a level whose finished lights need a part their early kinds did not tell builds its own
  // program once prepared (loadGlLevel), the one started here going unused.
  const LevelParts parts = preparation.levelParts();
  FaithfulFeatures features = physical ? FaithfulFeatures{.liquidCsg = parts.liquidCsg} : faithfulFeatures(preparation.lightKinds(), parts);
  features.luxels = luxels && !physical;
  programs.startPathTracer(physical, features);
  return features;
}

void loadGlLevel(GlLevel& level, LevelPreparation& preparation, GlContext& context, const std::shared_ptr<TracerPrograms>& programs,
                 bool physical, GlLevelTimes* times) {
  using Clock = GlLevelTimes::Clock;
  GlLevelTimes local;
  GlLevelTimes& t = times ? *times : local;
  const FaithfulFeatures early = startPathTracerFor(*programs, preparation, physical);
  t.programsStarted = Clock::now();
  if (programs->wavefrontState(physical, early).started) {
    programs->wavefrontTrace();
    t.traceLinked = Clock::now();
  }
  preparation.wait();
  t.lightsCollected = preparation.lightsCollected;
  t.prepared = preparation.prepared;
  t.uploadStarted = Clock::now();
  const GlLighting lighting = lightingFor(level.render);
  // Should the prepared level need a part its early kinds and parts did not tell, its own program
  // starts now, before the upload, so that the first image does not wait for it to start after
  // the upload (then the early one goes unused).
  const FaithfulFeatures features = faithfulFeatures(lighting);
  programs->startPathTracer(physical, features);
  const bool wavefront = programs->wavefrontState(physical, features).started;
  // The upload goes between the two waits: the trace kernel links well before the shade kernel,
  // and the preparation is done by then, so the upload costs the first image nothing.
  level.tracer = std::make_unique<GlTracer>(context, level.scene, level.render.tracer, programs, lighting);
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

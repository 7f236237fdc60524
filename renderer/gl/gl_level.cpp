#include "renderer/gl/gl_level.h"

#include "renderer/gl/gl_lighting.h"

#include <future>

namespace bt::gl {

void loadGlLevel(GlLevel& level, GlContext& context, const std::shared_ptr<TracerPrograms>& programs, bool physical,
                 const std::function<Scene()>& importLevel, GlLevelTimes* times) {
  using Clock = GlLevelTimes::Clock;
  GlLevelTimes local;
  GlLevelTimes& t = times ? *times : local;
  auto imported = std::async(std::launch::async, [&] {
    t.importStarted = Clock::now();
    level.scene = importLevel();
    level.render = buildRenderScene(level.scene, {}, level.scene.diagnostics);
    t.imported = Clock::now();
  });
  // The future's destructor joins the worker if a wait below throws; its own exception is then
  // lost to the compile error, which is the one the caller can do nothing about.
  if (programs->wavefrontState(physical).started) {
    programs->wavefrontTrace();
    t.traceLinked = Clock::now();
    programs->wavefront(physical);
    t.shadeLinked = Clock::now();
  }
  imported.get();
  t.uploadStarted = Clock::now();
  if (!programs->wavefrontState(physical).started) t.traceLinked = t.shadeLinked = t.uploadStarted;
  level.tracer = std::make_unique<GlTracer>(context, level.scene, level.render.tracer, programs, lightingFor(level.render));
  t.uploaded = Clock::now();
}

} // namespace bt::gl

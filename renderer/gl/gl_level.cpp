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
  const bool wavefront = programs->wavefrontState(physical).started;
  if (wavefront) {
    programs->wavefrontTrace();
    t.traceLinked = Clock::now();
  }
  imported.get();
  // The upload goes between the two waits: the trace kernel links well before the shade kernel,
  // and the import is done by then, so the upload costs the first image nothing (H100, lq_e4m3,
  // cold: 10 ms less than uploading after both waits, the shade kernel's link no later).
  t.uploadStarted = Clock::now();
  level.tracer = std::make_unique<GlTracer>(context, level.scene, level.render.tracer, programs, lightingFor(level.render));
  t.uploaded = Clock::now();
  if (wavefront) programs->wavefront(physical);
  t.shadeLinked = Clock::now();
  if (!wavefront) t.traceLinked = t.shadeLinked;
}

} // namespace bt::gl

// A level loaded for the GL tracer the way every front end gets to its first image: the level
// imported and prepared on a worker thread, started before the GL context exists; the path
// tracer's compile started as soon as the level's lights and parts say which program it needs;
// then the upload.
#pragma once

#include "lighting/render_scene.h"
#include "renderer/gl/gl_tracer.h"
#include "scene/scene.h"

#include <chrono>
#include <functional>
#include <future>
#include <memory>

namespace bt::gl {

// A level's import: importScene() with ImportOptions::entitiesRead set to the given callback,
// which the importer calls once its entities, brushes and faces are read, before it loads the
// textures. (A
// function, so that this library needs no importer: the GPU check links the portable one.)
using EntitiesRead = std::function<void(const Scene&)>;
using LevelImport = std::function<Scene(const EntitiesRead&)>;

// A level's import and preparation on a worker thread: importLevel(), lighting/render_scene.h's
// collectLights() and buildRenderScene(), into `scene` and `render` (render.scene points at
// scene), with the preparation's diagnostics into `lightDiagnostics` (null: scene.diagnostics).
// Those three belong to the worker until wait() returns. The level's lights are collected and
// its parts found as soon as its entities and faces are read, so its LightKinds and LevelParts
// are known well before the rest (a fraction of the textured import and the preparation;
// seconds before them on a `_bounce` level): a front end starts the GL program for them
// meanwhile. Exceptions of the import or the preparation reach lightKinds(), levelParts() and wait().
class LevelPreparation {
public:
  using Clock = std::chrono::steady_clock;
  LevelPreparation(Scene& scene, RenderScene& render, LevelImport importLevel, RenderSceneOptions options = {},
                   Diagnostics* lightDiagnostics = nullptr);
  ~LevelPreparation(); // waits for the worker
  LevelPreparation(const LevelPreparation&) = delete;
  LevelPreparation& operator=(const LevelPreparation&) = delete;

  // Block until the lights are collected and the parts found.
  LightKinds lightKinds();
  LevelParts levelParts();
  // Blocks until the preparation is done; then scene and render are the caller's again.
  void wait();
  // Whether wait() would return at once (the viewer's reload polls it between frames).
  bool ready() const;
  // Whether lightKinds() and levelParts() would return at once.
  bool kindsKnown() const;

  Clock::time_point started, lightsCollected, prepared; // the worker's steps, for timelines

private:
  struct Told {
    LightKinds kinds;
    LevelParts parts;
  };
  std::promise<Told> toldPromise_;
  std::shared_future<Told> told_;
  std::future<void> done_;
};

// The level, what the tracers need of it (render.scene points at scene, so a GlLevel stays
// where it was made), and its GPU buffers.
struct GlLevel {
  Scene scene;
  RenderScene render;
  std::unique_ptr<GlTracer> tracer;
};

// When each step of loadGlLevel() ended, for `brushtrace bench`'s first-image timeline.
struct GlLevelTimes {
  using Clock = std::chrono::steady_clock;
  Clock::time_point contextMade;               // the caller's, where it wants it in the timeline
  Clock::time_point lightsCollected, prepared; // the preparation's (LevelPreparation)
  Clock::time_point programsStarted;           // the path tracer's programs queued for the level's lights and parts
  Clock::time_point traceLinked, shadeLinked;  // both at the upload's end where none was started
  Clock::time_point uploadStarted, uploaded;
};

// The preparation of a level for the GL tracer: RenderSceneOptions' defaults, but the visapprox
// boxes left to the GL bake (VisBoxes::Gpu), off the first image's path.
RenderSceneOptions glSceneOptions();

// Starts a LevelPreparation of `importLevel` into `level` (with `options`, the preparation's
// diagnostics into the scene's). Start it before the GL context: the import then
// overlaps the context's creation.
std::unique_ptr<LevelPreparation> prepareGlLevel(GlLevel& level, LevelImport importLevel, RenderSceneOptions options = glSceneOptions());

// Starts `programs`' path tracer for `physical` lighting (the first images') and the level's
// kinds of light and parts, once the preparation knows them (a physical program has every part
// but the liquid CSG). The wavefront trace kernel needs nothing of the level: it is started while
// the preparation is still collecting the lights, else after the shade kernel, whose compile the
// first image waits for. `luxels`: whether the first images will show baked faces
// (FaithfulFeatures::luxels; a front end that bakes before them); loadGlLevel() tells it from the
// prepared level's lightmaps. The faithful features it was started with.
FaithfulFeatures startPathTracerFor(TracerPrograms& programs, LevelPreparation& preparation, bool physical, bool luxels = false);

// Finishes loading `level`, whose preparation is `preparation`: starts the path tracer
// (startPathTracerFor), then waits for the wavefront kernels where they were started. NVIDIA's
// driver does part of a compile on the thread that waits for it, so the first image comes
// sooner with the import on another thread than before the wait (bench/README.md). The upload needs this thread's GL context; it runs between the trace kernel's link
// and the shade kernel's. Exceptions of the preparation or the compile reach the caller.
void loadGlLevel(GlLevel& level, LevelPreparation& preparation, GlContext& context, const std::shared_ptr<TracerPrograms>& programs,
                 bool physical, GlLevelTimes* times = nullptr);
// Both, for a caller that has its context already (the viewer's reloads).
void loadGlLevel(GlLevel& level, GlContext& context, const std::shared_ptr<TracerPrograms>& programs, bool physical,
                 const LevelImport& importLevel, GlLevelTimes* times = nullptr);

} // namespace bt::gl

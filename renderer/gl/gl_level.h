// A level loaded for the GL tracer the way every front end gets to its first image: the level
// imported on a worker thread while the path tracer compiles, then uploaded.
#pragma once

#include "renderer/cpu/render_scene.h"
#include "renderer/gl/gl_tracer.h"
#include "scene/scene.h"

#include <chrono>
#include <functional>
#include <memory>

namespace bt::gl {

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
  Clock::time_point traceLinked, shadeLinked; // both at the upload's end where none was started
  Clock::time_point importStarted, imported;  // import and buildRenderScene (the worker thread)
  Clock::time_point uploadStarted, uploaded;
};

// Fills `level`: importLevel() and buildRenderScene() (diagnostics into the scene's) run on a
// worker thread while this one waits for the wavefront kernels where startPathTracer() started
// them for the first images (`physical`: the lighting they are for). NVIDIA's driver does part
// of a compile on the thread that waits for it (H100, lq_e4m3, faithful, cold: the first image
// 0.49-0.83 s this way, 0.86-1.2 s with the import on this thread before the wait). The upload
// needs this thread's GL context; it runs between the trace kernel's link and the shade
// kernel's. Exceptions of the import or the compile reach the caller, with the worker joined.
void loadGlLevel(GlLevel& level, GlContext& context, const std::shared_ptr<TracerPrograms>& programs, bool physical,
                 const std::function<Scene()>& importLevel, GlLevelTimes* times = nullptr);

} // namespace bt::gl

#include "renderer/gl/gl_render.h"

#include "renderer/gl/gl_bake.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_lighting.h"

#include <chrono>
#include <limits>

namespace bt::gl {

CameraBasis cameraFrom(const CameraPose& pose, int width, int height) {
  return CameraBasis::fromQuakeAngles(pose.origin, pose.pitch, pose.yaw, pose.roll, width, height);
}

std::optional<GlRenderResult> renderWithGl(const RenderScene& scene, const CameraPose& pose, const RenderSettings& settings,
                                           TextureMode textures, const std::function<void(const RenderProgress&)>& progress,
                                           std::string& whyNot, GlRenderParts parts) {
  std::unique_ptr<GlContext> context;
  try {
    context = GlContext::createHeadless();
  } catch (const GlError& e) {
    whyNot = e.what();
    return std::nullopt;
  }
  return renderWithGl(*context, scene, pose, settings, textures, progress, parts);
}

GlRenderResult renderWithGl(GlContext& context, const RenderScene& scene, const CameraPose& pose, const RenderSettings& settings,
                            TextureMode textures, const std::function<void(const RenderProgress&)>& progress, GlRenderParts parts) {
  return renderWithGl(context, scene, pose, settings, std::make_shared<TracerPrograms>(context, textures), progress, parts);
}

GlRenderResult renderWithGl(GlContext& context, const RenderScene& scene, const CameraPose& pose, const RenderSettings& settings,
                            std::shared_ptr<TracerPrograms> programs, const std::function<void(const RenderProgress&)>& progress,
                            GlRenderParts parts, const LuxelBakeJob* bake) {
  GlTracer tracer(context, *scene.scene, scene.tracer, std::move(programs), lightingFor(scene));
  if (bake && parts != GlRenderParts::AovsOnly) GlLightmapBake(tracer, *bake).finish();
  const CameraBasis camera = cameraFrom(pose, settings.width, settings.height);

  GlRenderResult result;
  result.device = context.info().renderer;
  result.textures = tracer.textureMode();
  RenderImage& image = result.image;
  image.width = settings.width;
  image.height = settings.height;

  const AovImages aov = tracer.renderAovs(camera, settings.width, settings.height);
  const size_t n = aov.face.size();
  image.albedo.resize(n);
  for (size_t i = 0; i < n; ++i) image.albedo[i] = glm::vec3(aov.albedo[i]);
  image.normal = aov.normal;
  image.depth = aov.depth;
  image.face = aov.face;
  if (parts == GlRenderParts::AovsOnly) return result;

  BeautySettings beauty;
  beauty.width = settings.width;
  beauty.height = settings.height;
  beauty.spp = settings.spp > 0 ? settings.spp : std::numeric_limits<int>::max();
  beauty.seed = settings.seed;
  beauty.physical = settings.integrator.mode == LightingMode::Physical;
  beauty.bounces = settings.integrator.bounces;
  beauty.clampIndirect = settings.integrator.clampIndirect;
  const auto start = std::chrono::steady_clock::now();
  const BeautyImage b = tracer.renderBeauty(camera, beauty, [&](int done) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress) {
      RenderProgress p;
      p.samplesDone = done;
      p.samplesTotal = settings.spp;
      p.elapsed = elapsed;
      p.estimatedRemaining = settings.spp > 0 ? elapsed / done * (settings.spp - done) : 0.0;
      if (settings.timeLimit > 0.0) p.estimatedRemaining = std::min(p.estimatedRemaining, std::max(0.0, settings.timeLimit - elapsed));
      progress(p);
    }
    return !(settings.timeLimit > 0.0 && elapsed >= settings.timeLimit);
  });
  image.samples = b.samples;
  image.beauty = b.beauty;
  image.luminanceMoment2 = b.luminanceMoment2;
  return result;
}

} // namespace bt::gl

// The GL backend of `brushtrace render`: the same inputs and output as renderCpu
// (renderer/render.h), rendered by the GL compute tracer.
#pragma once

#include "renderer/camera.h"
#include "renderer/render.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_textures.h"
#include "renderer/gl/gl_tracer.h"

#include <functional>
#include <optional>
#include <string>

namespace bt::gl {

// The pinhole camera of renderer/camera.h's Camera for a pose and image size.
CameraBasis cameraFrom(const CameraPose& pose, int width, int height);

struct GlRenderResult {
  RenderImage image;
  std::string device;   // GL_RENDERER
  TextureMode textures; // the path used
};

// What renderWithGl renders. The AOVs alone need no path tracer: on llvmpipe its build is
// most of an AOV render's time, so `render --aov albedo` to a PNG (which shows only the AOV)
// skips it.
enum class GlRenderParts { BeautyAndAovs, AovsOnly };

// Renders like renderCpu: AOVs from one ray through each pixel centre, beauty as the mean of
// settings.spp samples (or as many as settings.timeLimit allows); with AovsOnly, the AOVs alone
// (image.beauty empty, image.samples 0, progress never called). Returns std::nullopt with
// `whyNot` set to one line when no GL 4.5 context can be made, so the caller can fall back to
// the CPU; other GL failures throw GlError.
std::optional<GlRenderResult> renderWithGl(const RenderScene& scene, const CameraPose& pose, const RenderSettings& settings,
                                           TextureMode textures, const std::function<void(const RenderProgress&)>& progress,
                                           std::string& whyNot, GlRenderParts parts = GlRenderParts::BeautyAndAovs);

// The same on a context the caller made (`render` makes one first to choose its backend) ...
GlRenderResult renderWithGl(GlContext& context, const RenderScene& scene, const CameraPose& pose, const RenderSettings& settings,
                            TextureMode textures, const std::function<void(const RenderProgress&)>& progress,
                            GlRenderParts parts = GlRenderParts::BeautyAndAovs);
// ... and with programs it started building before it imported the level. With `bake`, faithful
// mode's luxels of scene.lightmaps (laid out, not lit) are baked on the GPU first (gl_bake.h).
GlRenderResult renderWithGl(GlContext& context, const RenderScene& scene, const CameraPose& pose, const RenderSettings& settings,
                            std::shared_ptr<TracerPrograms> programs, const std::function<void(const RenderProgress&)>& progress,
                            GlRenderParts parts = GlRenderParts::BeautyAndAovs, const LuxelBakeJob* bake = nullptr);

} // namespace bt::gl

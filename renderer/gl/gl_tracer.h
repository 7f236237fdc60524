// The GL compute tracer: a Scene uploaded once, images rendered from a camera.
#pragma once

#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_textures.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace bt::gl {

// A pinhole camera as the shaders take it. right and up are scaled by tan(fov / 2) along
// their axis: the ray through pixel centre (x, y) of a w by h image, y counted from the top,
// is forward + (2 (x + 0.5) / w - 1) right + (1 - 2 (y + 0.5) / h) up, normalised.
struct CameraBasis {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{1.0f, 0.0f, 0.0f};
  glm::vec3 right{0.0f, -1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
};

// Per pixel, rows top to bottom, with the CPU reference's meanings (renderer/cpu RenderImage).
// A pixel that sees nothing has albedo 0, normal 0, depth +infinity and face kNoFace.
struct AovImages {
  static constexpr uint32_t kNoFace = 0;
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> albedo; // linear rgb, a = 1 where something was hit
  std::vector<glm::vec3> normal; // world-space geometric normal (the face plane's)
  std::vector<float> depth;      // distance along the ray
  std::vector<uint32_t> face;    // index into Scene::faces + 1
};

class GlTracer {
public:
  // Uploads the scene. The context must stay current on this thread for the tracer's life.
  GlTracer(GlContext& context, const Scene& scene, TextureMode textures);
  ~GlTracer();
  GlTracer(const GlTracer&) = delete;
  GlTracer& operator=(const GlTracer&) = delete;

  TextureMode textureMode() const; // the path in use: Bindless or Arrays

  AovImages renderAovs(const CameraBasis& camera, int width, int height);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace bt::gl

// Material textures on the GPU, in one of two layouts chosen at run time:
//   bindless (GL_ARB_bindless_texture): one GL_TEXTURE_2D per material map, made resident once,
//     its 64-bit handle written into GlMaterial;
//   arrays (llvmpipe and any context without bindless): one GL_TEXTURE_2D_ARRAY per size class,
//     GlMaterial naming (array, layer). Past kMaxTextureArrays sizes, classes are merged and a
//     map sits in the corner of a larger layer; the shaders wrap it at its own size
//     (GlMaterial::baseTexels...), so both paths still give one image.
// The tracer samples neither through the sampler: shaders/textures.glsl fetches the four texels
// of level 0 and filters them bilinearly in fp32, as the CPU reference does (bvh/trace_scene.h
// sampleBilinearRepeat), so that the GL AOVs equal the CPU's. Mipmaps and anisotropy are not needed
// for antialiasing either: each progressive sample is jittered over its pixel, so their mean
// integrates the texture over the pixel's footprint. Both paths still carry mipmaps and the
// driver's anisotropy up to 16x with the same filters and GL_REPEAT, for any later sampler
// lookup (textureGrad); no shader makes one today.
#pragma once

#include "renderer/gl/gl_structs.h"
#include "scene/scene.h"

#include <optional>
#include <string_view>
#include <vector>

namespace bt::gl {

struct GlContextInfo;

enum class TextureMode { Auto, Bindless, Arrays };
const char* toString(TextureMode mode);
std::optional<TextureMode> parseTextureMode(std::string_view name); // "auto", "bindless", "arrays"
// The path `mode` means on `context`: Auto is bindless where the context has it, else arrays.
// Throws GlError for Bindless on a context without GL_ARB_bindless_texture.
TextureMode resolveTextureMode(TextureMode mode, const GlContextInfo& context);

inline constexpr int kMaxTextureArrays = BT_MAX_TEXTURE_ARRAYS; // shaders/gl_bindings.glsl

class GlTextures {
public:
  // Uploads every material's base colour, normal and emissive map. `Auto` picks bindless when
  // the context has it. Throws GlError when `Bindless` is asked of a context without it, or when
  // one array would need more layers than GL_MAX_ARRAY_TEXTURE_LAYERS.
  GlTextures(const Scene& scene, TextureMode mode, const GlContextInfo& context);
  ~GlTextures();
  GlTextures(const GlTextures&) = delete;
  GlTextures& operator=(const GlTextures&) = delete;

  TextureMode mode() const { return mode_; } // Bindless or Arrays, never Auto
  // One per Scene::materials entry, texture references filled in.
  const std::vector<GlMaterial>& materials() const { return materials_; }
  // The anisotropy every texture is sampled with: the driver's maximum up to 16, 1 without
  // anisotropic filtering.
  float anisotropy() const { return anisotropy_; }
  // Binds the texture arrays to units 0.. (the arrays path); nothing to do for bindless.
  void bind() const;

private:
  void readMaterials(const Scene& scene);
  void uploadBindless(const Scene& scene);
  void uploadArrays(const Scene& scene);
  unsigned createTexture(const Image& image, bool srgb);

  TextureMode mode_ = TextureMode::Arrays;
  float anisotropy_ = 1.0f;
  std::vector<GlMaterial> materials_;
  std::vector<unsigned> textures_; // everything created, deleted in the destructor
  std::vector<unsigned> arrays_;   // arrays path: unit i holds arrays_[i], at most kMaxTextureArrays
  unsigned placeholder_ = 0;       // arrays path: 1x1 array on the units no size class uses
  std::vector<uint64_t> residentHandles_;
};

} // namespace bt::gl

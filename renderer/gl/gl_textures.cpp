#include "renderer/gl/gl_textures.h"

#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <map>
#include <utility>

namespace bt::gl {

namespace {

// Plain GL_RGBA8 for every map, sRGB-encoded ones included: the CPU reference filters the
// stored 8-bit values and decodes afterwards (scene/color.h bilinearRepeat, and Quake's
// engine multiplies texture by light in that encoded space), so the shaders decode after
// sampling too; the arrays path keeps colour and normal maps of one size in one array.
GLenum internalFormat(bool /*srgb*/) {
  return GL_RGBA8;
}

GLsizei mipLevels(int width, int height) {
  return static_cast<GLsizei>(std::bit_width(static_cast<unsigned>(std::max(width, height))));
}

// Trilinear with the driver's anisotropy (up to 16x) on both paths, so that a sampler lookup
// with a footprint (textureGrad) filters alike through either. The tracer's own lookups do not
// go through the sampler: textures.glsl fetches texels and weights them in fp32, exactly as the
// CPU reference (whose AOVs the GL images must equal), so this state does not change them.
void setSampling(GLuint texture, float anisotropy) {
  BT_GL(glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR));
  BT_GL(glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR));
  BT_GL(glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_REPEAT));
  BT_GL(glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_REPEAT));
  if (anisotropy > 1.0f) BT_GL(glTextureParameterf(texture, GL_TEXTURE_MAX_ANISOTROPY, anisotropy));
}

// One map's place on the arrays path: its image, and where GlMaterial names its array and layer.
struct Layer {
  const Image* image;
  uint32_t* array;
  uint32_t* layer;
};

// One texture array: layers of width x height, each holding one map in its corner (most often
// the map fills it).
struct SizeClass {
  int width = 0, height = 0;
  std::vector<Layer> layers;
  size_t texels() const { return size_t(width) * size_t(height) * layers.size(); }
};

// The maps in at most `maxClasses` arrays: one array per distinct size where that fits (a level
// with many sizes, such as one with high-resolution replacement textures, has more sizes than
// sampler units). Past that, the two classes whose merge adds the fewest padding texels are
// merged until they fit: the merged array's layers are as wide and as tall as its largest map,
// and the shaders wrap each map at its own size (GlMaterial::baseTexels...), so padding
// changes no image, only memory.
std::vector<SizeClass> sizeClasses(const std::vector<Layer>& maps, size_t maxClasses) {
  std::map<std::pair<int, int>, std::vector<Layer>> bySize;
  for (const Layer& m : maps) bySize[{m.image->width, m.image->height}].push_back(m);
  std::vector<SizeClass> classes;
  for (auto& [size, layers] : bySize) classes.push_back({size.first, size.second, std::move(layers)});
  while (classes.size() > maxClasses) {
    size_t bestA = 0, bestB = 1, bestAdded = SIZE_MAX;
    for (size_t a = 0; a < classes.size(); ++a)
      for (size_t b = a + 1; b < classes.size(); ++b) {
        const size_t merged = size_t(std::max(classes[a].width, classes[b].width)) *
            size_t(std::max(classes[a].height, classes[b].height)) * (classes[a].layers.size() + classes[b].layers.size());
        const size_t added = merged - classes[a].texels() - classes[b].texels();
        if (added < bestAdded) bestA = a, bestB = b, bestAdded = added;
      }
    SizeClass& into = classes[bestA];
    SizeClass& from = classes[bestB];
    into.width = std::max(into.width, from.width);
    into.height = std::max(into.height, from.height);
    into.layers.insert(into.layers.end(), from.layers.begin(), from.layers.end());
    classes.erase(classes.begin() + std::ptrdiff_t(bestB));
  }
  return classes;
}

glm::uvec2 texelsOf(const Image& image) {
  return {uint32_t(image.width), uint32_t(image.height)};
}

} // namespace

const char* toString(TextureMode mode) {
  switch (mode) {
  case TextureMode::Auto: return "auto";
  case TextureMode::Bindless: return "bindless";
  case TextureMode::Arrays: return "arrays";
  }
  return "?";
}

std::optional<TextureMode> parseTextureMode(std::string_view name) {
  if (name == "auto") return TextureMode::Auto;
  if (name == "bindless") return TextureMode::Bindless;
  if (name == "arrays") return TextureMode::Arrays;
  return std::nullopt;
}

TextureMode resolveTextureMode(TextureMode mode, const GlContextInfo& context) {
  if (mode == TextureMode::Bindless && !context.bindlessTextures)
    throw GlError(fmt::format("--gl-textures bindless: {} has no GL_ARB_bindless_texture", context.renderer));
  return mode == TextureMode::Auto ? (context.bindlessTextures ? TextureMode::Bindless : TextureMode::Arrays) : mode;
}

GlTextures::GlTextures(const Scene& scene, TextureMode mode, const GlContextInfo& context) {
  mode_ = resolveTextureMode(mode, context);
  // GL 4.6 core, GL_ARB_texture_filter_anisotropic and GL_EXT_texture_filter_anisotropic share
  // the enums; 16x is where the hardware stops anyway.
  if (context.anisotropicFiltering) {
    GLfloat maxAnisotropy = 1.0f;
    BT_GL(glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &maxAnisotropy));
    anisotropy_ = std::clamp(maxAnisotropy, 1.0f, 16.0f);
  }
  readMaterials(scene);
  if (mode_ == TextureMode::Bindless)
    uploadBindless(scene);
  else
    uploadArrays(scene);
}

void GlTextures::readMaterials(const Scene& scene) {
  materials_.resize(scene.materials.size());
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    GlMaterial& g = materials_[i];
    g.size = {static_cast<float>(std::max(m.width, 1)), static_cast<float>(std::max(m.height, 1))};
    g.roughness = m.roughnessValue;
    g.metallic = m.metallicValue;
    g.opacity = 1.0f; // the render scene's liquids set theirs (gl_tracer.cpp withShadingFlags)
    g.liquid = glm::vec4(1.0f);
    if (!m.baseColor.empty()) g.flags |= kMaterialHasBase, g.baseTexels = texelsOf(m.baseColor);
    if (!m.normal.empty()) g.flags |= kMaterialHasNormal, g.normalTexels = texelsOf(m.normal);
    if (!m.emissive.empty()) g.flags |= kMaterialHasEmissive, g.emissiveTexels = texelsOf(m.emissive);
  }
}

void GlTextures::uploadBindless(const Scene& scene) {
  auto makeResident = [&](const Image& image, bool srgb) -> uint64_t {
    const GLuint texture = createTexture(image, srgb);
    const GLuint64 handle = glGetTextureHandleARB(texture);
    checkGlError("glGetTextureHandleARB", __FILE__, __LINE__);
    BT_GL(glMakeTextureHandleResidentARB(handle));
    residentHandles_.push_back(handle);
    return handle;
  };
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    if (!m.baseColor.empty()) materials_[i].baseHandle = makeResident(m.baseColor, true);
    if (!m.normal.empty()) materials_[i].normalHandle = makeResident(m.normal, false);
    if (!m.emissive.empty()) materials_[i].emissiveHandle = makeResident(m.emissive, true);
  }
}

// Every map gathered, grouped into size classes, then each class uploaded as one array.
void GlTextures::uploadArrays(const Scene& scene) {
  std::vector<Layer> maps;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    GlMaterial& g = materials_[i];
    if (!m.baseColor.empty()) maps.push_back({&m.baseColor, &g.baseArray, &g.baseLayer});
    if (!m.normal.empty()) maps.push_back({&m.normal, &g.normalArray, &g.normalLayer});
    if (!m.emissive.empty()) maps.push_back({&m.emissive, &g.emissiveArray, &g.emissiveLayer});
  }
  const std::vector<SizeClass> classes = sizeClasses(maps, size_t(kMaxTextureArrays));
  GLint maxLayers = 0;
  BT_GL(glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers));

  const uint8_t white[4] = {255, 255, 255, 255};
  BT_GL(glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &placeholder_));
  textures_.push_back(placeholder_);
  BT_GL(glTextureStorage3D(placeholder_, 1, GL_RGBA8, 1, 1, 1));
  BT_GL(glTextureSubImage3D(placeholder_, 0, 0, 0, 0, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white));
  for (const SizeClass& size : classes) {
    const std::vector<Layer>& layers = size.layers;
    if (static_cast<GLint>(layers.size()) > maxLayers)
      throw GlError(fmt::format("{} textures of {}x{}: more than GL_MAX_ARRAY_TEXTURE_LAYERS ({})", layers.size(), size.width, size.height,
                                maxLayers));
    GLuint array = 0;
    BT_GL(glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array));
    textures_.push_back(array);
    BT_GL(glTextureStorage3D(array, mipLevels(size.width, size.height), internalFormat(true), size.width, size.height,
                             static_cast<GLsizei>(layers.size())));
    for (size_t l = 0; l < layers.size(); ++l) {
      const Image& image = *layers[l].image;
      BT_GL(glTextureSubImage3D(array, 0, 0, 0, static_cast<GLint>(l), image.width, image.height, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                                image.rgba.data()));
      *layers[l].array = static_cast<uint32_t>(arrays_.size());
      *layers[l].layer = static_cast<uint32_t>(l);
    }
    BT_GL(glGenerateTextureMipmap(array));
    setSampling(array, anisotropy_);
    arrays_.push_back(array);
  }
}

GLuint GlTextures::createTexture(const Image& image, bool srgb) {
  GLuint texture = 0;
  BT_GL(glCreateTextures(GL_TEXTURE_2D, 1, &texture));
  textures_.push_back(texture);
  BT_GL(glTextureStorage2D(texture, mipLevels(image.width, image.height), internalFormat(srgb), image.width, image.height));
  // Rows go up in the order Quake stores them (top row first at t = 0), so texture coordinate
  // t / height addresses row floor(t) with no flip, in both paths.
  BT_GL(glTextureSubImage2D(texture, 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data()));
  BT_GL(glGenerateTextureMipmap(texture));
  setSampling(texture, anisotropy_);
  return texture;
}

void GlTextures::bind() const {
  if (mode_ != TextureMode::Arrays) return;
  // Every unit the shader declares gets a complete texture, the unused ones a 1x1 placeholder:
  // what an unbound sampler returns is the driver's choice.
  for (int i = 0; i < kMaxTextureArrays; ++i)
    BT_GL(glBindTextureUnit(static_cast<GLuint>(BT_TEXTURE_ARRAYS_UNIT + i),
                            i < static_cast<int>(arrays_.size()) ? arrays_[static_cast<size_t>(i)] : placeholder_));
}

GlTextures::~GlTextures() {
  for (uint64_t handle : residentHandles_) glMakeTextureHandleNonResidentARB(handle);
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
}

} // namespace bt::gl

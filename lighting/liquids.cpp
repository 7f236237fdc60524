#include "lighting/liquids.h"

#include "quake/bspfile_q2.h"
#include "quake/entity_keys.h"
#include "scene/color.h"
#include "scene/names.h"

#include <algorithm>
#include <string>

namespace bt {

LiquidKind liquidKind(std::string_view texture, const SurfaceAttributes* surface) {
  if (surface) {
    using namespace quake::q2;
    if (surface->contents & CONTENTS_LAVA) return LiquidKind::Lava;
    if (surface->contents & CONTENTS_SLIME) return LiquidKind::Slime;
    if (surface->contents & CONTENTS_WATER) return LiquidKind::Water;
  }
  const std::string name = lowercase(texture);
  const std::string_view base = std::string_view(name).substr(name.find_last_of('/') + 1);
  if (base.starts_with("*lava")) return LiquidKind::Lava;
  if (base.starts_with("*slime")) return LiquidKind::Slime;
  if (base.starts_with("*tele")) return LiquidKind::Tele;
  return LiquidKind::Water;
}

float LiquidAlphas::of(LiquidKind kind) const {
  // GL_WaterAlphaForSurface: a kind's own alpha where it is above 0, else water's.
  const float own = kind == LiquidKind::Lava ? lava : kind == LiquidKind::Slime ? slime : kind == LiquidKind::Tele ? tele : water;
  return own > 0.0f ? own : water;
}

LiquidAlphas liquidAlphas(const Scene& scene) {
  LiquidAlphas alphas;
  const Entity* world = scene.worldspawn();
  if (!world) return alphas;
  // The last of `_name` and `name` in the file wins, as R_ParseWorldspawn reads them in order.
  const auto read = [&](std::string_view name, float& value) {
    for (const auto& [key, text] : world->keys) {
      const std::string_view k = std::string_view(key).substr(key.starts_with("_") ? 1 : 0);
      if (k != name) continue;
      if (const std::optional<float> v = quake::parseFloat(text)) value = std::clamp(*v, 0.0f, 1.0f);
    }
  };
  read("wateralpha", alphas.water);
  read("slimealpha", alphas.slime);
  read("lavaalpha", alphas.lava);
  read("telealpha", alphas.tele);
  return alphas;
}

namespace {

// A Quake 3 shader's first-stage blend (ioquake3 tr_shade.c draws that stage over the
// framebuffer with its GL blend factors): add (GL_ONE GL_ONE), filter (GL_DST_COLOR GL_ZERO),
// blend (GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA, by the image's mean alpha here). False for an
// opaque shader, which keeps the liquid defaults.
bool applyShaderBlend(ShaderBlend blend, GpuMaterial& m) {
  switch (blend) {
  case ShaderBlend::Opaque: return false;
  case ShaderBlend::Add: m.flags |= kMaterialBlendAdd, m.opacity = 1.0f, m.physicalOpacity = 0.0f; break;
  case ShaderBlend::Filter: m.flags |= kMaterialBlendFilter, m.opacity = 0.0f, m.physicalOpacity = 0.0f; break;
  case ShaderBlend::Blend: m.opacity = m.averageAlbedo.a, m.physicalOpacity = physicalOpacityOfAlpha(m.opacity); break;
  }
  return true;
}

} // namespace

void applyLiquidBlends(const Scene& scene, const std::vector<uint32_t>& faceFlags, std::vector<GpuMaterial>& materials) {
  const Game game = gameOf(scene);
  const LiquidAlphas alphas = liquidAlphas(scene);
  std::vector<bool> decided(materials.size(), false);
  for (size_t i = 0; i < scene.faces.size() && i < faceFlags.size(); ++i) {
    const Face& face = scene.faces[i];
    if (!(faceFlags[i] & kFaceLiquid) || face.material >= materials.size() || decided[face.material]) continue;
    decided[face.material] = true;
    GpuMaterial& m = materials[face.material];
    const LiquidKind kind = liquidKind(face.texture, face.surface ? &*face.surface : nullptr);
    if (game == Game::Quake2) {
      m.opacity = quake2SurfaceAlpha(face.surface ? face.surface->flags : 0);
    } else if (game == Game::Quake) {
      m.opacity = alphas.of(kind);
    } else if (game == Game::Quake3 && applyShaderBlend(scene.materials[face.material].blend, m)) {
      continue;
    }
    const float physicalDefault = kind == LiquidKind::Water ? kPhysicalWaterOpacity
        : kind == LiquidKind::Slime                         ? kPhysicalSlimeOpacity
                                                            : 1.0f;
    m.physicalOpacity = m.opacity < 1.0f ? physicalOpacityOfAlpha(m.opacity) : physicalDefault;
  }
}

float physicalOpacityOfAlpha(float a) {
  return srgbToLinear(std::clamp(a, 0.0f, 1.0f));
}

glm::vec3 liquidTint(const GpuMaterial& m) {
  const glm::vec3 mean(m.averageAlbedo);
  if (m.flags & kMaterialBlendAdd) return glm::vec3(1.0f);
  if (m.flags & kMaterialBlendFilter) return mean;
  const float peak = std::max({mean.x, mean.y, mean.z});
  return peak > 0.0f ? mean / peak : glm::vec3(1.0f);
}

glm::vec3 liquidAddedRadiance(const GpuMaterial& m) {
  return (m.flags & kMaterialBlendAdd) ? glm::vec3(m.averageAlbedo) : glm::vec3(0.0f);
}

} // namespace bt

// Liquids as the engines draw them: which liquid a face is, and how its surface blends with
// what lies behind it (lighting/README.md, "Liquids"), and Quake 3 shaders' blends, drawn the
// same way. Both tracers read the blend from the face's material (GpuMaterial::opacity,
// kMaterialBlendAdd, kMaterialBlendFilter), only on kFaceLiquid faces.
#pragma once

#include "lighting/game_rules.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <string_view>
#include <vector>

namespace bt {

// Quake's four kinds, by name as QuakeSpasm's Mod_LoadFaces tells them (SURF_DRAWLAVA, ...):
// `*lava...`, `*slime...`, `*tele...`, any other liquid is water. Quake 2 by contents.
enum class LiquidKind : uint8_t { Water, Slime, Lava, Tele };
LiquidKind liquidKind(std::string_view texture, const SurfaceAttributes* surface);

// The worldspawn's liquid alphas as QuakeSpasm reads them (gl_rmisc.c R_ParseWorldspawn: a
// key's leading underscore is ignored, so `_wateralpha` and `wateralpha` both count): water
// defaults to r_wateralpha's 1 (opaque), the other three to 0, which means "as water"
// (GL_WaterAlphaForSurface). Values are clamped to 0..1 as the cvars are.
struct LiquidAlphas {
  float water = 1.0f, slime = 0.0f, lava = 0.0f, tele = 0.0f;
  float of(LiquidKind kind) const;
};
LiquidAlphas liquidAlphas(const Scene& scene);

// What a translucent liquid weighs in the image: the camera sees self x its colour + behind x
// what lies behind it; with `filter` (Quake 3's blendFunc filter) behind is also multiplied by
// the liquid's own colour. Opaque: (1, 0).
struct LiquidBlend {
  float self = 1.0f;
  float behind = 0.0f;
  bool filter = false;
};
inline LiquidBlend liquidBlend(const GpuMaterial& m) {
  if (m.flags & kMaterialBlendFilter) return {0.0f, 1.0f, true};
  return {m.opacity, (m.flags & kMaterialBlendAdd) ? 1.0f : 1.0f - m.opacity};
}
// What lies behind weighs, per channel, where the surface shows `surfaceSrgb` (its colour in
// the framebuffer's gamma space).
inline glm::vec3 behindWeight(const LiquidBlend& b, const glm::vec3& surfaceSrgb) {
  return b.filter ? surfaceSrgb : glm::vec3(b.behind);
}
// Physical mode's: the same with GpuMaterial::physicalOpacity. Quake 3's additive and filter
// blends have physicalOpacity 0: the ray always passes, adding liquidAddedRadiance and taking
// liquidTint.
inline LiquidBlend physicalLiquidBlend(const GpuMaterial& m) {
  return {m.physicalOpacity, 1.0f - m.physicalOpacity};
}

// Physical mode's opacity for an alpha the engine blends with (a level's `wateralpha`, Quake 2's
// SURF_TRANS33 / SURF_TRANS66, a Quake 3 `blendFunc blend`): the engine blends in the
// framebuffer's gamma space, so over darkness it shows srgbToLinear(a x srgb(t)), about
// srgbToLinear(a) of the liquid's linear colour t (0.21 at a = 0.5, where a linear blend at a
// shows 0.5), and over something as bright as the liquid all of it. A linear blend whose liquid
// share is srgbToLinear(a) gives both; between them (what lies behind darker than the liquid,
// or brighter) it shows more of what lies behind than the game does.
float physicalOpacityOfAlpha(float a);

// Physical mode's default opacity of a liquid the level leaves opaque: water lets half the
// light through, slime a fifth; lava and teleporters stay opaque (they glow instead).
inline constexpr float kPhysicalWaterOpacity = 0.5f;
inline constexpr float kPhysicalSlimeOpacity = 0.8f;

// Physical mode's tint of the light that crosses a liquid: its texture's mean linear colour
// scaled so that its brightest channel is 1 (the hue, not the darkness, of the texture); a
// filter's mean linear colour itself; none (1) for an additive one.
glm::vec3 liquidTint(const GpuMaterial& m);
// Physical mode's radiance an additive surface adds to a ray that crosses it: its texture's mean
// linear colour (an emitter that hides nothing); 0 for every other liquid.
glm::vec3 liquidAddedRadiance(const GpuMaterial& m);

// Sets the blend of every material that a liquid face (kFaceLiquid in faceFlags) uses, for
// faithful mode (opacity) and physical mode (physicalOpacity: physicalOpacityOfAlpha of the
// level's alpha where it gives one below 1, else kPhysicalWaterOpacity / kPhysicalSlimeOpacity /
// 1 by kind): Quake's
// worldspawn alphas (Quake and Hexen II), Quake 2's SURF_TRANS33 / SURF_TRANS66 (0.33 / 0.66,
// ref_gl R_DrawAlphaSurfaces; a texture's first liquid face decides), Quake 3 shaders' first
// stage blendFunc (Material::blend: add, filter, blend by the image's mean alpha; physical mode
// the same, add and filter always crossed). Other materials stay opaque.
void applyLiquidBlends(const Scene& scene, const std::vector<uint32_t>& faceFlags, std::vector<GpuMaterial>& materials);

} // namespace bt

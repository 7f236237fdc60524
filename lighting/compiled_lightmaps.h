// `--lighting compiled`: a .bsp drawn with the lightmaps its compiler baked, as its engine shows
// them. The compiled faces (Scene::compiledLighting) become the fragments of the scene faces
// (brush sides) they lie on, in faithful mode's layout (lightmaps.h), so both tracers draw them
// through the same bilinear lookup. Each luxel holds what the engine uploads to its lightmap
// texture (the styles summed at their values when the level loads, scaled and clamped as the
// engine does), and Lightmaps::displayScale what it multiplies the texture by.
//
// The engines' rules, read from their sources:
//   quake    QuakeSpasm (gl_rsurf.c R_BuildLightMap, gl_overbright 1 by default):
//            luxel = min(255, (Σ stored × style) >> 8), shown as texture × luxel × 2 / 255.
//   hexen2   GLHexen / uHexen2 (GLQuake's R_BuildLightMap, no overbright):
//            luxel = min(255, (Σ stored × style) >> 7), shown as texture × luxel / 255.
//   halflife GoldSrc as Xash3D FWGS reimplements it (gl_overbright 0; lighting/luxel_display.h):
//            luxel = lightgammatable[min(1023, (Σ stored × style) × 338 >> 14)] >> 2 at the
//            defaults gamma 2.5, lightgamma 2.5, brightness 0, shown as texture × luxel / 255.
//            Stored here as min(255, Σ stored × style / 264), the table applied by the tracers.
//   quake2   id's ref_gl R_BuildLightMap with gl_modulate 1: the sum Σ stored × style / 'm'
//            truncated, scaled down to keep its hue where a channel passes 255, shown as
//            texture × luxel / 255.
//   quake3   ioquake3 with its defaults r_mapOverBrightBits 2, r_overBrightBits 1 (fullscreen,
//            hardware gamma): R_ColorShiftLightingBytes doubles each luxel, scaled down to keep
//            its hue where a channel passes 255, and the gamma ramp doubles the picture:
//            texture × luxel × 2 / 255. Its planar surfaces' lightmap blocks only (patches,
//            triangle soups and vertex light are not drawn from compiled light yet).
// Styles (the `lightstyle` strings the game code sets at worldspawn, the same table in Quake,
// Hexen II, Half-Life and Quake 2) take their first letter, the value at time 0: Quake and
// Half-Life weigh a letter (c - 'a') × 22 (so 'm' is 264, 3 % over 256) and a style nobody set
// 256; Quake 2 weighs (c - 'a') / 12 and an unset style 1. Switchable styles (32..62) are 'm',
// or 'a' where a light with that style starts off (spawnflags 1), as the lights' spawn code sets.
#pragma once

#include "lighting/lightmaps.h"
#include "lighting/render_scene.h"
#include "scene/compiled_lighting.h"
#include "scene/scene.h"

#include <array>
#include <cstddef>
#include <string>

namespace bt {

enum class LightmapEngine { Quake, Hexen2, HalfLife, Quake2, Quake3 };

// The engine named by CompiledLighting::engine or `--game` ("quake", "hexen2", "halflife",
// "quake2", "quake3"); nullopt for any other name.
std::optional<LightmapEngine> lightmapEngineNamed(const std::string& name);

// The engine's weight of each of the 256 light styles when the level loads (see above).
std::array<float, 256> styleValuesAtLoad(LightmapEngine engine, const Scene& scene);

// What the engine uploads for one luxel: `stored` holds the luxel's value in each of its styles.
glm::vec3 engineLuxel(LightmapEngine engine, const std::array<float, 256>& styleValues, const std::array<uint8_t, 4>& styles,
                      const std::array<glm::vec3, 4>& stored);

// shown = texture × luxel × this.
float engineDisplayScale(LightmapEngine engine);

struct CompiledLightmaps {
  Lightmaps lightmaps;
  size_t facesShown = 0;    // scene faces drawn from compiled luxels
  size_t facesUnlit = 0;    // scene faces whose compiled faces carry no lightmap (drawn black, as the engine does)
  size_t compiledFaces = 0; // compiled faces with a lightmap
};

// The compiled lightmaps of `scene` laid out on the faces of `rs` (built from it). Empty when
// the level has none (compiled without light, a .map source, Quake 3's pages). `styleScale`:
// each style's weight times this (the viewer's light-style sliders, render --style; nullptr: 1),
// as the game's lightstyle strings would weigh it.
CompiledLightmaps buildCompiledLightmaps(const Scene& scene, const RenderScene& rs, LightmapEngine engine,
                                         const std::array<float, 256>* styleScale = nullptr);

// `--lighting compiled`: sets rs.lightmaps to the level's compiled ones, drawn by the engine of
// `game` (a --game name; empty: the file's own, CompiledLighting::engine). Returns why it
// cannot (the caller warns and shows faithful lighting instead), empty when it did.
std::string showCompiledLightmaps(const Scene& scene, RenderScene& rs, const std::string& game,
                                  const std::array<float, 256>* styleScale = nullptr);

} // namespace bt

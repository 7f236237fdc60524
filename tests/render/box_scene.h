// Builds small scenes of axis-aligned box brushes in code, for analytic lighting tests.
#pragma once

#include "renderer/cpu/cpu_renderer.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bt::test {

class BoxSceneBuilder {
public:
  BoxSceneBuilder();

  // A material with a solid base colour (sRGB bytes); returns its name.
  std::string material(const std::string& name, uint8_t r, uint8_t g, uint8_t b);
  uint32_t entity(std::vector<std::pair<std::string, std::string>> keys);
  void worldKey(const std::string& key, const std::string& value);
  // An axial box brush with the same texture on all six sides, owned by `entity` (0 = world).
  void box(glm::dvec3 min, glm::dvec3 max, const std::string& texture, uint32_t entity = 0);
  // Six boxes of `thickness` enclosing the inside [min, max].
  void room(glm::dvec3 min, glm::dvec3 max, const std::string& texture, double thickness = 16.0);

  Scene build() const { return scene_; }
  Scene& scene() { return scene_; }

private:
  Scene scene_;
};

// The furnished room the sampler's and the denoiser's tests measure noise in: a white 256 x 256 x
// 128 room around (0 0 64), a red pillar before the far wall and a low blue block in a corner,
// lit by one inverse-square light (delay 2, light 300) near the ceiling. `range`: worldspawn
// `_range`, which scales every light and nothing else (a dark or a bright version of the same
// room); `softLight`: the light's `_deviance 8`; `bricks`: every texture a brick wall, its dark
// mortar lines 2 units wide every 8 units (about half a pixel in the render below), so that a
// pixel's samples cover texels of unlike colour where its albedo AOV (the centre) sees one;
// `tinted`: that mortar blue-grey rather than a darker red-brown, so that they mix hues too.
struct FurnishedRoom {
  std::optional<std::string> range;
  bool softLight = false;
  bool bricks = false;
  bool tinted = false;
};
Scene furnishedRoom(const FurnishedRoom& options);
// The room seen from a corner at 48 x 36, physical mode with one bounce, `spp` samples of `seed`,
// with the Sobol sequence (IntegratorSettings::lowDiscrepancy) or PCG alone.
RenderImage renderFurnishedRoom(const RenderScene& rs, int spp, uint32_t seed, bool lowDiscrepancy);

// A 1024 x 1024 x 256 room around (0 0 128) with pillars, a half wall and a skylight, lit by
// `count` point lights of every kind (formulas, wait, _falloff, spots, colours, _deviance when
// `softLights`), a darklight, a local minlight and a sun: for light selection tests.
Scene manyLightsRoom(int count, bool softLights, uint32_t seed);

// A 4096 x 512 x 256 hall around (0 0 128) cut into eight rooms by walls with a doorway, lit by
// `count` lights of short, varied reach (linear with wait 1 to 3 or a _falloff, inverse square
// with wait 2 to 8, a few coloured and spots): a level's many lights, of which a point sees few.
Scene manyLightsHall(int count, uint32_t seed);

// Physical mode's fireflies (lighting/README.md, "Fireflies"): a 256 x 256 x 128 room around
// (0 0 64), lit by one inverse-square light (delay 2, light 300) 8 units from the wall x = -128,
// where that wall is 256 times brighter than at the light's match distance (128 units), and a
// grey pillar; the floor's light from a bounce is mostly that rare bright spot.
Scene lightNearWallRoom();

// A white room (x -256 .. 256, y -128 .. 128, z 0 .. 256) roofed by two skies, `sky_a` over its
// west half (x < 0) and `sky_b` over its east, under a sun (light 300) shining straight down
// with `_suntexture sky_b`: the compiler lights the east half of the floor alone. Its camera
// (info_intermission) looks down onto both halves.
Scene twoSkiesRoom();

// A floor (top z = 0, texture "floor") with a water brush on it (x 0 .. 256, y -256 .. 256, z 0 ..
// 128, texture `water`, every face with `surface`) and a light at (-64 0 64) beside it, without
// bounce, in `game` (Scene::game): a Quake 2 water drawn as a wall shadows the floor under it from
// inside (lighting/render_scene.h RenderScene::blocksFromInside).
Scene waterBesideALight(const char* game, const char* water, std::optional<SurfaceAttributes> surface);

} // namespace bt::test

// What each game's own code does with a level's entities, where it differs between the games:
// which brush entities it never draws, and where it puts the player's eye.
#pragma once

#include "lighting/lights.h"
#include "scene/scene.h"

#include <string_view>

namespace bt {

// The game a level is for, as far as its entities' meaning goes. A Valve 220 .map is Half-Life's
// when its textures come from WAD3 files; without them it reads as Quake's, which differs only in
// the eye height of its spawn points (the hiding rules below hold for both).
enum class Game { Quake, HalfLife, Quake2, Quake3 };

Game gameOf(const Scene& scene);

// Whether the game code never draws this brush entity's model when the level starts (README,
// "What the engine hides", lists each rule with the function of id's or Valve's game code).
bool gameHidesEntity(const Entity& entity, Game game);

// The worldspawn defaults ericw-tools `light` takes from its game target before the level's keys
// (light.cc, each game's defaults; lighting/README.md lists them), and how the game's engine
// shows a stored lightmap value.
WorldLighting compilerDefaults(Game game);

// Light units per unit of the worldspawn's `_minlight`: ericw-tools reads a Quake 2 level's
// `_minlight` as a fraction of 128 (arghrad's convention: the lit-games oracle stores 0.26 -> 33,
// 0.5 -> 64, 0.75 -> 96 at range 1), every other game's in light units.
float minlightUnit(Game game);

// ericw-tools' glass: a Quake 2 face with SURF_TRANS33 or SURF_TRANS66 (trace_embree.cc
// CreateGeometry `is_glass`). `light` lets shadow rays through it, tinted by the texel they
// cross at the face's opacity (Embree_FilterFuncN, raystream getPushedRayColor: mix(c, c x texel,
// opacity)); the opacity is the texel's alpha where below 255, so a texture it has no pixels for
// (every lit-games level: `can't find pixel data`) samples 0 and passes the light whole. It lights
// the face from both sides (ltface.cc Lightsurf_Init: twosided = Face_IsTranslucent).
bool compilerGlass(const Face& face, Game game);

} // namespace bt

// What each game's own code does with a level's entities, where it differs between the games:
// which brush entities it never draws, and where it puts the player's eye.
#pragma once

#include "lighting/lights.h"
#include "scene/scene.h"

#include <cstdint>
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

// Quake 2's alpha of a face by its surface flags (ref_gl gl_rsurf.c R_DrawAlphaSurfaces:
// qglColor4f(intens, intens, intens, 0.33) for SURF_TRANS33, 0.66 for SURF_TRANS66, 1 for the
// others), for its liquids (lighting/liquids.h) and its glass alike.
float quake2SurfaceAlpha(int32_t surfaceFlags);

// Quake 2's glass as its engine draws it: a SURF_TRANS33/66 face that is not a liquid (no
// SURF_WARP, which lighting/liquids.h draws) goes to R_DrawAlphaSurfaces, which binds its texture
// alone, without the lightmap the compiler gave it (compilerGlass lights it), modulated by
// gl_state.inverse_intensity and blended at quake2SurfaceAlpha over what lies behind. The
// texture was scaled by the `intensity` cvar as it was loaded (gl_image.c GL_LightScaleTexture),
// so 1 / intensity gives the texture's own colour back, as the liquids' warp draws it
// (EmitWaterPolys, same colour): the unlit texture, as faithful mode shows Quake's liquids.
// (At `intensity 2`, ref_gl's default, a channel above 127 saturates to 127 on the glass: not
// modelled, as faithful mode draws every Quake 2 face at intensity 1's scale, texture × luxel /
// 255.) The alpha; 1 where the engine draws the face as any other.
float engineGlassAlpha(const Face& face, Game game);

} // namespace bt

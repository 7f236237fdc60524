#include "lighting/game_rules.h"

#include "lighting/lights.h"
#include "lighting/luxel_display.h"
#include "lighting/q3map2_light.h"
#include "quake/bspfile_q2.h"
#include "quake/entity_keys.h"

#include <cmath>

namespace bt {

namespace {

int spawnflags(const Entity& e) {
  return int(quake::parseFloat(e.value("spawnflags", "0")).value_or(0.0f));
}

// Brush entities whose spawn function never links a visible model, in every game that has them.
// The classnames do not clash between the games, so one list serves all.
constexpr std::string_view kNeverDrawn[] = {
    "func_episodegate",   // Quake misc.qc func_episodegate: returns before setmodel on a new game
    "func_areaportal",    // Quake 2 g_misc.c SP_func_areaportal: no gi.setmodel
    "func_killbox",       // Quake 2 g_func.c SP_func_killbox: SVF_NOCLIENT
    "func_ladder",        // Half-Life triggers.cpp CLadder::Precache: kRenderTransTexture, renderamt 0
    "func_monsterclip",   // Half-Life bmodels.cpp CFuncMonsterClip::Spawn: EF_NODRAW
    "func_mortar_field",  // Half-Life mortar.cpp CFuncMortarField::Spawn: EF_NODRAW
    "func_tankcontrols",  // Half-Life func_tank.cpp CFuncTankControls::Spawn: EF_NODRAW
    "func_traincontrols", // Half-Life plats.cpp CFuncTrainControls::Spawn: EF_NODRAW
    "game_zone_player",   // Half-Life maprules.cpp CRuleBrushEntity::Spawn: EF_NODRAW
    "env_bubbles",        // Half-Life effects.cpp CBubbling::Spawn: kRenderTransTexture, renderamt 0
};

// Quake 2's trigger-spawned brush models start unlinked from the client (SVF_NOCLIENT).
bool quake2WaitsForTrigger(std::string_view classname, int flags) {
  if (classname == "func_wall") return (flags & 7) != 0 && !(flags & 4); // g_misc.c SP_func_wall: START_ON is 4
  if (classname == "func_object") return flags != 0;                     // g_misc.c SP_func_object
  if (classname == "func_explosive") return (flags & 1) != 0;            // g_misc.c SP_func_explosive
  return false;
}

// Half-Life's renderer skips a model drawn blended at amount 0 (rendermode other than normal).
bool halfLifeInvisible(const Entity& e) {
  const auto mode = quake::parseFloat(e.value("rendermode", "0"));
  const auto amount = quake::parseFloat(e.value("renderamt", "255"));
  return mode && amount && *mode != 0.0f && *amount == 0.0f;
}

} // namespace

Game gameOf(const Scene& scene) {
  if (scene.game == "halflife") return Game::HalfLife;
  if (scene.game == "quake2") return Game::Quake2;
  if (scene.game == "quake3") return Game::Quake3;
  if (scene.game == "quake" || scene.game == "hexen2") return Game::Quake;
  const std::string_view f = scene.format;
  if (f.starts_with("quake2") || f == "ibsp38" || f == "daikatana") return Game::Quake2;
  if (f.starts_with("quake3") || f == "ibsp46") return Game::Quake3;
  if (f == "bsp30") return Game::HalfLife;
  for (const Material& m : scene.materials)
    if (m.source == TextureSource::Wad3) return Game::HalfLife;
  return Game::Quake;
}

WorldLighting compilerDefaults(Game game) {
  WorldLighting world;
  if (game == Game::Quake2) {
    // ericw-tools' Quake 2 target ("from game target" in the light log of every lit-games level).
    world.range = 1.0f;
    world.bounces = 1;
    world.bouncestyled = true;
    world.bouncescale = 0.85f;
    world.bouncecolorscale = 0.5f;
    world.surflightScale = 0.65f;
    world.surflightSkyScale = 0.65f;
    world.surflightRadiosity = true;
  }
  // Quake 2's ref_gl (gl_modulate 1) and Half-Life's GoldSrc draw texture × lightmap / 255, with
  // no overbright (lighting/README.md, "The compiled view").
  if (game == Game::Quake2 || game == Game::HalfLife) world.overbrightOne = 255.0f;
  // GoldSrc brightens each luxel through its light gamma table first (lighting/luxel_display.h).
  if (game == Game::HalfLife) world.luxelDisplay = BT_LUXEL_DISPLAY_GOLDSRC;
  if (game == Game::Quake3) {
    // q3map2 stores the light sum itself; ioquake3 shows it shifted one bit and doubled by the
    // gamma ramp (lighting/q3map2_light.h).
    world.range = q3map2::kLuxelScale;
    world.overbrightOne = q3map2::kOverbrightOne;
  }
  return world;
}

float minlightUnit(Game game) {
  return game == Game::Quake2 ? 128.0f : 1.0f;
}

bool compilerGlass(const Face& face, Game game) {
  using namespace quake::q2;
  return game == Game::Quake2 && face.surface && (face.surface->flags & (SURF_TRANS33 | SURF_TRANS66));
}

float quake2SurfaceAlpha(int32_t surfaceFlags) {
  using namespace quake::q2;
  return (surfaceFlags & SURF_TRANS33) ? 0.33f : (surfaceFlags & SURF_TRANS66) ? 0.66f : 1.0f;
}

float engineGlassAlpha(const Face& face, Game game) {
  if (game != Game::Quake2 || !face.surface || (face.surface->flags & quake::q2::SURF_WARP)) return 1.0f;
  return quake2SurfaceAlpha(face.surface->flags);
}

bool gameHidesEntity(const Entity& entity, Game game) {
  const std::string_view classname = entity.classname();
  // Quake triggers.qc InitTrigger (modelindex 0), Quake 2 g_trigger.c InitTrigger and Quake 3
  // g_trigger.c InitTrigger (SVF_NOCLIENT), Half-Life triggers.cpp CBaseTrigger::InitTrigger (EF_NODRAW).
  if (classname.starts_with("trigger_")) return true;
  for (std::string_view hidden : kNeverDrawn)
    if (classname == hidden) return true;
  if (game == Game::Quake2 && quake2WaitsForTrigger(classname, spawnflags(entity))) return true;
  return (game == Game::Quake || game == Game::HalfLife) && halfLifeInvisible(entity);
}

} // namespace bt

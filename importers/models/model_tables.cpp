#include "importers/models/model_tables.h"

#include <array>

namespace bt::models {
namespace {

// Quake: id's QuakeC 1.06, each spawn function's precache_model / setmodel.
constexpr std::string_view kItems = "QuakeC items.qc";
constexpr std::string_view kMisc = "QuakeC misc.qc";
constexpr auto kQuake = std::to_array<ClassModel>({
    {"item_health", "maps/b_bh10.bsp", 1, 0, kItems},  // H_ROTTEN
    {"item_health", "maps/b_bh100.bsp", 2, 0, kItems}, // H_MEGA
    {"item_health", "maps/b_bh25.bsp", 0, 0, kItems},
    {"item_shells", "maps/b_shell1.bsp", 1, 0, kItems}, // WEAPON_BIG2
    {"item_shells", "maps/b_shell0.bsp", 0, 0, kItems},
    {"item_spikes", "maps/b_nail1.bsp", 1, 0, kItems},
    {"item_spikes", "maps/b_nail0.bsp", 0, 0, kItems},
    {"item_rockets", "maps/b_rock1.bsp", 1, 0, kItems},
    {"item_rockets", "maps/b_rock0.bsp", 0, 0, kItems},
    {"item_cells", "maps/b_batt1.bsp", 1, 0, kItems},
    {"item_cells", "maps/b_batt0.bsp", 0, 0, kItems},
    {"item_armor1", "progs/armor.mdl", 0, 0, kItems},
    {"item_armor2", "progs/armor.mdl", 0, 1, kItems},
    {"item_armorInv", "progs/armor.mdl", 0, 2, kItems},
    {"weapon_supershotgun", "progs/g_shot.mdl", 0, 0, kItems},
    {"weapon_nailgun", "progs/g_nail.mdl", 0, 0, kItems},
    {"weapon_supernailgun", "progs/g_nail2.mdl", 0, 0, kItems},
    {"weapon_grenadelauncher", "progs/g_rock.mdl", 0, 0, kItems},
    {"weapon_rocketlauncher", "progs/g_rock2.mdl", 0, 0, kItems},
    {"weapon_lightning", "progs/g_light.mdl", 0, 0, kItems},
    {"item_artifact_invulnerability", "progs/invulner.mdl", 0, 0, kItems},
    {"item_artifact_envirosuit", "progs/suit.mdl", 0, 0, kItems},
    {"item_artifact_invisibility", "progs/invisibl.mdl", 0, 0, kItems},
    {"item_artifact_super_damage", "progs/quaddama.mdl", 0, 0, kItems},
    {"misc_explobox", "maps/b_explob.bsp", 0, 0, kMisc},
    {"misc_explobox2", "maps/b_exbox2.bsp", 0, 0, kMisc},
    {"monster_army", "progs/soldier.mdl", 0, 0, "QuakeC soldier.qc"},
    {"monster_dog", "progs/dog.mdl", 0, 0, "QuakeC dog.qc"},
    {"monster_ogre", "progs/ogre.mdl", 0, 0, "QuakeC ogre.qc"},
    {"monster_knight", "progs/knight.mdl", 0, 0, "QuakeC knight.qc"},
    {"monster_hell_knight", "progs/hknight.mdl", 0, 0, "QuakeC hknight.qc"},
    {"monster_demon1", "progs/demon.mdl", 0, 0, "QuakeC demon.qc"},
    {"monster_wizard", "progs/wizard.mdl", 0, 0, "QuakeC wizard.qc"},
    {"monster_zombie", "progs/zombie.mdl", 0, 0, "QuakeC zombie.qc"},
    {"monster_shambler", "progs/shambler.mdl", 0, 0, "QuakeC shambler.qc"},
    {"monster_enforcer", "progs/enforcer.mdl", 0, 0, "QuakeC enforcer.qc"},
    {"monster_fish", "progs/fish.mdl", 0, 0, "QuakeC fish.qc"},
    {"monster_shalrath", "progs/shalrath.mdl", 0, 0, "QuakeC shalrath.qc"},
    {"monster_tarbaby", "progs/tarbaby.mdl", 0, 0, "QuakeC tarbaby.qc"},
});

// Quake 2: game/g_items.c itemlist[], world_model.
constexpr std::string_view kG = "Quake 2 g_items.c";
constexpr auto kQuake2 = std::to_array<ClassModel>({
    {"item_armor_body", "models/items/armor/body/tris.md2", 0, 0, kG},
    {"item_armor_combat", "models/items/armor/combat/tris.md2", 0, 0, kG},
    {"item_armor_jacket", "models/items/armor/jacket/tris.md2", 0, 0, kG},
    {"item_armor_shard", "models/items/armor/shard/tris.md2", 0, 0, kG},
    {"weapon_shotgun", "models/weapons/g_shotg/tris.md2", 0, 0, kG},
    {"weapon_supershotgun", "models/weapons/g_shotg2/tris.md2", 0, 0, kG},
    {"weapon_machinegun", "models/weapons/g_machn/tris.md2", 0, 0, kG},
    {"weapon_chaingun", "models/weapons/g_chain/tris.md2", 0, 0, kG},
    {"weapon_grenadelauncher", "models/weapons/g_launch/tris.md2", 0, 0, kG},
    {"weapon_rocketlauncher", "models/weapons/g_rocket/tris.md2", 0, 0, kG},
    {"weapon_hyperblaster", "models/weapons/g_hyperb/tris.md2", 0, 0, kG},
    {"weapon_railgun", "models/weapons/g_rail/tris.md2", 0, 0, kG},
    {"weapon_bfg", "models/weapons/g_bfg/tris.md2", 0, 0, kG},
    {"ammo_shells", "models/items/ammo/shells/medium/tris.md2", 0, 0, kG},
    {"ammo_bullets", "models/items/ammo/bullets/medium/tris.md2", 0, 0, kG},
    {"ammo_cells", "models/items/ammo/cells/medium/tris.md2", 0, 0, kG},
    {"ammo_rockets", "models/items/ammo/rockets/medium/tris.md2", 0, 0, kG},
    {"ammo_slugs", "models/items/ammo/slugs/medium/tris.md2", 0, 0, kG},
    {"item_quad", "models/items/quaddama/tris.md2", 0, 0, kG},
    {"item_invulnerability", "models/items/invulner/tris.md2", 0, 0, kG},
    {"item_adrenaline", "models/items/adrenal/tris.md2", 0, 0, kG},
    {"item_health", "models/items/healing/medium/tris.md2", 0, 0, kG},
    {"item_health_small", "models/items/healing/stimpack/tris.md2", 0, 0, kG},
    {"item_health_large", "models/items/healing/large/tris.md2", 0, 0, kG},
    {"item_health_mega", "models/items/mega_h/tris.md2", 0, 0, kG},
});

// Quake 3 (and OpenArena, which keeps its item list): game/bg_misc.c bg_itemlist[], world_model[0].
constexpr std::string_view kB = "Quake 3 bg_misc.c";
constexpr auto kQuake3 = std::to_array<ClassModel>({
    {"item_armor_shard", "models/powerups/armor/shard.md3", 0, 0, kB},
    {"item_armor_combat", "models/powerups/armor/armor_yel.md3", 0, 0, kB},
    {"item_armor_body", "models/powerups/armor/armor_red.md3", 0, 0, kB},
    {"item_health_small", "models/powerups/health/small_cross.md3", 0, 0, kB},
    {"item_health", "models/powerups/health/medium_cross.md3", 0, 0, kB},
    {"item_health_large", "models/powerups/health/large_cross.md3", 0, 0, kB},
    {"item_health_mega", "models/powerups/health/mega_cross.md3", 0, 0, kB},
    {"weapon_gauntlet", "models/weapons2/gauntlet/gauntlet.md3", 0, 0, kB},
    {"weapon_shotgun", "models/weapons2/shotgun/shotgun.md3", 0, 0, kB},
    {"weapon_machinegun", "models/weapons2/machinegun/machinegun.md3", 0, 0, kB},
    {"weapon_grenadelauncher", "models/weapons2/grenadel/grenadel.md3", 0, 0, kB},
    {"weapon_rocketlauncher", "models/weapons2/rocketl/rocketl.md3", 0, 0, kB},
    {"weapon_lightning", "models/weapons2/lightning/lightning.md3", 0, 0, kB},
    {"weapon_railgun", "models/weapons2/railgun/railgun.md3", 0, 0, kB},
    {"weapon_plasmagun", "models/weapons2/plasma/plasma.md3", 0, 0, kB},
    {"weapon_bfg", "models/weapons2/bfg/bfg.md3", 0, 0, kB},
    {"ammo_shells", "models/powerups/ammo/shotgunam.md3", 0, 0, kB},
    {"ammo_bullets", "models/powerups/ammo/machinegunam.md3", 0, 0, kB},
    {"ammo_grenades", "models/powerups/ammo/grenadeam.md3", 0, 0, kB},
    {"ammo_cells", "models/powerups/ammo/plasmaam.md3", 0, 0, kB},
    {"ammo_lightning", "models/powerups/ammo/lightningam.md3", 0, 0, kB},
    {"ammo_rockets", "models/powerups/ammo/rocketam.md3", 0, 0, kB},
    {"ammo_slugs", "models/powerups/ammo/railgunam.md3", 0, 0, kB},
    {"ammo_bfg", "models/powerups/ammo/bfgam.md3", 0, 0, kB},
    {"item_quad", "models/powerups/instant/quad.md3", 0, 0, kB},
    {"item_enviro", "models/powerups/instant/enviro.md3", 0, 0, kB},
    {"item_haste", "models/powerups/instant/haste.md3", 0, 0, kB},
    {"item_invis", "models/powerups/instant/invis.md3", 0, 0, kB},
    {"item_regen", "models/powerups/instant/regen.md3", 0, 0, kB},
    {"item_flight", "models/powerups/instant/flight.md3", 0, 0, kB},
    {"holdable_teleporter", "models/powerups/holdable/teleporter.md3", 0, 0, kB},
    {"holdable_medkit", "models/powerups/holdable/medkit.md3", 0, 0, kB},
    {"team_CTF_redflag", "models/flags/r_flag.md3", 0, 0, kB},
    {"team_CTF_blueflag", "models/flags/b_flag.md3", 0, 0, kB},
});

} // namespace

std::span<const ClassModel> classModels(std::string_view game) {
  if (game == "quake") return kQuake;
  if (game == "quake2") return kQuake2;
  if (game == "quake3") return kQuake3;
  return {};
}

const ClassModel* findClassModel(std::string_view game, std::string_view classname, int spawnflags) {
  for (const ClassModel& c : classModels(game))
    if (c.classname == classname && (c.spawnflags == 0 || (spawnflags & c.spawnflags) != 0)) return &c;
  return nullptr;
}

} // namespace bt::models

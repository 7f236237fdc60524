#include "importers/game/game_profile.h"

#include "scene/names.h"

#include <algorithm>

namespace bt::game {

namespace {
// Folders from the games' own file systems (Quake's COM_InitFilesystem, Quake 2's FS_InitFilesystem,
// Hexen II's data1, Half-Life's valve, ioquake3's BASEGAME and OpenArena's baseoa).
const std::vector<GameProfile>& profiles() {
  static const std::vector<GameProfile> table{
      {"quake", "Quake", {"id1"}, {".pak"}, "gfx/palette.lmp", "", "gfx/env", "progs", "", MapDialect::Standard, {"bsp29", "bsp2", "2psb"}},
      {"hexen2", "Hexen II", {"data1"}, {".pak"}, "gfx/palette.lmp", "", "gfx/env", "models", "", MapDialect::Hexen2, {}},
      {"halflife", "Half-Life", {"valve"}, {".pak"}, "", "", "gfx/env", "models", "", MapDialect::Valve220, {"bsp30"}},
      {"quake2", "Quake 2", {"baseq2"}, {".pak"}, "pics/colormap.pcx", "textures", "env", "models", "", MapDialect::Quake2, {"ibsp38"}},
      {"quake3", "Quake 3", {"baseq3", "baseoa"}, {".pk3"}, "", "textures", "env", "models", "scripts", MapDialect::Quake3, {"ibsp46"}},
  };
  return table;
}
} // namespace

std::span<const GameProfile> gameProfiles() {
  return profiles();
}

const GameProfile* findGameProfile(std::string_view name) {
  for (const GameProfile& p : profiles())
    if (equalsIgnoreCase(p.name, name)) return &p;
  return nullptr;
}

const GameProfile* profileForFormat(std::string_view format) {
  const std::optional<MapDialect> dialect = parseDialect(format);
  // Valve 220 is also what TrenchBroom and J.A.C.K. write for Quake (LibreQuake, ericw-tools' test
  // maps): Half-Life is told by its folder (valve/) or --game, and its WAD3s carry their palettes.
  if (dialect == MapDialect::Valve220) return findGameProfile("quake");
  for (const GameProfile& p : profiles()) {
    if (std::find(p.bspVersions.begin(), p.bspVersions.end(), format) != p.bspVersions.end()) return &p;
    if (!dialect) continue;
    // The Valve-format variants of Quake 2 and Quake 3 are written by the same editors for the same games.
    if (p.dialect == *dialect || (*dialect == MapDialect::Quake2Valve && p.dialect == MapDialect::Quake2) ||
        (*dialect == MapDialect::Quake3Valve && p.dialect == MapDialect::Quake3))
      return &p;
  }
  // Daikatana keeps Quake 2's layout.
  if (dialect == MapDialect::Daikatana) return findGameProfile("quake2");
  return nullptr;
}

const GameProfile* profileForBaseGame(std::string_view folder) {
  for (const GameProfile& p : profiles())
    for (std::string_view base : p.baseGames)
      if (equalsIgnoreCase(base, folder)) return &p;
  return nullptr;
}

std::string gameProfileNames() {
  std::string names;
  for (const GameProfile& p : profiles()) names += (names.empty() ? "" : ", ") + std::string(p.name);
  return names;
}

} // namespace bt::game

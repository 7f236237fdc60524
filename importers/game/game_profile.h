// The games brushtrace knows, and where each keeps its files: the conventions of Quake-family
// installs in one place, named as the games name them.
#pragma once

#include "importers/import.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt::game {

struct GameProfile {
  std::string_view name;                      // "quake": --game, config keys, BT_QUAKE_BASEDIR
  std::string_view title;                     // "Quake", for messages
  std::vector<std::string_view> baseGames;    // the base folder(s) under the install: "id1"
  std::vector<std::string> archiveExtensions; // ".pak", ".pk3"
  std::string_view palette;                   // the game palette's file: "gfx/palette.lmp", "pics/colormap.pcx", ""
  std::string_view textures;                  // loose textures: "textures" (.wal, Quake 3 images), "" (WADs only)
  std::string_view skies;                     // skybox images: "gfx/env", "env"
  std::string_view models;                    // "progs", "models"
  std::string_view shaderScripts;             // "scripts" (Quake 3 family), ""
  MapDialect dialect;                         // what an editor writes for it
  std::vector<std::string_view> bspVersions;  // Scene::format of its levels ("bsp29", "ibsp38")
};

std::span<const GameProfile> gameProfiles();
// By --game name ("quake", "hexen2", "halflife", "quake2", "quake3"); nullptr when unknown.
const GameProfile* findGameProfile(std::string_view name);
// The game a level was made for, from its Scene::format (dialect or BSP version).
// BSP29 is Quake's (Hexen II levels share it: --game hexen2, or a level under data1/).
const GameProfile* profileForFormat(std::string_view format);
// The game whose base folder is called `folder` ("id1", "baseq2", "baseoa"), or nullptr.
const GameProfile* profileForBaseGame(std::string_view folder);
// "quake, hexen2, halflife, quake2, quake3"
std::string gameProfileNames();

} // namespace bt::game

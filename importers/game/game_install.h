// A game install as the engine sees it: the game profile, the folders searched (mods first, then
// the base game) and the file system over their loose files and archives.
#pragma once

#include "importers/game/file_system.h"
#include "importers/game/game_profile.h"
#include "importers/import.h"
#include "importers/textures/textures.h"
#include "scene/diagnostics.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace bt::game {

struct GameInstall {
  const GameProfile* profile = nullptr;        // nullptr: not known (no --game, an unusual format)
  std::filesystem::path baseDir;               // the install; empty when none was found
  std::vector<std::filesystem::path> gameDirs; // in search order
  FileSystem files;                            // over gameDirs
  Diagnostics problems;                        // game folders named but absent, archives skipped as corrupt
};

// The install a level belongs to. The profile: --game, else the game folder the level lies in
// (<install>/id1/maps/x.map), else the level's format (Scene::format: dialect or BSP version).
// The install: --basedir, else the level's path, else options.configuredBaseDirs[profile].
// `levelPath` may be "archive.pak:maps/x.bsp" (the archive's folder is then the level's game
// folder) or empty. Never throws: a corrupt archive in a game folder is skipped and reported in
// `problems`.
GameInstall openGameInstall(const GameOptions& options, const std::string& levelPath, std::string_view format);

// A level named without a path ("e1m1", "oa_dm1"): maps/<name>.bsp in the install of
// options.game (or of every configured game, when no --game). Returns the name to import
// ("/q/id1/pak0.pak:maps/e1m1.bsp" or a loose file); nullopt when `name` is not such a name
// or no install holds it.
std::optional<std::string> findLevelByName(const GameOptions& options, const std::string& name);

// The palette of the install's game that 8-bit textures index: the game folder's own file
// (gfx/palette.lmp, Quake 2's pics/colormap.pcx) through the file system, else the built-in one
// (default_palettes.h) with a note in `diagnostics`. `quake2`: the .wal palette is wanted, whatever
// the profile. `readFrom` receives the file on disk that gave it (empty for the built-in one).
std::optional<Palette> installPalette(const GameInstall& install, bool quake2, const std::string& sceneFile, Diagnostics& diagnostics,
                                      std::string* readFrom);

} // namespace bt::game

// The importers' front door: open any level file the tool understands and get a Scene.
#pragma once

#include "scene/curves.h"
#include "scene/scene.h"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace bt {

// The .map dialects. TrenchBroom's names for them are used in `// Format:` headers.
enum class MapDialect { Standard, Valve220, Quake2, Quake2Valve, Quake3, Quake3Valve, Hexen2, Daikatana };

// "standard", "valve220", "quake2", "quake2-valve", "quake3", "quake3-valve", "hexen2", "daikatana"
const char* toString(MapDialect dialect);
std::optional<MapDialect> parseDialect(std::string_view name);

// Where the game's own files are: importers/game/game_install.h. Every field is optional: a
// level inside a game folder (<install>/id1/maps/x.map) finds its game by itself.
struct GameOptions {
  std::string game;              // --game: a profile (quake, hexen2, halflife, quake2, quake3); empty: from the level
  std::string baseDir;           // --basedir: the install, the folder holding id1/, baseq2/, valve/, baseoa/ ...
  std::vector<std::string> mods; // --mod: game folders under baseDir searched before the base game, first given first
  // Each game's install as the user configured it (config file, environment), by profile name;
  // read by the front end, used when neither --basedir nor the level's own path names one.
  std::map<std::string, std::string> configuredBaseDirs;
};

// Where textures are looked for, in order. See importers/textures.h.
struct TextureSearch {
  std::vector<std::string> wads;        // --wad, then the map's "wad" key (relative to the map)
  std::vector<std::string> textureDirs; // --textures: loose images
  std::string palette;                  // --palette: a 768-byte palette.lmp; empty = look beside the wads
  bool load = true;                     // false: geometry only, every material left as a placeholder
  GameOptions game;                     // the game install, searched after the map's own folders
};

struct ImportOptions {
  std::optional<MapDialect> dialect; // --dialect forces one; otherwise detected
  TextureSearch textures;
  // Called once, as soon as the importer has the level's entities, brushes and faces, before it
  // loads the textures: with a scene that holds them (its materials named, not loaded). A front
  // end acts on the level's lights and parts meanwhile (renderer/gl LevelPreparation starts the
  // GL program they need: on lq_e4m3 the textures are about half of the import).
  std::function<void(const Scene&)> entitiesRead;
  // Quake 3 curves: the most a tessellated chord may lie off the curve (scene/curves.h; the
  // engine's r_subdivisions). Tests pass less for a finer reference.
  double curveMaxError = kPatchMaxError;
};

// Opens a .map or .bsp (or "archive.pak:maps/x.bsp", "archive.pk3:maps/x.bsp", or a bare level
// name such as "e1m1" that the game install of options.textures.game holds) and returns its scene with materials
// resolved. Throws ImportError when the file cannot be imported at all; everything skipped on
// the way (invalid brushes, missing textures) is in Scene::diagnostics.
Scene importScene(const std::string& path, const ImportOptions& options);
// The same with options.entitiesRead set to `entitiesRead` (the GL front ends' level import,
// renderer/gl LevelPreparation).
Scene importScene(const std::string& path, ImportOptions options, std::function<void(const Scene&)> entitiesRead);

} // namespace bt

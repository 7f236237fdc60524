// The importers' front door: open any level file the tool understands and get a Scene.
#pragma once

#include "scene/scene.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace bt {

// The .map dialects. TrenchBroom's names for them are used in `// Format:` headers.
enum class MapDialect { Standard, Valve220, Quake2, Quake2Valve, Quake3, Quake3Valve, Hexen2, Daikatana };

// "standard", "valve220", "quake2", "quake2-valve", "quake3", "quake3-valve", "hexen2", "daikatana"
const char* toString(MapDialect dialect);
std::optional<MapDialect> parseDialect(std::string_view name);

// Where textures are looked for, in order. See importers/textures.h.
struct TextureSearch {
  std::vector<std::string> wads;        // --wad, then the map's "wad" key (relative to the map)
  std::vector<std::string> textureDirs; // --textures: loose images
  std::string palette;                  // --palette: a 768-byte palette.lmp; empty = look beside the wads
  bool load = true;                     // false: geometry only, every material left as a placeholder
};

struct ImportOptions {
  std::optional<MapDialect> dialect; // --dialect forces one; otherwise detected
  TextureSearch textures;
  // Called once, before the textures are loaded, with the scene's entities as they will be
  // returned (its faces' texture frames may still change; materials are names only then). Loading textures is most of a
  // textured import (lq_e4m3: 130 PNGs); a front end acts on the level's lights meanwhile
  // (renderer/gl LevelPreparation starts the GL programs they need).
  std::function<void(const Scene&)> entitiesRead;
};

// Opens a .map or .bsp (or "archive.pk3:maps/x.bsp") and returns its scene with materials
// resolved. Throws ImportError when the file cannot be imported at all; everything skipped on
// the way (invalid brushes, missing textures) is in Scene::diagnostics.
Scene importScene(const std::string& path, const ImportOptions& options);

} // namespace bt

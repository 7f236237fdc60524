#include "importers/import.h"

#include "importers/bsp/bsp_import.h"
#include "importers/bsp/pk3.h"
#include "importers/game/game_install.h"
#include "importers/map/map_scene.h"
#include "importers/models/entity_models.h"
#include "importers/textures/textures.h"
#include "quake/bspfile_q2.h"
#include "scene/names.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>

namespace bt {

namespace {
struct DialectName {
  MapDialect dialect;
  const char* name;
};
constexpr std::array<DialectName, 8> kDialectNames{{
    {MapDialect::Standard, "standard"},
    {MapDialect::Valve220, "valve220"},
    {MapDialect::Quake2, "quake2"},
    {MapDialect::Quake2Valve, "quake2-valve"},
    {MapDialect::Quake3, "quake3"},
    {MapDialect::Quake3Valve, "quake3-valve"},
    {MapDialect::Hexen2, "hexen2"},
    {MapDialect::Daikatana, "daikatana"},
}};
} // namespace

const char* toString(MapDialect dialect) {
  for (const auto& d : kDialectNames)
    if (d.dialect == dialect) return d.name;
  return "unknown";
}

std::optional<MapDialect> parseDialect(std::string_view name) {
  for (const auto& d : kDialectNames)
    if (name == d.name) return d.dialect;
  return std::nullopt;
}

namespace {
std::string lowercaseExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}
} // namespace

namespace {
// Physical mode's glowing liquids (lighting/README.md, "Liquids"): lava and teleporters emit
// their whole texture, as fullbright texels do (their emissive map becomes the base colour).
// Faithful mode draws liquids unlit, so it shows the same.
void makeLiquidsGlow(Scene& scene) {
  std::vector<bool> glows(scene.materials.size(), false);
  for (const Face& face : scene.faces) {
    if (face.material >= glows.size()) continue;
    const std::string name = lowercase(face.texture);
    const std::string_view base = std::string_view(name).substr(name.find_last_of('/') + 1);
    const bool lavaContents = face.surface && (face.surface->contents & quake::q2::CONTENTS_LAVA);
    glows[face.material] = glows[face.material] || base.starts_with("*lava") || base.starts_with("*tele") || lavaContents;
  }
  for (size_t m = 0; m < glows.size(); ++m)
    if (glows[m] && !scene.materials[m].baseColor.empty()) scene.materials[m].emissive = scene.materials[m].baseColor;
}

// "e1m1" (or "e1m1.bsp"): a name, not a path, as the engines' `map e1m1` takes it.
bool isBareLevelName(const std::string& path) {
  if (path.empty() || path.find_first_of("/\\:") != std::string::npos) return false;
  const std::string ext = lowercaseExtension(path);
  return ext.empty() || ext == ".bsp";
}
} // namespace

Scene importScene(const std::string& path, const ImportOptions& options) {
  std::error_code ec;
  if (isBareLevelName(path) && !std::filesystem::exists(path, ec)) {
    if (auto found = game::findLevelByName(options.textures.game, path)) return importScene(*found, options);
    const std::string stem = std::filesystem::path(path).stem().string();
    throw ImportError(Diagnostic{Severity::Error, path, 0, 0,
                                 "no such file, and no game install holds maps/" + stem +
                                     ".bsp (name the game and its folder: --game NAME --basedir DIR, or set it once "
                                     "with `brushtrace config set GAME.basedir DIR`)"});
  }
  // Compiled levels: "x.bsp", "archive.pak:maps/x.bsp" or "archive.pk3:maps/x.bsp".
  // The game the user names rules what the level means (lighting/game_rules.h gameOf). Then
  // the models the game shows at the level's point entities, from its install.
  const auto named = [&](Scene scene) {
    scene.game = options.textures.game.game;
    models::addEntityModels(scene, path, options);
    makeLiquidsGlow(scene);
    return scene;
  };
  if (bsp::splitArchivePath(path) || lowercaseExtension(path) == ".bsp") return named(bsp::importBsp(path, options));
  if (lowercaseExtension(path) == ".map") return named(map::importMap(path, options)); // materials included
  throw ImportError(
      Diagnostic{Severity::Error, path, 0, 0,
                 "not a level brushtrace reads (expected .map, .bsp, archive.pak:maps/name.bsp or archive.pk3:maps/name.bsp)"});
}

Scene importScene(const std::string& path, ImportOptions options, std::function<void(const Scene&)> entitiesRead) {
  options.entitiesRead = std::move(entitiesRead);
  return importScene(path, options);
}

} // namespace bt

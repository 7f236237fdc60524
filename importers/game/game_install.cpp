#include "importers/game/game_install.h"

#include "importers/game/default_palettes.h"
#include "scene/names.h"

#include <fmt/format.h>

namespace bt::game {

namespace fs = std::filesystem;

namespace {

bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

// The game folder a level lies in: the folder holding the archive it is in, or the parent of
// its maps/ folder. Empty when the level is elsewhere.
fs::path levelGameDir(const std::string& levelPath) {
  if (levelPath.empty()) return {};
  std::error_code ec;
  if (const auto archive = splitArchivePath(levelPath)) return fs::absolute(archive->archive, ec).parent_path();
  const fs::path level = fs::absolute(levelPath, ec).lexically_normal();
  if (ec || !equalsIgnoreCase(level.parent_path().filename().string(), "maps")) return {};
  return level.parent_path().parent_path();
}

// A folder named like a base game ("id1") or a game folder beside one ("ad" beside "id1"): the
// install is its parent. `profile`, when null, becomes the game of that base folder.
fs::path installOf(const fs::path& gameDir, const GameProfile*& profile) {
  if (gameDir.empty()) return {};
  if (const GameProfile* p = profileForBaseGame(gameDir.filename().string())) {
    if (!profile) profile = p;
    return gameDir.parent_path();
  }
  for (const GameProfile& p : gameProfiles())
    for (std::string_view base : p.baseGames)
      if ((!profile || profile == &p) && isDir(gameDir.parent_path() / base)) {
        profile = &p;
        return gameDir.parent_path();
      }
  return {};
}

// --basedir may name the install or, forgivingly, its base game folder (".../quake/id1").
fs::path normaliseBaseDir(const fs::path& dir, const GameProfile* profile) {
  if (!profile) return dir;
  for (std::string_view base : profile->baseGames)
    if (equalsIgnoreCase(dir.filename().string(), base) && !isDir(dir / base)) return dir.parent_path();
  return dir;
}

// A profile guessed from the format yields to the install's own base folder: a Valve 220 map
// with --basedir naming a Half-Life install is Half-Life's.
const GameProfile* profileInstalledAt(const fs::path& baseDir, const GameProfile* guess) {
  if (baseDir.empty()) return guess;
  if (guess)
    for (std::string_view base : guess->baseGames)
      if (isDir(baseDir / base)) return guess;
  for (const GameProfile& p : gameProfiles())
    for (std::string_view base : p.baseGames)
      if (isDir(baseDir / base)) return &p;
  return guess;
}

void addGameDir(GameInstall& install, const fs::path& dir) {
  for (const fs::path& d : install.gameDirs)
    if (d == dir) return;
  install.gameDirs.push_back(dir);
}

} // namespace

GameInstall openGameInstall(const GameOptions& options, const std::string& levelPath, std::string_view format) {
  GameInstall install;
  if (!options.game.empty()) install.profile = findGameProfile(options.game);
  const fs::path levelDir = levelGameDir(levelPath);
  const fs::path levelInstall = installOf(levelDir, install.profile);
  if (!install.profile) install.profile = profileForFormat(format);

  if (!options.baseDir.empty())
    install.baseDir = normaliseBaseDir(fs::path(options.baseDir), install.profile);
  else if (!levelInstall.empty())
    install.baseDir = levelInstall;
  else if (install.profile)
    if (auto it = options.configuredBaseDirs.find(std::string(install.profile->name)); it != options.configuredBaseDirs.end())
      install.baseDir = it->second;
  if (options.game.empty() && levelInstall.empty()) install.profile = profileInstalledAt(install.baseDir, install.profile);
  if (!install.baseDir.empty() && !isDir(install.baseDir))
    install.problems.push_back({Severity::Warning, install.baseDir.string(), 0, 0,
                                "the game install (--basedir, BT_<GAME>_BASEDIR or the config file) is not a folder"});

  // The engine's order: mods, the level's own game folder (a mod when it is not the base), the base game.
  for (const std::string& mod : options.mods) {
    const fs::path dir = install.baseDir / mod;
    if (isDir(dir))
      addGameDir(install, dir);
    else
      install.problems.push_back({Severity::Warning, dir.string(), 0, 0, "mod folder (--mod) not found"});
  }
  if (!levelDir.empty()) addGameDir(install, levelDir);
  if (install.profile && !install.baseDir.empty())
    for (std::string_view base : install.profile->baseGames)
      if (isDir(install.baseDir / base)) addGameDir(install, install.baseDir / base);

  static const std::vector<std::string> kAnyArchive{".pak", ".pk3"};
  const std::vector<std::string>& kinds = install.profile ? install.profile->archiveExtensions : kAnyArchive;
  for (const fs::path& dir : install.gameDirs) install.files.addGameDir(dir, kinds);
  for (const Diagnostic& d : install.files.skipped()) install.problems.push_back(d);
  return install;
}

std::optional<std::string> findLevelByName(const GameOptions& options, const std::string& name) {
  if (name.empty() || name.find_first_of("/\\:") != std::string::npos) return std::nullopt;
  const std::string stem = lowercase(fs::path(name).extension().string()) == ".bsp" ? fs::path(name).stem().string() : name;
  const std::string entry = "maps/" + stem + ".bsp";
  std::vector<const GameProfile*> candidates;
  if (!options.game.empty())
    candidates.push_back(findGameProfile(options.game));
  else
    for (const GameProfile& p : gameProfiles()) candidates.push_back(&p);
  for (const GameProfile* profile : candidates) {
    if (!profile) continue;
    GameOptions forGame = options;
    forGame.game = profile->name;
    if (options.game.empty() && options.baseDir.empty() && !options.configuredBaseDirs.contains(std::string(profile->name))) continue;
    const GameInstall install = openGameInstall(forGame, "", "");
    if (auto where = install.files.describe(entry)) return where;
  }
  return std::nullopt;
}

std::optional<Palette> installPalette(const GameInstall& install, bool quake2, const std::string& sceneFile, Diagnostics& diagnostics,
                                      std::string* readFrom) {
  const GameProfile* quake2Profile = findGameProfile("quake2");
  const GameProfile* profile = quake2 ? quake2Profile : install.profile;
  // WAD2 textures are Quake's whatever the level's format says (a Half-Life or Quake 2 map
  // that names one); Hexen II keeps its own.
  if (!profile || profile->palette.empty() || (!quake2 && profile == quake2Profile)) profile = findGameProfile("quake");
  const std::string file(profile->palette);
  if (auto bytes = install.files.read(file)) {
    try {
      Palette palette = paletteFromBytes(*bytes, *install.files.describe(file));
      if (readFrom) *readFrom = install.files.fileHolding(file)->string();
      return palette;
    } catch (const ImportError& e) {
      diagnostics.push_back({Severity::Warning, e.diagnostic().file, 0, 0, "palette not usable: " + e.diagnostic().message});
    }
  }
  std::optional<Palette> builtIn = builtinPalette(profile->name);
  if (builtIn)
    diagnostics.push_back({Severity::Warning, sceneFile, 0, 0,
                           fmt::format("no {} in the game folders (give --basedir, or --palette): using brushtrace's "
                                       "built-in {} palette",
                                       file, profile->title)});
  if (readFrom) readFrom->clear();
  return builtIn;
}

} // namespace bt::game

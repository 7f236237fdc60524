#include "app/commands.h"

#include "importers/game/archive.h"
#include "importers/game/game_profile.h"
#include "importers/textures/textures.h"
#include "scene/names.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace bt::app {

void addImportOptions(CLI::App& command, ImportOptions& options) {
  command
      .add_option_function<std::string>(
          "--dialect",
          [&options](const std::string& name) {
            options.dialect = parseDialect(name);
            if (!options.dialect) throw CLI::ValidationError("--dialect", "unknown dialect '" + name + "'");
          },
          "Force the .map dialect: standard|valve220|quake2|quake2-valve|quake3|quake3-valve|hexen2|daikatana")
      ->type_name("DIALECT");
  command.add_option("--wad", options.textures.wads, "WAD file to search for textures (repeatable), before the map's \"wad\" key")
      ->type_name("FILE")
      ->check(CLI::ExistingFile);
  command.add_option("--textures", options.textures.textureDirs, "Folder of loose texture images <name>.png|tga|jpg (repeatable)")
      ->type_name("DIR")
      ->check(CLI::ExistingDirectory);
  command.add_option("--palette", options.textures.palette, "Quake palette.lmp (768 bytes) for WAD2 textures")
      ->type_name("FILE")
      ->check(CLI::ExistingFile);
  command.add_flag_callback(
      "--no-textures", [&options] { options.textures.load = false; }, "Import geometry only: every texture is a placeholder");
  addGameOptions(command, options.textures.game);
}

void addGameOptions(CLI::App& command, GameOptions& game) {
  command
      .add_option_function<std::string>(
          "--game",
          [&game](const std::string& name) {
            if (!game::findGameProfile(name))
              throw CLI::ValidationError("--game", fmt::format("unknown game '{}' (one of {})", name, game::gameProfileNames()));
            game.game = name;
          },
          "The game: quake|hexen2|halflife|quake2|quake3 (otherwise from the level's format and folder)")
      ->type_name("NAME");
  command
      .add_option("--basedir", game.baseDir,
                  "The game install: the folder holding id1/, baseq2/, valve/, baseq3/ or baseoa/ "
                  "(default: the level's own, else `brushtrace config`)")
      ->type_name("DIR");
  command.add_option("--mod", game.mods, "A game folder under --basedir searched before the base game (repeatable, first first)")
      ->type_name("NAME");
  // The user's settings and environment are read here, at the edge, once the command line is parsed.
  command.parse_complete_callback([&game] { game.configuredBaseDirs = configuredBaseDirs(); });
}

void addSizeOption(CLI::App& command, ImageSize& size, const std::string& help) {
  command
      .add_option_function<std::string>(
          "--size",
          [&size](const std::string& text) {
            int width = 0, height = 0;
            char x = 0, rest = 0;
            if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' || width <= 0 || height <= 0 ||
                width > 16384 || height > 16384)
              throw CLI::ValidationError("--size", "expected WIDTHxHEIGHT (1..16384 each), got '" + text + "'");
            size = {width, height};
          },
          help)
      ->type_name("WxH")
      ->default_str(std::to_string(size.width) + "x" + std::to_string(size.height));
}

void addClampIndirectOption(CLI::App& command, float& clampIndirect) {
  command
      .add_option("--clamp-indirect", clampIndirect,
                  "Physical lighting: after the first surface, point lights count as at least this many units away "
                  "(removes fireflies; 0 = off)")
      ->check(CLI::Range(0.0f, 4096.0f))
      ->type_name("UNITS")
      ->capture_default_str();
}

namespace {
bool hasExtension(const std::string& name, std::initializer_list<std::string_view> extensions) {
  const std::string ext = lowercase(std::filesystem::path(name).extension().string());
  return std::find(extensions.begin(), extensions.end(), ext) != extensions.end();
}
} // namespace

bool printArchiveContents(const std::string& path, bool json) {
  if (!game::isArchiveName(path) || game::splitArchivePath(path)) return false;
  const std::unique_ptr<game::Archive> archive = game::openArchive(path); // throws naming the archive
  nlohmann::ordered_json levels = nlohmann::ordered_json::array(), textures = nlohmann::ordered_json::array();
  nlohmann::ordered_json wads = nlohmann::ordered_json::array();
  for (const std::string& name : archive->names()) {
    const std::string lower = lowercase(name);
    if (lower.starts_with("maps/") && hasExtension(name, {".bsp"}))
      levels.push_back(name);
    else if (lower.starts_with("textures/") && hasExtension(name, {".wal", ".tga", ".jpg", ".jpeg", ".png"}))
      textures.push_back(name);
    else if (hasExtension(name, {".wad"})) {
      const WadFile wad = WadFile::fromBytes(*archive->read(name), path + ":" + name);
      nlohmann::ordered_json names = nlohmann::ordered_json::array();
      for (const WadFile::Entry& e : wad.entries())
        if (e.type == WadFile::kTypeMiptexWad2 || e.type == WadFile::kTypeMiptexWad3) names.push_back(e.name);
      wads.push_back({{"path", name}, {"textures", names}});
    }
  }
  if (json) {
    fmt::print("{}\n", nlohmann::ordered_json{{"archive", path}, {"levels", levels}, {"textures", textures}, {"wads", wads}}.dump(1));
    return true;
  }
  fmt::print("{}\n  levels    {}\n", path, levels.size());
  for (const auto& level : levels) fmt::print("    {}\n", level.get<std::string>());
  fmt::print("  textures  {}\n", textures.size());
  for (const auto& texture : textures) fmt::print("    {}\n", texture.get<std::string>());
  fmt::print("  wads      {}\n", wads.size());
  for (const auto& wad : wads) {
    fmt::print("    {} ({} textures)\n", wad["path"].get<std::string>(), wad["textures"].size());
    for (const auto& name : wad["textures"]) fmt::print("      {}\n", name.get<std::string>());
  }
  return true;
}

} // namespace bt::app

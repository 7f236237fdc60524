// brushtrace config set|get|list: the user's settings file, which remembers each game's install
// so that a mapper names it once. The file is $XDG_CONFIG_HOME/brushtrace/config.json (else
// ~/.config/brushtrace/config.json):  { "quake": { "basedir": "/home/me/quake" }, ... }
// Environment variables (BT_QUAKE_BASEDIR, ...) override it, and the command line overrides both.
#include "app/commands.h"

#include "importers/game/game_profile.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace bt::app {

namespace fs = std::filesystem;

namespace {

fs::path configFile() {
  return userConfigFolder() / "config.json";
}

// The file's settings; an empty object when there is no file yet. Throws naming the file when
// it is not a JSON object.
nlohmann::json readConfig(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return nlohmann::json::object();
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the configuration file");
  try {
    nlohmann::json config = nlohmann::json::parse(in);
    if (!config.is_object()) throw std::runtime_error("not a JSON object");
    return config;
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: not a brushtrace configuration file: {}", file.string(), e.what()));
  }
}

void writeConfig(const fs::path& file, const nlohmann::json& config) {
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  const fs::path temporary = file.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << config.dump(2) << "\n";
    if (!out) throw std::runtime_error(temporary.string() + ": cannot write the configuration file");
  }
  fs::rename(temporary, file, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw std::runtime_error(file.string() + ": cannot write the configuration file");
  }
}

// "quake.basedir" -> {"quake", "basedir"}; a usage error for anything else.
std::pair<std::string, std::string> splitKey(const std::string& key) {
  const size_t dot = key.find('.');
  const std::string gameName = key.substr(0, dot);
  if (dot == std::string::npos || !game::findGameProfile(gameName) || key.substr(dot + 1) != "basedir")
    throw CLI::ValidationError(
        "KEY", fmt::format("unknown setting '{}': the settings are GAME.basedir, GAME one of {}", key, game::gameProfileNames()));
  return {gameName, "basedir"};
}

std::string environmentName(std::string_view gameName) {
  std::string name = "BT_";
  for (char c : gameName) name += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return name + "_BASEDIR";
}

} // namespace

fs::path userConfigFolder() {
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) return fs::path(xdg) / "brushtrace";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".config" / "brushtrace";
  throw std::runtime_error("no configuration folder: neither XDG_CONFIG_HOME nor HOME is set");
}

std::map<std::string, std::string> configuredBaseDirs() {
  std::map<std::string, std::string> dirs;
  try {
    const nlohmann::json config = readConfig(configFile());
    for (const auto& [gameName, settings] : config.items())
      if (settings.is_object() && settings.contains("basedir") && settings["basedir"].is_string())
        dirs[gameName] = settings["basedir"].get<std::string>();
  } catch (const std::runtime_error& e) {
    fmt::print(stderr, "brushtrace: {} (ignored)\n", e.what());
  }
  for (const game::GameProfile& p : game::gameProfiles())
    if (const char* dir = std::getenv(environmentName(p.name).c_str()); dir && *dir) dirs[std::string(p.name)] = dir;
  return dirs;
}

void addConfigCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand("config", "Remember each game's install: config set quake.basedir DIR, get KEY, list");
  cmd->require_subcommand(1);
  auto key = std::make_shared<std::string>();
  auto value = std::make_shared<std::string>();

  CLI::App* set = cmd->add_subcommand("set", "Set GAME.basedir (GAME: quake, hexen2, halflife, quake2, quake3)");
  set->add_option("KEY", *key, "GAME.basedir")->required();
  set->add_option("VALUE", *value, "The folder holding the game's base folder (id1/, baseq2/, ...)")->required();
  set->callback([key, value, &exitCode] {
    const auto [gameName, setting] = splitKey(*key);
    const fs::path file = configFile();
    nlohmann::json config = readConfig(file);
    std::error_code ec;
    const fs::path dir = fs::absolute(*value, ec).lexically_normal();
    if (!fs::is_directory(dir, ec)) fmt::print(stderr, "brushtrace: warning: {} is not a folder (saved anyway)\n", dir.string());
    config[gameName][setting] = dir.string();
    writeConfig(file, config);
    exitCode = 0;
  });

  CLI::App* get = cmd->add_subcommand("get", "Print one setting (with the environment's override)");
  get->add_option("KEY", *key, "GAME.basedir")->required();
  get->callback([key, &exitCode] {
    const auto [gameName, setting] = splitKey(*key);
    const auto dirs = configuredBaseDirs();
    const auto it = dirs.find(gameName);
    if (it == dirs.end()) {
      fmt::print(stderr, "brushtrace: {} is not set\n", *key);
      exitCode = 1;
      return;
    }
    fmt::print("{}\n", it->second);
    exitCode = 0;
  });

  CLI::App* list = cmd->add_subcommand("list", "Print every setting and where the file is");
  list->callback([&exitCode] {
    fmt::print("# {}\n", configFile().string());
    for (const auto& [gameName, dir] : configuredBaseDirs()) fmt::print("{}.basedir = {}\n", gameName, dir);
    exitCode = 0;
  });
}

} // namespace bt::app

// brushtrace's subcommands. Each lives in its own cmd_*.cpp and registers itself on the
// CLI11 app; the callback stores the exit code in `exitCode` (0 success, 1 the job failed).
#pragma once

#include "importers/import.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>

namespace bt::app {

// --dialect, --wad, --textures, --palette, --no-textures and the game options: every command
// that imports a level.
void addImportOptions(CLI::App& command, ImportOptions& options);
// --game NAME, --basedir DIR, --mod NAME; the configured installs are read after the parse.
void addGameOptions(CLI::App& command, GameOptions& game);

// The user's settings folder: $XDG_CONFIG_HOME/brushtrace, else ~/.config/brushtrace; throws
// when neither is set (cmd_config.cpp). config.json and the viewer's bookmarks.json live there.
std::filesystem::path userConfigFolder();
// Each game's install from the user's config file, overridden by BT_<GAME>_BASEDIR (cmd_config.cpp).
std::map<std::string, std::string> configuredBaseDirs();
// brushtrace config set|get|list (cmd_config.cpp).
void addConfigCommand(CLI::App& app, int& exitCode);
// `info` on an archive (pak0.pak, x.pk3): the levels and textures it holds. False when `path`
// is not an archive of its own (a level, or "archive:maps/x.bsp").
bool printArchiveContents(const std::string& path, bool json);

// --size WIDTHxHEIGHT into `size`, checked while the command line is parsed, so a malformed
// size is a usage error (exit 2) like any other bad option.
struct ImageSize {
  int width = 0;
  int height = 0;
};
void addSizeOption(CLI::App& command, ImageSize& size, const std::string& help);

// --clamp-indirect UNITS (render, view, bench): physical mode's firefly clamp, the nearest a
// point light counts as to a surface met after the camera's (IntegratorSettings::clampIndirect).
void addClampIndirectOption(CLI::App& command, float& clampIndirect);

// The level `render` and `view` open when given none: maps/start.map.
std::string defaultMapPath();

// What `info --json` prints for a level: dialect, counts, bounds, textures, problems (cmd_info.cpp).
nlohmann::ordered_json infoJson(const Scene& scene);

// info MAP [--json], dump MAP --json, convert IN -o OUT [--dialect D] [--in-place]
void addInfoCommand(CLI::App& app, int& exitCode);
void addDumpCommand(CLI::App& app, int& exitCode);
void addConvertCommand(CLI::App& app, int& exitCode);
// brushtrace render: path-trace a level (app/cmd_render.cpp).
void addRenderCommand(CLI::App& app, int& exitCode);
// brushtrace bench [MAP] (cmd_bench.cpp): GL tracer throughput.
void addBenchCommand(CLI::App& app, int& exitCode);
// brushtrace view [MAP] (cmd_view.cpp): the live viewer.
void addViewCommand(CLI::App& app, int& exitCode);
// brushtrace batch (cmd_batch.cpp): many levels' checks and renders, restartable and shardable.
void addBatchCommand(CLI::App& app, int& exitCode);

} // namespace bt::app

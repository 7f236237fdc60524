// The checks of the command line made while it is parsed, before any work starts: what can be
// known wrong from the options alone (a level that is not there, an output that cannot be
// written, a malformed camera) is a usage error, exit 2, with a message naming the option. What
// only the work finds (a malformed level, a full disk) fails the job, exit 1. One place, so that
// every command checks its options the same way.
#pragma once

#include "renderer/camera.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace bt::app {

// A level to import: the file exists and is a file.
CLI::Validator levelFile();
// A file to write: its folder exists and a file can be created in it.
CLI::Validator outputFile();
// An image `render` writes: outputFile() with a .png or .exr name.
CLI::Validator imageFile();
// A folder files are written into: it exists and a file can be created in it.
CLI::Validator writableFolder();

// A number above 0 (--spp, --time, --seconds); CLI11's PositiveNumber names a range up to 1.8e308.
CLI::Validator positive();

// --camera in every form parseCameraPose reads, parsed while the command line is.
void addCameraOption(CLI::App& command, std::optional<CameraPose>& pose, const std::string& help);

// What `brushtrace` alone and a mistyped command print: the commands with their descriptions,
// and for a near miss of one (`rendr`), "did you mean 'render'?".
std::string commandList(const CLI::App& app);
bool isCommand(const CLI::App& app, const std::string& name);
std::optional<std::string> nearestCommand(const CLI::App& app, std::string_view typed);

} // namespace bt::app

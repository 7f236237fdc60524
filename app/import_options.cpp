#include "app/commands.h"

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
  command.add_option("--palette", options.textures.palette, "Quake palette.lmp (768 bytes) for WAD2 textures")->type_name("FILE")->check(CLI::ExistingFile);
  command.add_flag_callback("--no-textures", [&options] { options.textures.load = false; }, "Import geometry only: every texture is a placeholder");
}

void addSizeOption(CLI::App& command, ImageSize& size, const std::string& help) {
  command
      .add_option_function<std::string>(
          "--size",
          [&size](const std::string& text) {
            int width = 0, height = 0;
            char x = 0, rest = 0;
            if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' || width <= 0 ||
                height <= 0 || width > 16384 || height > 16384)
              throw CLI::ValidationError("--size", "expected WIDTHxHEIGHT (1..16384 each), got '" + text + "'");
            size = {width, height};
          },
          help)
      ->type_name("WxH")
      ->default_str(std::to_string(size.width) + "x" + std::to_string(size.height));
}

} // namespace bt::app

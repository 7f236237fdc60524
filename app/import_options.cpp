#include "app/commands.h"

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
      ->type_name("FILE");
  command.add_option("--textures", options.textures.textureDirs, "Folder of loose texture images <name>.png|tga|jpg (repeatable)")
      ->type_name("DIR");
  command.add_option("--palette", options.textures.palette, "Quake palette.lmp (768 bytes) for WAD2 textures")->type_name("FILE");
  command.add_flag_callback("--no-textures", [&options] { options.textures.load = false; }, "Import geometry only: every texture is a placeholder");
}

} // namespace bt::app

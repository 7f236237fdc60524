// brushtrace: open Quake-family levels and preview their lighting.
#include "app/commands.h"

#include <fmt/format.h>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  CLI::App app{"brushtrace: import Quake-family levels (.map, .bsp) and preview their lighting"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "brushtrace 0.1.0");

  int exitCode = 0;
  bt::app::addInfoCommand(app, exitCode);
  bt::app::addDumpCommand(app, exitCode);
  bt::app::addConvertCommand(app, exitCode);
  bt::app::addRenderCommand(app, exitCode);
  bt::app::addBenchCommand(app, exitCode);
  bt::app::addViewCommand(app, exitCode);
  bt::app::addConfigCommand(app, exitCode);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or --help); the README's contract says usage errors exit 2.
    const int cliCode = app.exit(e);
    return cliCode == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    // Importers report bad input as ImportError with file:line:col already in the text.
    fmt::print(stderr, "brushtrace: {}\n", e.what());
    return 1;
  }
  return exitCode;
}

// brushtrace: open Quake-family levels and preview their lighting.
#include "app/commands.h"
#include "app/usage_checks.h"

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
  bt::app::addBatchCommand(app, exitCode);

  // CLI11 alone says only "A subcommand is required" or that an argument was not expected.
  if (argc < 2 || (argv[1][0] != '-' && !bt::app::isCommand(app, argv[1]))) {
    if (argc < 2)
      fmt::print(stderr, "brushtrace: a command is required\n");
    else if (const auto near = bt::app::nearestCommand(app, argv[1]))
      fmt::print(stderr, "brushtrace: unknown command '{}'; did you mean '{}'?\n", argv[1], *near);
    else
      fmt::print(stderr, "brushtrace: unknown command '{}'\n", argv[1]);
    fmt::print(stderr, "{}", bt::app::commandList(app));
    return 2;
  }

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

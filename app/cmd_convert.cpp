// brushtrace convert IN -o OUT [--dialect D] [--in-place]: rewrite a .map, in its own dialect or another.
#include "app/commands.h"
#include "app/usage_checks.h"

#include "importers/map/map_parser.h"
#include "importers/map/map_writer.h"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

namespace bt::app {

void addConvertCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand("convert", "Rewrite a .map in another dialect (by default its own, losslessly)");
  struct Args {
    std::string input;
    std::string output;
    std::optional<MapDialect> dialect;
    std::optional<MapDialect> inputDialect;
    bool inPlace = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("IN", args->input, "The .map to read")->required()->check(levelFile());
  cmd->add_option("-o,--output", args->output, "The .map to write")->required()->check(outputFile());
  auto dialectOption = [](std::optional<MapDialect>& into, const char* name) {
    return [&into, name](const std::string& value) {
      into = parseDialect(value);
      if (!into) throw CLI::ValidationError(name, "unknown dialect '" + value + "'");
    };
  };
  cmd->add_option_function<std::string>("--dialect", dialectOption(args->dialect, "--dialect"),
                                        "Dialect to write: standard|valve220|quake2|quake2-valve|quake3|quake3-valve|hexen2|daikatana "
                                        "(default: the input's)")
      ->type_name("DIALECT");
  cmd->add_option_function<std::string>("--from", dialectOption(args->inputDialect, "--from"),
                                        "Force the input's dialect instead of detecting it")
      ->type_name("DIALECT");
  cmd->add_flag("--in-place", args->inPlace, "Allow OUT to be the same file as IN");
  cmd->callback([args, &exitCode] {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!args->inPlace && fs::exists(args->output, ec) && fs::equivalent(args->input, args->output, ec)) {
      fmt::print(stderr, "brushtrace: {}: refusing to overwrite the input (pass --in-place to allow it)\n", args->output);
      exitCode = 1;
      return;
    }
    const map::MapDocument doc = map::readMapFile(args->input, args->inputDialect);
    Diagnostics report;
    const map::MapDocument converted = map::convertDocument(doc, args->dialect.value_or(doc.dialect), report);
    map::writeFileAtomically(args->output, map::writeMap(converted));
    size_t inexact = 0;
    for (const Diagnostic& d : report) {
      fmt::print(stderr, "{}\n", format(d));
      inexact += d.severity == Severity::Warning;
    }
    fmt::print(stderr, "{}: {} -> {}, {} face(s) not represented exactly\n", args->output, toString(doc.dialect),
               toString(converted.dialect), inexact);
    exitCode = 0;
  });
}

} // namespace bt::app

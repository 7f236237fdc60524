// brushtrace view [MAP]: the live viewer (viewer/viewer.h).
#include "app/commands.h"
#include "app/usage_checks.h"
#include "viewer/viewer.h"

#include <fmt/format.h>

#include <cstdio>

namespace bt::app {

namespace {

struct ViewCommand {
  ViewerOptions viewer;
  std::optional<CameraPose> camera;
  ImageSize size{1280, 720};
  std::string textures = "auto";
  std::string lighting = "faithful";
  std::string luxels = "on";
  std::string backend = "auto";
  CLI::Option* lightingOption = nullptr;
};

int runView(ViewCommand& cmd) {
  ViewerOptions& o = cmd.viewer;
  if (o.map.empty()) o.map = defaultMapPath();
  o.width = cmd.size.width;
  o.height = cmd.size.height;
  o.camera = cmd.camera;
  o.textures = *gl::parseTextureMode(cmd.textures); // --gl-textures admits only the names it parses
  o.lighting = cmd.lighting == "physical" ? LightingMode::Physical : LightingMode::Faithful;
  o.luxels = cmd.luxels == "on";
  o.backend = cmd.backend == "gl" ? ViewerBackend::Gl : cmd.backend == "cpu" ? ViewerBackend::Cpu : ViewerBackend::Auto;
  o.compiled = cmd.lighting == "compiled";
  o.lightingGiven = cmd.lightingOption && cmd.lightingOption->count() > 0;
  try {
    o.bookmarksFile = userConfigFolder() / "bookmarks.json";
  } catch (const std::exception&) {} // no HOME: bookmarks last for the session

  Viewer viewer(o);
  // A level that does not load opens the window anyway, waiting for a save that fixes it.
  if (!viewer.error().empty()) fmt::print(stderr, "{}\n", viewer.error());
  for (const std::string& warning : viewer.warnings()) fmt::print(stderr, "{}\n", warning);
  if (cmd.lighting == "difference") viewer.showDifference();
  if (!viewer.note().empty()) fmt::print(stderr, "{}: note: {}\n", o.map, viewer.note());
  if (!viewer.notice().empty()) fmt::print(stderr, "{}: warning: {}\n", o.map, viewer.notice());
  if (viewer.cpuTracer()) fmt::print(stderr, "brushtrace: {}\n", viewer.cpuReason());
  while (viewer.frame()) {}
  // Where the mapper left the camera, as --camera takes it back.
  fmt::print("camera {}\n", formatCameraPose(viewer.camera()));
  return 0;
}

} // namespace

void addViewCommand(CLI::App& app, int& exitCode) {
  auto cmd = std::make_shared<ViewCommand>();
  CLI::App* view = app.add_subcommand("view", "Open a level in a window, path-traced progressively; reloads on save");
  view->add_option("map", cmd->viewer.map,
                   "Level file (.map, .bsp, ARCHIVE:maps/x.bsp, or a level name with --game/--basedir); default maps/start.map")
      ->check(levelFile());
  addImportOptions(*view, cmd->viewer.import);
  addSizeOption(*view, cmd->size, "Window size");
  addCameraOption(*view, cmd->camera,
                  "Start camera \"(x y z) pitch yaw roll\" or \"setpos x y z pitch yaw roll\" (roll is ignored: the viewer has none)");
  cmd->lightingOption = view->add_option("--lighting", cmd->lighting, "faithful|physical|compiled|difference (keys 4, 5, 6, 7)")
                            ->check(CLI::IsMember({"faithful", "physical", "compiled", "difference"}))
                            ->capture_default_str();
  view->add_option(
          "--luxels", cmd->luxels,
          "Faithful lighting: on = the compiler's luxels, baked on the GPU as the first frames show, off = the light at each pixel")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  view->add_option("--extra", cmd->viewer.bake.extra, "Faithful luxels: sample points per luxel along each axis (light -extra: 1, 2 or 4)")
      ->check(CLI::IsMember({1, 2, 4}))
      ->capture_default_str();
  view->add_option("--bounces", cmd->viewer.bounces, "Bounces in physical mode")->check(CLI::Range(0, 64))->capture_default_str();
  addClampIndirectOption(*view, cmd->viewer.clampIndirect);
  view->add_option("--backend", cmd->backend, "auto|gl|cpu: auto draws with the CPU tracer where the window's GL is software (llvmpipe)")
      ->check(CLI::IsMember({"auto", "gl", "cpu"}))
      ->capture_default_str();
  view->add_option("--gl-textures", cmd->textures, "bindless|arrays|auto")
      ->check(CLI::IsMember({"auto", "bindless", "arrays"}))
      ->capture_default_str();
  view->add_option("--screenshots", cmd->viewer.screenshotDir, "Folder F12 writes screenshots into")
      ->check(writableFolder())
      ->capture_default_str();
  view->callback([cmd, &exitCode] { exitCode = runView(*cmd); });
}

} // namespace bt::app

// A level imported and prepared for the CPU tracer, and its picture from the default camera: the
// set-up the liquid, Quake 3 blend and sky tests share (each at its own size and spp).
#pragma once

#include "importers/import.h"
#include "lighting/render_scene.h"
#include "renderer/camera.h"
#include "renderer/cpu/cpu_renderer.h"

#include <filesystem>
#include <memory>

namespace bt::test {

struct Level {
  Scene scene;
  RenderScene render; // points at scene: a Level stays where it was made (hence unique_ptr)
};

inline std::unique_ptr<Level> loadLevel(const std::filesystem::path& path) {
  auto level = std::make_unique<Level>();
  level->scene = importScene(path.string(), ImportOptions{});
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, {}, diagnostics);
  return level;
}

// Two threads, two bounces in physical mode.
inline RenderImage renderFromDefaultCamera(const Level& level, LightingMode mode, int spp, int width, int height) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.threads = 2;
  settings.integrator.mode = mode;
  settings.integrator.bounces = 2;
  return renderCpu(level.render, Camera(defaultCameraPose(level.scene), width, height), settings);
}

} // namespace bt::test

// A level imported once per benchmark process, with its render scene and default camera: the
// CPU render benchmarks time tracing, never importing.
#pragma once

#include "importers/import.h"
#include "renderer/camera.h"
#include "lighting/render_scene.h"

#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace bt::bench {

struct LoadedLevel {
  Scene scene;
  RenderScene rs;
  CameraPose pose;
};

// nullptr when the file is absent (../shared missing), so the benchmark can report it.
inline const LoadedLevel* loadLevel(const std::string& path) {
  static std::map<std::string, std::unique_ptr<LoadedLevel>> cache;
  if (auto it = cache.find(path); it != cache.end()) return it->second.get();
  std::unique_ptr<LoadedLevel> level;
  if (std::filesystem::exists(path)) {
    level = std::make_unique<LoadedLevel>();
    level->scene = importScene(path, ImportOptions{});
    Diagnostics diagnostics;
    level->rs = buildRenderScene(level->scene, {}, diagnostics);
    level->pose = defaultCameraPose(level->scene);
  }
  return cache.emplace(path, std::move(level)).first->second.get();
}

} // namespace bt::bench

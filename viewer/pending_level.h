// A level being loaded by the viewer, at start-up or after a save, off the frame loop.
#pragma once

#include "importers/textures/missing_textures.h"
#include "renderer/gl/gl_level.h"
#include "viewer/viewer.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace bt {

// A level being loaded, at start-up or after a save: the import and preparation on a worker
// thread (the frames go on showing the current level), then the upload on the frame's thread.
// Rebuilt whole every time, so a failed reload leaves the level on screen untouched.
struct PendingLevel {
  std::unique_ptr<gl::GlLevel> level = std::make_unique<gl::GlLevel>();
  // Where the level's missing textures would be: a texture that appears there reloads it. Found
  // on the worker too (the loose folders are indexed again).
  std::shared_ptr<std::vector<std::string>> missingFiles = std::make_shared<std::vector<std::string>>();
  std::array<float, 256> styleScale; // what its lights are scaled by
  std::unique_ptr<gl::LevelPreparation> preparation;

  // `styleScale`: the light-style sliders' values (LightOptions::styleScale).
  PendingLevel(const ViewerOptions& options, const std::array<float, 256>& styleScale)
      : styleScale(styleScale),
        preparation(gl::prepareGlLevel(
            *level,
            [map = options.map, import = options.import, missing = missingFiles](const gl::EntitiesRead& entitiesRead) {
              Scene scene = importScene(map, import, entitiesRead);
              *missing = missingTextureFiles(scene, import.textures);
              return scene;
            },
            RenderSceneOptions{.lights = LightOptions{.styleScale = styleScale}})) {}
};

// What to watch when a level never loaded: the file named (an archive's for ARCHIVE:maps/x.bsp).
std::filesystem::path levelFileOf(const std::string& map);

} // namespace bt

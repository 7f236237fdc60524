// The files a level's missing textures would have been read from, so that `brushtrace view`
// reloads the level when one of them appears (an artist saving the texture a mapper used).
#pragma once

#include "importers/textures/textures.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace bt {

// For every material loadMaterials() left missing, each spelling of its name
// (textureFileStems) with each image extension in each loose folder the search indexes, lower
// case; empty when none is missing. Indexes the folders again: call it off the frame's thread.
std::vector<std::string> missingTextureFiles(const Scene& scene, const TextureSearch& search);

} // namespace bt

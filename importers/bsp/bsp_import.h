// .bsp (and .pk3:maps/x.bsp) → Scene: entities, brushes with texture frames, materials.
#pragma once

#include "importers/bsp/bsp_file.h"
#include "importers/import.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace bt::bsp {

// Fills in the materials of a scene (pixels and true sizes) from wherever textures live; called
// once the scene has its entities, brushes and one Material per distinct texture name, each sized
// as the BSP says (Q1/HL miptex header, else 64x64) and marked missing.
using MaterialResolver = std::function<void(Scene& scene)>;

// The scene of a parsed BSP file: entities from the entities lump; for each brush entity
// (worldspawn = model 0, others by their "model" "*N" key) the brushes of its model, moved to the
// entity's "origin"; materials resolved by `resolve` (if given) before Quake 3's frames, which
// count texture widths, are scaled to texels by the material's size; the compiled lightmaps in
// Scene::compiledLighting, coloured by `litFile` (a .lit file's bytes) when given.
// Quake 3 curves are tessellated to `curveMaxError` (scene/curves.h).
Scene sceneFromBsp(const BspFile& bsp, const MaterialResolver& resolve = {},
                   const std::optional<std::vector<uint8_t>>& litFile = std::nullopt, double curveMaxError = kPatchMaxError);

// Opens a .bsp file (or "archive.pk3:maps/x.bsp") and returns its scene with textures resolved
// as options say. This is importScene's .bsp branch.
Scene importBsp(const std::string& path, const ImportOptions& options);

} // namespace bt::bsp

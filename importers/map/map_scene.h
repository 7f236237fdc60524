// From a MapDocument to the format-neutral Scene: planes, windings, texture frames, materials.
#pragma once

#include "importers/map/map_document.h"
#include "scene/curves.h"
#include "scene/scene.h"

namespace bt::map {

// Builds every brush of the document. Faces whose points are collinear and duplicate planes
// are dropped, brushes with no volume or unbounded are skipped, each with a diagnostic naming
// its line. Materials are created by name only (one per distinct name, case-insensitive as in
// Quake); loading their pixels is importers/textures' job.
// `loaded`: the materials of an earlier build of the same document after their pixels were
// loaded; brushDef texture matrices are then sized by them (qbsp uses the texture's real size,
// 64x64 when it is missing), otherwise by 64x64.
// Quake 3 patches are tessellated to `curveMaxError` (scene/curves.h).
Scene buildScene(const MapDocument& doc, const std::vector<Material>* loaded = nullptr, double curveMaxError = kPatchMaxError);

// Imports a .map file: parse, build, load the materials' pixels (importers/textures).
Scene importMap(const std::string& path, const ImportOptions& options);

} // namespace bt::map

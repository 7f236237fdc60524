// From a MapDocument to the format-neutral Scene: planes, windings, texture frames, materials.
#pragma once

#include "importers/map/map_document.h"
#include "scene/scene.h"

namespace bt::map {

// Builds every brush of the document. Faces whose points are collinear and duplicate planes
// are dropped, brushes with no volume or unbounded are skipped, each with a diagnostic naming
// its line. Materials are created by name only (one per distinct name, case-insensitive as in
// Quake); loading their pixels is importers/textures' job.
Scene buildScene(const MapDocument& doc);

// Imports a .map file: parse, build, and (when the textures part is present) load materials.
Scene importMap(const std::string& path, const ImportOptions& options);

} // namespace bt::map

// Writing a MapDocument back to .map text, in its own dialect or converted to another.
#pragma once

#include "importers/map/map_document.h"
#include "scene/diagnostics.h"

#include <string>

namespace bt::map {

// Converts every face to the texture kind `target` uses (Standard or Valve 220 face lines;
// Quake 3 keeps brushDef blocks) and drops fields the target cannot hold. When target is the
// document's own dialect nothing changes: a same-dialect round trip is lossless, mixed
// Standard/Valve brushes stay mixed. Standard -> Valve 220 is exact; Valve 220 (or brushDef)
// -> Standard fits the closest rotation/scale/offset and reports, as a warning with the face's
// line, every face whose texel coordinates move by more than 0.01 texel at a winding vertex.
MapDocument convertDocument(const MapDocument& doc, MapDialect target, Diagnostics& report);

// The .map text of a document, TrenchBroom-style ("// Format:" header, one face per line).
// Doubles are written with the shortest text that reads back to the same value.
std::string writeMap(const MapDocument& doc);

// Writes text to `path` through a temporary file in the same folder and a rename, so a reader
// never sees half a file. Throws ImportError when the file cannot be written.
void writeFileAtomically(const std::string& path, const std::string& text);

} // namespace bt::map

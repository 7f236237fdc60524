// Reading .map text into a MapDocument.
#pragma once

#include "importers/map/map_document.h"

#include <optional>
#include <string>
#include <string_view>

namespace bt::map {

// Parses .map text. `path` only names the file in messages. Throws ImportError
// ("path:line:col: error: ...") on anything that is not a well-formed .map: truncated
// files, unbalanced braces, bad numbers, stray bytes. `forced` overrides dialect detection.
MapDocument parseMap(std::string_view text, const std::string& path, std::optional<MapDialect> forced = std::nullopt);

// Reads the file and parses it; throws ImportError when it cannot be read.
MapDocument readMapFile(const std::string& path, std::optional<MapDialect> forced = std::nullopt);

// The dialect a TrenchBroom "// Format: NAME" header names, if any ("Valve", "Quake2 (Valve)", ...).
std::optional<MapDialect> dialectFromFormatName(std::string_view name);

// What the face lines and keys say when no header names the dialect: brushDef or patches mean
// Quake 3, surface fields Quake 2 (Valve axes: Quake 2 Valve), a single extra field Hexen II,
// surface fields plus a colour Daikatana, Valve axes or "mapversion" "220" Valve 220.
MapDialect detectDialect(const MapDocument& doc);

} // namespace bt::map

// Quake's, Hexen II's and Quake 2's palettes, built in (provenance in default_palettes.cpp).
#pragma once

#include "importers/textures/textures.h"

#include <optional>
#include <string_view>

namespace bt::game {

// The palette of the game profile called `game` ("quake", "hexen2", "quake2"); nullopt for
// games whose textures carry their own colours (Half-Life, Quake 3).
std::optional<Palette> builtinPalette(std::string_view game);

} // namespace bt::game

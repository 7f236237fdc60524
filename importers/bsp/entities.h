// The entities lump: the same `{ "key" "value" ... }` blocks as a .map file, without brushes.
#pragma once

#include "scene/scene.h"

#include <string>
#include <string_view>
#include <vector>

namespace bt::bsp {

// Parses the entities lump text. Entity::line is the 1-based line of its '{' within the lump.
// Throws ImportError (file = `path`, with line and column in the lump text) on malformed text.
std::vector<Entity> parseEntities(std::string_view text, const std::string& path);

} // namespace bt::bsp

// Quake's names (textures, classnames, keys, file extensions) compare without regard to case:
// the engines and compilers lowercase them, and DOS-era maps spell them both ways.
#pragma once

#include <string>
#include <string_view>

namespace bt {

std::string lowercase(std::string_view s);
bool equalsIgnoreCase(std::string_view a, std::string_view b);

} // namespace bt

// The palette indices of an 8-bit colour-mapped PNG, which decoding to RGBA loses: LibreQuake
// stores its textures so, and marks the see-through texels of `{` textures by index 255.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

namespace bt {

// One index per pixel, rows top to bottom, for a PNG whose pixels are indices into a palette
// of its own; nullopt for any other image (or a file libpng cannot read: the caller has
// decoded it already, and reported what went wrong).
std::optional<std::vector<uint8_t>> readPngPaletteIndices(const std::filesystem::path& file);

} // namespace bt

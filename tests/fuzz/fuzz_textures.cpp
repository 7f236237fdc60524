// Texture files the importers decode themselves: WAD2/WAD3 (directory, every texture, the
// palette lump), a bare miptex (Quake with a palette, Half-Life with its own), a Quake 2 .wal,
// a palette.lmp / PCX palette. Loose images go to OpenImageIO and are not fuzzed here.
//
// Input: one selector byte, then the file. Selector % 5: 0 WAD, 1 Quake miptex, 2 Half-Life
// miptex, 3 .wal, 4 palette.
#include "importers/textures/textures.h"

#include <cstdint>
#include <span>

namespace {

bt::Palette greyPalette() {
  bt::Palette p;
  for (size_t i = 0; i < p.rgb.size(); ++i) p.rgb[i] = static_cast<uint8_t>(i / 3);
  return p;
}

void decodeEveryWadTexture(std::span<const uint8_t> bytes, const bt::Palette& palette) {
  const bt::WadFile wad = bt::WadFile::fromBytes({bytes.begin(), bytes.end()}, "fuzz.wad");
  (void)wad.palette();
  for (const bt::WadFile::Entry& entry : wad.entries()) {
    try {
      (void)wad.loadTexture(entry.name, &palette);
    } catch (const bt::ImportError&) {
      // One corrupt texture; loadMaterials goes on with the others, so do we.
    }
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const bt::Palette palette = greyPalette();
  const std::span<const uint8_t> bytes(data + 1, size - 1);
  try {
    switch (data[0] % 5) {
    case 0: decodeEveryWadTexture(bytes, palette); break;
    case 1: (void)bt::decodeMiptex(bytes, &palette, false, "fuzz.mip"); break;
    case 2: (void)bt::decodeMiptex(bytes, nullptr, true, "fuzz.mip"); break;
    case 3: (void)bt::decodeWal(bytes, palette, "fuzz.wal"); break;
    case 4: (void)bt::paletteFromBytes(bytes, "fuzz.lmp"); break;
    }
  } catch (const bt::ImportError&) {}
  return 0;
}

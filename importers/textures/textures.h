// Texture and material loading shared by the .map and .bsp importers.
//
// Quake-family textures come from three places:
//   - WAD files: Quake's WAD2 (8-bit miptex that index the game's palette.lmp) and Half-Life's
//     WAD3 (miptex that carry their own 256-colour palette after the smallest mip);
//   - the miptex lump inside a Quake 1 / Half-Life .bsp (same miptex layout as in the WADs);
//   - loose images (PNG/TGA/JPG: image.cpp), the way modern source ports and
//     LibreQuake's texture folders ship them, plus companion maps (_norm, _gloss, _glow, ...).
// Quake 2 .wal files index the Quake 2 palette.
#pragma once

#include "importers/import.h"
#include "scene/scene.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt {

// 256 RGB triples, the layout of Quake's gfx/palette.lmp.
struct Palette {
  std::array<uint8_t, 768> rgb{};
};

// Reads a 768-byte palette.lmp (or the palette at the end of a 256-colour PCX file, which is
// where Quake 2 keeps it: pics/colormap.pcx). Throws ImportError naming the file on any other size.
Palette loadPalette(const std::filesystem::path& lmp);
// The same for bytes already in memory (a WAD's palette lump, a file inside a .pk3).
Palette paletteFromBytes(std::span<const uint8_t> bytes, std::string_view what);

// Decodes one miptex (Quake WAD2 / BSP29 texture lump entry, or Half-Life WAD3/BSP30 with its
// own palette after the mips) into a Material named after the miptex header. Only the full-size
// mip is decoded. Quake (halfLife == false): quakePalette is required; indices 224..255 are
// fullbright: `emissive` then holds their colour (other texels black); it stays empty when the
// texture has no fullbright texel. Index 255 in '{' textures is transparent (alpha 0, black).
// Half-Life: the embedded palette is used, no fullbrights, and in '{' textures index 255 is
// transparent. source is Miptex; WadFile::loadTexture changes it to Wad2/Wad3.
// Throws ImportError naming `what` on truncation or bad sizes (or a null Quake palette).
// A miptex whose pixel offsets are all zero (texture stored outside the .bsp) also throws:
// the caller then looks it up by name like any other missing texture.
Material decodeMiptex(std::span<const uint8_t> bytes, const Palette* quakePalette, bool halfLife, std::string_view what);

// Decodes a Quake 2 .wal (name[32], width, height, 4 mip offsets, ...) with the Quake 2 palette.
// Index 255 is transparent, as in Quake 2's GL renderer. Throws ImportError naming `what` on
// truncation or bad sizes.
Material decodeWal(std::span<const uint8_t> bytes, const Palette& quake2Palette, std::string_view what);

// For every material in scene.materials that is still missing: find and load it (WADs from
// search.wads then the worldspawn "wad" key — semicolon list, paths relative to the map file dir
// scene.sourcePath, also tried by file name beside the map — loose images from search.textureDirs
// and <mapdir>/textures), plus companion maps; otherwise a checker placeholder. Adds ONE warning
// diagnostic listing all missing names. Never throws for a missing/corrupt WAD: a warning instead.
// Details:
//  - Name spellings: see textureFileStems(); WAD and file lookups ignore case.
//  - A WAD named in "wad" that is not there but has a folder of the same name beside it
//    (LibreQuake's texture-wads/lq_dev/ for lq_dev.wad) is searched as a loose folder.
//  - TrenchBroom's worldspawn "_tb_textures" folders (relative to the map) are loose folders too,
//    and so is <mapdir>/../textures (a Quake 2 game dir with the map in maps/).
//  - Loose .wal files are decoded with the Quake 2 palette: search.palette, else
//    pics/colormap.pcx up the tree.
//  - After those, the game install of search.game (importers/game/game_install.h): WADs named
//    by the "wad" key by the tails of their path, <textures>/<name>.wal and images, the game's
//    palette. A WAD2 or .wal texture with no palette anywhere is decoded with the built-in
//    palette of the game (importers/game/default_palettes.h), with one warning that says so.
//  - Companion maps are also looked up for materials that are already loaded (BSP miptex).
//  - search.load == false: every missing material just gets its placeholder, no warnings.
// Sizes (texture coordinates are divided by them): a missing material keeps the size it has
// (64x64 by default, or what the .bsp importer set from the miptex header) for its placeholder.
// A texture found in a WAD takes the WAD's size. A loose image takes the image's size, unless
// the material's size was already set to something other than the 64x64 default: then that
// size stays and the image is a (possibly higher-resolution) replacement drawn over it.
void loadMaterials(Scene& scene, const TextureSearch& search);

// The level's sky images (Scene::sky), appended to scene.materials: the worldspawn's sky box
// (Quake `sky`, Half-Life `skyname`, Quake 2 `sky`), its six images <skies>/NAME{rt,bk,lf,ft,up,dn}.tga
// (else .pcx; the game profile's skies folder) from the game's files; else Quake's two layers of
// the sky texture (Material::skyFront). Where a sky box image is not found or cannot be read, one
// warning names the files tried and the level keeps the layers, if any.
void loadSky(Scene& scene, const TextureSearch& search);

// A checker of two greys in 8x8-texel cells, opaque. Used for every texture that is not found.
// Sides above 1024 are divided by the smallest whole factor that brings both to 1024 or less (a
// corrupt size costs no more than a 1024x1024 image; the material keeps its size).
Image checkerPlaceholder(int width, int height);

// ---------------------------------------------------------------------------------------------
// Lower-level pieces, public so that the .bsp importer and tools can reuse them.

// One WAD2 ("WAD2") or WAD3 ("WAD3") file held in memory, directory bounds-checked on open.
class WadFile {
public:
  // Quake's lump types; only miptex are textures.
  static constexpr uint8_t kTypePalette = 0x40;    // '@'
  static constexpr uint8_t kTypeQpic = 0x42;       // 'B', status-bar pictures: not textures
  static constexpr uint8_t kTypeMiptexWad2 = 0x44; // 'D'
  static constexpr uint8_t kTypeMiptexWad3 = 0x43; // 'C'

  struct Entry {
    std::string name; // as stored (up to 16 chars), lookups ignore case
    uint8_t type = 0;
    uint8_t compression = 0;
    uint32_t offset = 0;
    uint32_t size = 0; // on disk
  };

  // Reads and validates the header and directory. Throws ImportError naming the file on a bad
  // magic, a directory past the end, or an entry whose data lies outside the file.
  static WadFile open(const std::filesystem::path& path);
  static WadFile fromBytes(std::vector<uint8_t> bytes, std::string displayName);

  bool halfLife() const { return halfLife_; } // WAD3
  const std::string& displayName() const { return displayName_; }
  const std::vector<Entry>& entries() const { return entries_; }

  // The miptex entry called name (case-insensitive), or nullptr. Non-texture lumps are skipped.
  const Entry* findTexture(std::string_view name) const;
  std::span<const uint8_t> data(const Entry& entry) const;

  // Decodes the named texture; std::nullopt when the WAD has no such texture. Throws ImportError
  // when the entry exists but is corrupt or compressed. quakePalette is needed for WAD2 only.
  std::optional<Material> loadTexture(std::string_view name, const Palette* quakePalette) const;

  // The game palette stored as a lump of type '@' (Quake's gfx.wad has one), if any.
  std::optional<Palette> palette() const;

private:
  std::vector<uint8_t> bytes_;
  std::vector<Entry> entries_;
  std::string displayName_;
  bool halfLife_ = false;
};

// Case-insensitive comparison the way Quake compares texture names.
bool textureNamesEqual(std::string_view a, std::string_view b);

// The file names a texture may have on disk, in the order they are tried: the name as written,
// then the other spellings of Quake's special prefixes ('*', '#' and "star_"; '+' and "plus_"),
// and a Quake 3 name without its "textures/" prefix. Folders in names ("e1u1/floor1_3") are kept.
std::vector<std::string> textureFileStems(std::string_view name);

// Loads a loose image (PNG, JPEG, TGA, BMP, GIF, PSD, PNM; the format from the file's first
// bytes) as 8-bit RGBA, the texels as stored. Throws ImportError naming the file when it cannot
// be read.
Image loadImage(const std::filesystem::path& path);

// The same for an image file held in memory (one read from a pak or pk3); `name` is the file's
// name, which names it in the ImportError.
Image decodeImage(std::span<const uint8_t> bytes, const std::string& name);

// Quake's palette for a level: `explicitPalette` when given (throws ImportError if unreadable),
// otherwise the first gfx/palette.lmp (or palette.lmp) found walking up from each of
// `startDirs`. Never invents one: std::nullopt when nothing is found. `readFrom`, when given,
// receives the file the palette was read from.
std::optional<Palette> findPalette(const std::string& explicitPalette, const std::vector<std::filesystem::path>& startDirs,
                                   std::filesystem::path* readFrom = nullptr);
// Quake 2's palette: `explicitPalette`, else pics/colormap.pcx walking up from `startDirs`.
std::optional<Palette> findQuake2Palette(const std::string& explicitPalette, const std::vector<std::filesystem::path>& startDirs,
                                         std::filesystem::path* readFrom = nullptr);

// Reads a whole texture/WAD/palette file; throws ImportError naming it when it cannot be read.
std::vector<uint8_t> readTextureFile(const std::filesystem::path& path);

} // namespace bt

// Palettes and the 8-bit texture formats: Quake/Half-Life miptex and Quake 2 .wal.
#include "quake/binary_reader.h"
#include "importers/textures/textures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <system_error>

namespace bt {

using quake::fits;
using quake::readName;
using quake::readU16;
using quake::readU32;

namespace {

[[noreturn]] void fail(std::string_view what, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, std::string(what), 0, 0, message});
}

// Larger than any texture a Quake-family engine accepts; keeps width * height * 4 far from
// overflow and a corrupt header from asking for gigabytes.
constexpr uint32_t kMaxTextureSide = 16384;

void checkSize(uint32_t width, uint32_t height, std::string_view what) {
  if (width == 0 || height == 0 || width > kMaxTextureSide || height > kMaxTextureSide)
    fail(what, fmt::format("bad texture size {}x{}", width, height));
}

std::vector<uint8_t> readWholeFile(const std::filesystem::path& path, uint64_t maxSize) {
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) fail(path.string(), fmt::format("cannot read: {}", ec.message()));
  if (size > maxSize) fail(path.string(), fmt::format("file too large ({} bytes)", size));
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes(size);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) fail(path.string(), "cannot read");
  return bytes;
}

// Quake 1 texture names start with '{' when they are alpha-tested ("fence") textures.
bool isFenceTexture(std::string_view name) {
  return !name.empty() && name.front() == '{';
}

// Quake's scrolling sky: QuakeSpasm (Mod_LoadTextures) gives every texture named sky* two layers.
bool isQuakeSky(std::string_view name) {
  return name.size() >= 3 && std::tolower(static_cast<unsigned char>(name[0])) == 's' &&
      std::tolower(static_cast<unsigned char>(name[1])) == 'k' && std::tolower(static_cast<unsigned char>(name[2])) == 'y';
}

// Quake's software renderer draws palette indices 224..255 at full brightness regardless of
// lighting; GL engines and ericw-tools' light follow the same rule for "fullbright" texels.
constexpr int kFirstFullbright = 224;
// Index 255 of '{' textures is the see-through colour (both Quake and Half-Life).
constexpr int kTransparentIndex = 255;

void setTexel(Image& image, size_t i, const uint8_t* rgb, uint8_t alpha) {
  image.rgba[i * 4 + 0] = rgb[0];
  image.rgba[i * 4 + 1] = rgb[1];
  image.rgba[i * 4 + 2] = rgb[2];
  image.rgba[i * 4 + 3] = alpha;
}

Image blankImage(int width, int height) {
  Image image;
  image.width = width;
  image.height = height;
  image.rgba.assign(static_cast<size_t>(width) * height * 4, 0);
  return image;
}

// QuakeSpasm's Sky_LoadTexture: the front layer is the left half, and its palette index 0 is
// clear. The clear texels get alpha 0 and black, so that filtering them adds no colour.
Image skyFrontLayer(const Image& texture, const uint8_t* indices) {
  const int half = texture.width / 2;
  Image front = blankImage(half, texture.height);
  for (int y = 0; y < texture.height; ++y)
    for (int x = 0; x < half; ++x) {
      const size_t i = size_t(y) * size_t(texture.width) + size_t(x);
      if (indices[i] != 0) std::copy_n(&texture.rgba[i * 4], 4, &front.rgba[(size_t(y) * size_t(half) + size_t(x)) * 4]);
    }
  return front;
}

} // namespace

std::vector<uint8_t> readTextureFile(const std::filesystem::path& path) {
  // WADs of full games reach tens of megabytes; a 1 GiB cap only guards against reading
  // something that is clearly not a texture file.
  return readWholeFile(path, uint64_t{1} << 30);
}

Palette paletteFromBytes(std::span<const uint8_t> bytes, std::string_view what) {
  Palette palette;
  if (bytes.size() == palette.rgb.size()) {
    std::copy(bytes.begin(), bytes.end(), palette.rgb.begin());
    return palette;
  }
  // A PCX file (Quake 2's pics/colormap.pcx) ends with 0x0C and a 256-colour palette.
  constexpr size_t kPcxTail = 769;
  if (bytes.size() > 128 + kPcxTail && bytes[0] == 0x0A && bytes[bytes.size() - kPcxTail] == 0x0C) {
    std::copy(bytes.end() - 768, bytes.end(), palette.rgb.begin());
    return palette;
  }
  fail(what,
       fmt::format("not a palette: {} bytes (a palette.lmp has 768, or a PCX file with a "
                   "256-colour palette)",
                   bytes.size()));
}

Palette loadPalette(const std::filesystem::path& lmp) {
  const std::vector<uint8_t> bytes = readWholeFile(lmp, 16 << 20);
  return paletteFromBytes(bytes, lmp.string());
}

namespace {
std::optional<std::filesystem::path> findUpwards(const std::vector<std::filesystem::path>& startDirs,
                                                 std::initializer_list<const char*> relativeNames) {
  std::error_code ec;
  for (const auto& start : startDirs) {
    std::filesystem::path dir = std::filesystem::absolute(start, ec).lexically_normal();
    if (ec) continue;
    while (true) {
      for (const char* name : relativeNames) {
        const auto candidate = dir / name;
        if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
      }
      if (!dir.has_relative_path()) break; // reached the root
      dir = dir.parent_path();
    }
  }
  return std::nullopt;
}
} // namespace

namespace {
// `explicitPalette`, else the first of `relativeNames` up the tree from `startDirs`.
std::optional<Palette> findPaletteFile(const std::string& explicitPalette, const std::vector<std::filesystem::path>& startDirs,
                                       std::initializer_list<const char*> relativeNames, std::filesystem::path* readFrom) {
  std::optional<std::filesystem::path> file;
  if (!explicitPalette.empty())
    file = explicitPalette;
  else
    file = findUpwards(startDirs, relativeNames);
  if (!file) return std::nullopt;
  if (readFrom) *readFrom = *file;
  return loadPalette(*file);
}
} // namespace

std::optional<Palette> findPalette(const std::string& explicitPalette, const std::vector<std::filesystem::path>& startDirs,
                                   std::filesystem::path* readFrom) {
  // A Quake game dir (id1/, or LibreQuake's lq1/) keeps it in gfx/; some mods ship it loose.
  return findPaletteFile(explicitPalette, startDirs, {"gfx/palette.lmp", "palette.lmp"}, readFrom);
}

std::optional<Palette> findQuake2Palette(const std::string& explicitPalette, const std::vector<std::filesystem::path>& startDirs,
                                         std::filesystem::path* readFrom) {
  // Quake 2 has no palette.lmp: its palette is the one of baseq2/pics/colormap.pcx.
  return findPaletteFile(explicitPalette, startDirs, {"pics/colormap.pcx"}, readFrom);
}

Material decodeMiptex(std::span<const uint8_t> bytes, const Palette* quakePalette, bool halfLife, std::string_view what) {
  // struct miptex_t { char name[16]; uint32 width, height; uint32 offsets[4]; } followed by the
  // four mip levels (offsets relative to the miptex start); Half-Life adds a palette after mip 3.
  constexpr size_t kHeaderSize = 40;
  if (!fits(bytes, 0, kHeaderSize))
    fail(what, fmt::format("truncated miptex: {} bytes, the header alone has {}", bytes.size(), kHeaderSize));
  const uint32_t width = readU32(bytes, 16);
  const uint32_t height = readU32(bytes, 20);
  checkSize(width, height, what);
  uint32_t offsets[4];
  for (int i = 0; i < 4; ++i) offsets[i] = readU32(bytes, 24 + 4 * i);
  if (offsets[0] == 0) fail(what, "miptex has no pixel data (the compiler left it to be found in a WAD)");

  const uint64_t pixelCount = uint64_t{width} * height;
  if (!fits(bytes, offsets[0], pixelCount))
    fail(what,
         fmt::format("truncated miptex: {}x{} pixels at offset {} need {} bytes, have {}", width, height, offsets[0],
                     offsets[0] + pixelCount, bytes.size()));

  Palette ownPalette;
  const Palette* palette = quakePalette;
  if (halfLife) {
    // After the smallest mip (1/8 size): uint16 colour count, then count RGB triples.
    const uint64_t paletteAt = uint64_t{offsets[3]} + uint64_t{width / 8} * (height / 8);
    if (offsets[3] == 0 || !fits(bytes, paletteAt, 2)) fail(what, "truncated Half-Life miptex: no palette after the last mip");
    const uint16_t colours = readU16(bytes, paletteAt);
    if (colours > 256) fail(what, fmt::format("Half-Life miptex palette has {} colours (at most 256)", colours));
    if (!fits(bytes, paletteAt + 2, uint64_t{colours} * 3))
      fail(what, fmt::format("truncated Half-Life miptex: palette of {} colours cut off", colours));
    std::copy_n(bytes.begin() + static_cast<ptrdiff_t>(paletteAt + 2), colours * 3, ownPalette.rgb.begin());
    palette = &ownPalette;
  } else if (!palette) {
    fail(what, "a Quake miptex needs the Quake palette and none was given");
  }

  Material material;
  material.name = readName(bytes, 0, 16);
  material.width = static_cast<int>(width);
  material.height = static_cast<int>(height);
  material.source = TextureSource::Miptex;
  material.baseColor = blankImage(material.width, material.height);

  const bool fence = isFenceTexture(material.name);
  const uint8_t* indices = bytes.data() + offsets[0];
  bool anyFullbright = false;
  for (size_t i = 0; i < pixelCount; ++i) {
    const int index = indices[i];
    if (fence && index == kTransparentIndex) continue; // stays (0,0,0,0)
    setTexel(material.baseColor, i, &palette->rgb[index * 3], 255);
    anyFullbright |= !halfLife && index >= kFirstFullbright;
  }
  // Half-Life draws its sky* faces with the level's skybox only (`skyname`), never the texture.
  if (!halfLife && isQuakeSky(material.name) && width >= 2) material.skyFront = skyFrontLayer(material.baseColor, indices);

  if (anyFullbright) {
    material.emissive = blankImage(material.width, material.height);
    for (size_t i = 0; i < pixelCount; ++i) {
      const int index = indices[i];
      if (index < kFirstFullbright || (fence && index == kTransparentIndex)) {
        material.emissive.rgba[i * 4 + 3] = 255; // black, opaque
        continue;
      }
      setTexel(material.emissive, i, &palette->rgb[index * 3], 255);
    }
  }
  return material;
}

Material decodeWal(std::span<const uint8_t> bytes, const Palette& quake2Palette, std::string_view what) {
  // struct miptex_t (Quake 2) { char name[32]; uint32 width, height; uint32 offsets[4];
  //   char animname[32]; int32 flags, contents, value; } = 100 bytes, then the mips.
  constexpr size_t kHeaderSize = 100;
  if (!fits(bytes, 0, kHeaderSize)) fail(what, fmt::format("truncated .wal: {} bytes, the header alone has {}", bytes.size(), kHeaderSize));
  const uint32_t width = readU32(bytes, 32);
  const uint32_t height = readU32(bytes, 36);
  checkSize(width, height, what);
  const uint32_t offset = readU32(bytes, 40);
  const uint64_t pixelCount = uint64_t{width} * height;
  if (offset < kHeaderSize || !fits(bytes, offset, pixelCount))
    fail(what,
         fmt::format("truncated .wal: {}x{} pixels at offset {} need {} bytes, have {}", width, height, offset,
                     uint64_t{offset} + pixelCount, bytes.size()));

  Material material;
  material.name = readName(bytes, 0, 32);
  material.width = static_cast<int>(width);
  material.height = static_cast<int>(height);
  material.source = TextureSource::Wal;
  material.baseColor = blankImage(material.width, material.height);
  const uint8_t* indices = bytes.data() + offset;
  for (size_t i = 0; i < pixelCount; ++i) {
    // Quake 2's GL renderer makes index 255 transparent in every 8-bit texture.
    if (indices[i] == kTransparentIndex) continue;
    setTexel(material.baseColor, i, &quake2Palette.rgb[indices[i] * 3], 255);
  }
  return material;
}

Image checkerPlaceholder(int width, int height) {
  width = std::clamp(width, 1, static_cast<int>(kMaxTextureSide));
  height = std::clamp(height, 1, static_cast<int>(kMaxTextureSide));
  // A decoded texture is no bigger than the file that holds it, but a placeholder costs what its
  // header asks: 40 bytes of miptex header could ask for 16384x16384 (a GB). Past this side the
  // checker is drawn smaller by a whole factor; texture coordinates divide by the material's own
  // size, so it still covers the surface, its cells that factor larger.
  constexpr int kMaxPlaceholderSide = 1024;
  const int reduce = (std::max(width, height) + kMaxPlaceholderSide - 1) / kMaxPlaceholderSide;
  width = (width + reduce - 1) / reduce;
  height = (height + reduce - 1) / reduce;
  constexpr int kCell = 8;
  constexpr uint8_t kDark = 0x40, kLight = 0x90;
  Image image = blankImage(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const uint8_t grey = ((x / kCell + y / kCell) % 2 == 0) ? kLight : kDark;
      uint8_t* t = &image.rgba[(static_cast<size_t>(y) * width + x) * 4];
      t[0] = t[1] = t[2] = grey;
      t[3] = 255;
    }
  return image;
}

} // namespace bt

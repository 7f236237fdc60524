// WAD2 (Quake) and WAD3 (Half-Life) texture archives.
//
// Layout: "WAD2"/"WAD3", int32 entry count, int32 directory offset; the directory is an array of
//   { int32 filepos, disksize, size; int8 type, compression; int16 pad; char name[16]; }.
// Every offset and size comes from the file, so each one is checked before it is used.
#include "quake/binary_reader.h"
#include "scene/names.h"
#include "importers/textures/textures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace bt {

using quake::fits;
using quake::readName;
using quake::readU32;

namespace {

constexpr size_t kHeaderSize = 12;
constexpr size_t kDirectoryEntrySize = 32;
constexpr size_t kNameSize = 16;

[[noreturn]] void fail(const std::string& file, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, file, 0, 0, message});
}

// The magic as text for error messages, with unprintable bytes escaped.
std::string printableMagic(std::span<const uint8_t> bytes) {
  std::string text;
  for (size_t i = 0; i < 4 && i < bytes.size(); ++i) {
    const uint8_t c = bytes[i];
    if (std::isprint(c))
      text.push_back(static_cast<char>(c));
    else
      text += fmt::format("\\x{:02x}", c);
  }
  return text;
}

bool isMiptexType(uint8_t type) {
  return type == WadFile::kTypeMiptexWad2 || type == WadFile::kTypeMiptexWad3;
}

} // namespace

bool textureNamesEqual(std::string_view a, std::string_view b) {
  return equalsIgnoreCase(a, b);
}

WadFile WadFile::open(const std::filesystem::path& path) {
  return fromBytes(readTextureFile(path), path.string());
}

WadFile WadFile::fromBytes(std::vector<uint8_t> bytes, std::string displayName) {
  WadFile wad;
  wad.displayName_ = std::move(displayName);
  const std::span<const uint8_t> all(bytes);
  if (!fits(all, 0, kHeaderSize))
    fail(wad.displayName_, fmt::format("too small for a WAD header ({} bytes, need {})", bytes.size(), kHeaderSize));

  const std::string magic = printableMagic(all);
  if (magic == "WAD3")
    wad.halfLife_ = true;
  else if (magic != "WAD2")
    fail(wad.displayName_, fmt::format("not a WAD2/WAD3 file (magic '{}')", magic));

  const uint32_t count = readU32(all, 4);
  const uint32_t directoryOffset = readU32(all, 8);
  if (!fits(all, directoryOffset, uint64_t{count} * kDirectoryEntrySize))
    fail(
        wad.displayName_,
        fmt::format("directory of {} entries at offset {} runs past the end of the file ({} bytes)", count, directoryOffset, bytes.size()));

  wad.entries_.reserve(count);
  for (uint32_t i = 0; i < count; ++i) {
    const size_t at = directoryOffset + size_t{i} * kDirectoryEntrySize;
    Entry entry;
    entry.offset = readU32(all, at);
    entry.size = readU32(all, at + 4);
    entry.type = all[at + 12];
    entry.compression = all[at + 13];
    entry.name = readName(all, at + 16, kNameSize);
    // Some tools leave unnamed slots in the directory; nothing can refer to them.
    if (entry.name.empty()) continue;
    if (!fits(all, entry.offset, entry.size))
      fail(wad.displayName_,
           fmt::format("entry {} '{}' (offset {}, size {}) lies past the end of the file ({} bytes)", i, entry.name, entry.offset,
                       entry.size, bytes.size()));
    wad.entries_.push_back(std::move(entry));
  }
  wad.bytes_ = std::move(bytes);
  return wad;
}

const WadFile::Entry* WadFile::findTexture(std::string_view name) const {
  for (const Entry& entry : entries_)
    if (isMiptexType(entry.type) && textureNamesEqual(entry.name, name)) return &entry;
  return nullptr;
}

std::span<const uint8_t> WadFile::data(const Entry& entry) const {
  return std::span<const uint8_t>(bytes_).subspan(entry.offset, entry.size);
}

std::optional<Palette> WadFile::palette() const {
  // Quake's gfx.wad carries the game palette as a 768-byte lump of type '@'.
  for (const Entry& entry : entries_)
    if (entry.type == kTypePalette && entry.compression == 0 && entry.size == 768)
      return paletteFromBytes(data(entry), displayName_ + ":" + entry.name);
  return std::nullopt;
}

std::optional<Material> WadFile::loadTexture(std::string_view name, const Palette* quakePalette) const {
  const Entry* entry = findTexture(name);
  if (!entry) return std::nullopt;
  const std::string what = displayName_ + ":" + entry->name;
  if (entry->compression != 0) fail(what, fmt::format("compressed WAD lump (compression {}) is not supported", entry->compression));
  Material material = decodeMiptex(data(*entry), quakePalette, halfLife_, what);
  material.name = std::string(name);
  material.source = halfLife_ ? TextureSource::Wad3 : TextureSource::Wad2;
  material.sourcePath = displayName_;
  return material;
}

} // namespace bt

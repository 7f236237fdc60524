// Little-endian reads from byte spans, for the textures part's binary formats. Internal header.
// Callers check bounds first (fits()); the readers themselves only assert them.
#pragma once

#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace bt::detail {

// True when [offset, offset + size) lies inside bytes. Computed in 64 bits so that offsets
// read from a file cannot wrap around.
inline bool fits(std::span<const uint8_t> bytes, uint64_t offset, uint64_t size) {
  return offset <= bytes.size() && size <= bytes.size() - offset;
}

inline uint32_t readU32(std::span<const uint8_t> bytes, size_t offset) {
  assert(fits(bytes, offset, 4));
  return static_cast<uint32_t>(bytes[offset]) | static_cast<uint32_t>(bytes[offset + 1]) << 8 |
      static_cast<uint32_t>(bytes[offset + 2]) << 16 | static_cast<uint32_t>(bytes[offset + 3]) << 24;
}

inline uint16_t readU16(std::span<const uint8_t> bytes, size_t offset) {
  assert(fits(bytes, offset, 2));
  return static_cast<uint16_t>(bytes[offset] | bytes[offset + 1] << 8);
}

// A fixed-size name field (WAD directory, miptex, .wal): NUL-terminated, or using the whole
// field when it has no NUL. Bytes after the NUL are garbage in many real files and are ignored.
inline std::string readName(std::span<const uint8_t> bytes, size_t offset, size_t fieldSize) {
  assert(fits(bytes, offset, fieldSize));
  std::string name;
  for (size_t i = 0; i < fieldSize && bytes[offset + i] != 0; ++i) name.push_back(static_cast<char>(bytes[offset + i]));
  return name;
}

} // namespace bt::detail

// Little-endian fields from byte spans, whatever the host's byte order: the one reader of the
// games' binary formats (BSP lumps and BSPX, WAD, miptex, .wal, .pak). Callers check that what
// they read lies in the data first, so that a truncated file gets an error naming the file and
// the lump or entry; the reads check again and throw std::out_of_range rather than read past it.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

namespace bt::quake {

// True when [offset, offset + size) lies inside bytes. Computed in 64 bits so that offsets
// read from a file cannot wrap around.
inline bool fits(std::span<const uint8_t> bytes, uint64_t offset, uint64_t size) {
  return offset <= bytes.size() && size <= bytes.size() - offset;
}

// Fields in order from the start of a span.
class LittleEndianReader {
public:
  explicit LittleEndianReader(std::span<const uint8_t> bytes) : bytes_(bytes) {}

  size_t position() const { return pos_; }
  size_t remaining() const { return bytes_.size() - pos_; }

  uint8_t u8() { return *take(1); }
  uint16_t u16() {
    const uint8_t* p = take(2);
    return static_cast<uint16_t>(p[0] | (p[1] << 8));
  }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  uint32_t u32() {
    const uint8_t* p = take(4);
    return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
        (static_cast<uint32_t>(p[3]) << 24);
  }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  glm::vec3 vec3() {
    const float x = f32(), y = f32();
    return {x, y, f32()};
  }
  // A fixed-size name field (WAD directory, miptex, .wal, lumps): NUL-terminated, or using the
  // whole field when it has no NUL. Bytes after the NUL are garbage in many real files.
  std::string name(size_t fieldSize) {
    const uint8_t* p = take(fieldSize);
    const auto* nul = static_cast<const uint8_t*>(std::memchr(p, 0, fieldSize));
    return std::string(reinterpret_cast<const char*>(p), nul ? static_cast<size_t>(nul - p) : fieldSize);
  }
  void skip(size_t n) { take(n); }

private:
  const uint8_t* take(size_t n) {
    if (remaining() < n) throw std::out_of_range("little-endian read past the end of its data");
    const uint8_t* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }

  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
};

// Single fields at a byte offset.
inline uint16_t readU16(std::span<const uint8_t> bytes, size_t offset) {
  return LittleEndianReader(bytes.subspan(std::min(offset, bytes.size()))).u16();
}
inline uint32_t readU32(std::span<const uint8_t> bytes, size_t offset) {
  return LittleEndianReader(bytes.subspan(std::min(offset, bytes.size()))).u32();
}
inline std::string readName(std::span<const uint8_t> bytes, size_t offset, size_t fieldSize) {
  return LittleEndianReader(bytes.subspan(std::min(offset, bytes.size()))).name(fieldSize);
}

} // namespace bt::quake

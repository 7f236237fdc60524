#include "quake/binary_reader.h"

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>

namespace bt::quake {
namespace {

TEST(BinaryReader, ReadsLittleEndianFieldsInOrder) {
  const std::array<uint8_t, 18> bytes{0x34, 0x12, 0xfe, 0xff, 0x78, 0x56, 0x34, 0x12, 0x00, 0x00, 0x80, 0x3f, 'a', 'b', 0, 'x', 'y', 'z'};
  LittleEndianReader r(bytes);
  EXPECT_EQ(r.u16(), 0x1234);
  EXPECT_EQ(r.i16(), -2);
  EXPECT_EQ(r.u32(), 0x12345678u);
  EXPECT_EQ(r.f32(), 1.0f);
  EXPECT_EQ(r.name(6), "ab"); // what follows the NUL is garbage in real files
  EXPECT_EQ(r.remaining(), 0u);
  EXPECT_EQ(readU32(bytes, 4), 0x12345678u);
  EXPECT_EQ(readU16(bytes, 0), 0x1234);
  EXPECT_EQ(readName(bytes, 15, 3), "xyz"); // a full field without a NUL
}

TEST(BinaryReader, NeverReadsPastTheEnd) {
  const std::array<uint8_t, 6> bytes{1, 2, 3, 4, 5, 6};
  const std::span<const uint8_t> firstFive = std::span<const uint8_t>(bytes).first(5);
  LittleEndianReader r(firstFive);
  EXPECT_EQ(r.u32(), 0x04030201u);
  EXPECT_THROW(r.u16(), std::out_of_range);
  EXPECT_EQ(r.u8(), 5);
  EXPECT_THROW(r.u8(), std::out_of_range);
  EXPECT_THROW(readU32(bytes, 3), std::out_of_range);
  EXPECT_THROW(readU32(bytes, 1000), std::out_of_range);
  EXPECT_THROW(readName(bytes, 4, 3), std::out_of_range);
  EXPECT_TRUE(fits(bytes, 2, 4));
  EXPECT_FALSE(fits(bytes, 3, 4));
  EXPECT_FALSE(fits(bytes, ~uint64_t{0}, 2)); // an offset from a file must not wrap around
}

} // namespace
} // namespace bt::quake

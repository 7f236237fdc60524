// Quake 1's (and Half-Life's) leaf contents, as id's bspfile.h and ericw-tools' bspfile_q1 name
// them: negative numbers, one per leaf, not bits.
#pragma once

#include <cstdint>

namespace bt::quake::q1 {

inline constexpr int32_t CONTENTS_EMPTY = -1;
inline constexpr int32_t CONTENTS_SOLID = -2;
inline constexpr int32_t CONTENTS_WATER = -3;
inline constexpr int32_t CONTENTS_SLIME = -4;
inline constexpr int32_t CONTENTS_LAVA = -5;
inline constexpr int32_t CONTENTS_SKY = -6;

} // namespace bt::quake::q1

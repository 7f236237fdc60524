// Quake 2's surface flags (texinfo, .wal, the .map's third number) and contents bits (brushes,
// leaves, the .map's first number), as id's qfiles.h and ericw-tools' bspfile_q2 name them.
#pragma once

#include <cstdint>

namespace bt::quake::q2 {

inline constexpr int32_t SURF_LIGHT = 0x1;
inline constexpr int32_t SURF_SLICK = 0x2;
inline constexpr int32_t SURF_SKY = 0x4;
inline constexpr int32_t SURF_WARP = 0x8; // turbulent water, slime, lava
inline constexpr int32_t SURF_TRANS33 = 0x10;
inline constexpr int32_t SURF_TRANS66 = 0x20;
inline constexpr int32_t SURF_FLOWING = 0x40;
inline constexpr int32_t SURF_NODRAW = 0x80;
inline constexpr int32_t SURF_HINT = 0x100;
inline constexpr int32_t SURF_SKIP = 0x200;

inline constexpr int32_t CONTENTS_SOLID = 0x1;
inline constexpr int32_t CONTENTS_WINDOW = 0x2;
inline constexpr int32_t CONTENTS_AUX = 0x4;
inline constexpr int32_t CONTENTS_LAVA = 0x8;
inline constexpr int32_t CONTENTS_SLIME = 0x10;
inline constexpr int32_t CONTENTS_WATER = 0x20;
inline constexpr int32_t CONTENTS_MIST = 0x40;
inline constexpr int32_t CONTENTS_AREAPORTAL = 0x8000;
inline constexpr int32_t CONTENTS_PLAYERCLIP = 0x10000;
inline constexpr int32_t CONTENTS_MONSTERCLIP = 0x20000;
inline constexpr int32_t CONTENTS_ORIGIN = 0x1000000; // the brush only marks the model's origin
inline constexpr int32_t CONTENTS_MONSTER = 0x2000000;
inline constexpr int32_t CONTENTS_DEADMONSTER = 0x4000000;
inline constexpr int32_t CONTENTS_DETAIL = 0x8000000;
inline constexpr int32_t CONTENTS_TRANSLUCENT = 0x10000000;
inline constexpr int32_t CONTENTS_LADDER = 0x20000000;

inline constexpr int32_t MASK_LIQUID = CONTENTS_WATER | CONTENTS_LAVA | CONTENTS_SLIME;
inline constexpr int32_t MASK_CLIP = CONTENTS_PLAYERCLIP | CONTENTS_MONSTERCLIP; // brushtrace's name: what qbsp's clip textures set

} // namespace bt::quake::q2

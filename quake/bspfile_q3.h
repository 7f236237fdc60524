// Quake 3's surface flags and contents bits (a shader's surfaceparms, IBSP 46's shader lump),
// as id's surfaceflags.h names them. Sky, nodraw, hint, skip, the liquids and the clips keep
// Quake 2's values (bspfile_q2.h); SURF_LADDER takes the bit that is Quake 2's SURF_WARP.
#pragma once

#include <cstdint>

namespace bt::quake::q3 {

inline constexpr int32_t SURF_NODAMAGE = 0x1;
inline constexpr int32_t SURF_SLICK = 0x2;
inline constexpr int32_t SURF_SKY = 0x4;
inline constexpr int32_t SURF_LADDER = 0x8;
inline constexpr int32_t SURF_NOIMPACT = 0x10;
inline constexpr int32_t SURF_NOMARKS = 0x20;
inline constexpr int32_t SURF_FLESH = 0x40;
inline constexpr int32_t SURF_NODRAW = 0x80;
inline constexpr int32_t SURF_HINT = 0x100;
inline constexpr int32_t SURF_SKIP = 0x200;
inline constexpr int32_t SURF_NOLIGHTMAP = 0x400;
inline constexpr int32_t SURF_POINTLIGHT = 0x800;
inline constexpr int32_t SURF_METALSTEPS = 0x1000;
inline constexpr int32_t SURF_NOSTEPS = 0x2000;
inline constexpr int32_t SURF_NONSOLID = 0x4000;
inline constexpr int32_t SURF_LIGHTFILTER = 0x8000;
inline constexpr int32_t SURF_ALPHASHADOW = 0x10000;
inline constexpr int32_t SURF_NODLIGHT = 0x20000;

inline constexpr int32_t CONTENTS_SOLID = 0x1;
inline constexpr int32_t CONTENTS_LAVA = 0x8;
inline constexpr int32_t CONTENTS_SLIME = 0x10;
inline constexpr int32_t CONTENTS_WATER = 0x20;
inline constexpr int32_t CONTENTS_FOG = 0x40;
inline constexpr int32_t CONTENTS_AREAPORTAL = 0x8000;
inline constexpr int32_t CONTENTS_PLAYERCLIP = 0x10000;
inline constexpr int32_t CONTENTS_MONSTERCLIP = 0x20000;
inline constexpr int32_t CONTENTS_ORIGIN = 0x1000000;
inline constexpr int32_t CONTENTS_DETAIL = 0x8000000;
inline constexpr int32_t CONTENTS_TRANSLUCENT = 0x20000000;

} // namespace bt::quake::q3

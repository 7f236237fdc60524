// The tonemap operators' constants, one source for both tracers: scene/color.h includes
// this file as C++ and shaders/tonemap.comp as GLSL. Hence only #defines of float literals with
// the f suffix, which both languages read alike (GLSL since 1.30).
#ifndef BT_TONEMAP_CONSTANTS
#define BT_TONEMAP_CONSTANTS

// Narkowicz's fit of the ACES filmic curve: x (a x + b) / (x (c x + d) + e).
#define BT_ACES_A 2.51f
#define BT_ACES_B 0.03f
#define BT_ACES_C 2.43f
#define BT_ACES_D 0.59f
#define BT_ACES_E 0.14f

// AgX (Troy Sobotka): the inset matrix's rows, the log2 exposure range it maps to 0..1, the
// polynomial contrast fit by Benjamin Wrensch (x^6 .. x^0), the outset matrix's rows, and the
// display gamma it ends with.
#define BT_AGX_IN_ROW0 0.842479062253094f, 0.0784335999999992f, 0.0792237451477643f
#define BT_AGX_IN_ROW1 0.0423282422610123f, 0.878468636469772f, 0.0791661274605434f
#define BT_AGX_IN_ROW2 0.0423756549057051f, 0.0784336f, 0.879142973793104f
#define BT_AGX_MIN_EV -12.47393f
#define BT_AGX_MAX_EV 4.026069f
#define BT_AGX_POLY6 15.5f
#define BT_AGX_POLY5 -40.14f
#define BT_AGX_POLY4 31.96f
#define BT_AGX_POLY3 -6.868f
#define BT_AGX_POLY2 0.4298f
#define BT_AGX_POLY1 0.1191f
#define BT_AGX_POLY0 -0.00232f
#define BT_AGX_OUT_ROW0 1.19687900512017f, -0.0980208811401368f, -0.0990297440797205f
#define BT_AGX_OUT_ROW1 -0.0528968517574562f, 1.15190312990417f, -0.0989611768448433f
#define BT_AGX_OUT_ROW2 -0.0529716355144438f, -0.0980434501171241f, 1.15107367264116f
#define BT_AGX_GAMMA 2.2f

// The sRGB transfer function (IEC 61966-2-1).
#define BT_SRGB_LINEAR_LIMIT 0.0031308f
#define BT_SRGB_LINEAR_SLOPE 12.92f
#define BT_SRGB_SCALE 1.055f
#define BT_SRGB_OFFSET 0.055f
#define BT_SRGB_GAMMA 2.4f

#endif

// What an engine does to a stored luxel before it draws it, one source for both tracers:
// lighting/luxel_display.cpp includes this file as C++ (it builds the table), shaders/lightmaps.glsl
// as GLSL (it reads the table the C++ packs into the lightmap buffer). Only #defines of literals.
#ifndef BT_LUXEL_DISPLAY_CONSTANTS
#define BT_LUXEL_DISPLAY_CONSTANTS

// Lightmaps::luxelDisplay and WorldLighting::luxelDisplay.
#define BT_LUXEL_DISPLAY_IDENTITY 0u // Quake, Hexen II, Quake 2, Quake 3: the luxel as stored
#define BT_LUXEL_DISPLAY_GOLDSRC 1u  // Half-Life: GoldSrc's light gamma table

// Entries of the table: one per stored byte.
#define BT_LUXEL_TABLE_SIZE 256

// GoldSrc's display cvars at the engine's defaults, as Xash3D FWGS registers them
// (engine/client/gamma.c: `gamma` 2.5, `lightgamma` 2.5, `brightness` 0, `texgamma` 2.0).
#define BT_GOLDSRC_GAMMA 2.5f
#define BT_GOLDSRC_LIGHTGAMMA 2.5f
#define BT_GOLDSRC_BRIGHTNESS 0.0f
// Light style 'm' (world.cpp's "m" strings): ('m' - 'a') × 22, the weight of style 0.
#define BT_GOLDSRC_STYLE_M 264

#endif

// The light models' numbers, one source for both tracers: lighting/faithful.h, lighting/sampling.h
// and renderer/cpu/integrator.h include this file as C++, shaders/*.glsl as GLSL. Hence only
// #defines of literals (floats with the f suffix), which both languages read alike.
#ifndef BT_LIGHT_CONSTANTS
#define BT_LIGHT_CONSTANTS

#define BT_PI 3.14159265358979f

// ericw-tools `light` (faithful mode).
#define BT_FORMULA_SCALE 128.0f          // LF_SCALE: distances in the formulas are over 128 units
#define BT_OVERBRIGHT_ONE 128.0f         // the engine shows lightmap 128 as the texture's own colour
#define BT_SURFACE_HOTSPOT_CLAMP 16.0f   // radiosity surface lights: ltface.cc's hotspot clamp
#define BT_BOUNCE_HOTSPOT_CLAMP 128.0f   // bounce lights: IndirectLightFace's hotspot clamp
#define BT_BOUNCE_GATE 0.01f             // a bounce light's share below this in every channel is dropped
#define BT_BOUNCE_SHADOW_RAYS 16u        // shadow rays a shown point draws among its cell's bounce lights
#define BT_DIRT_AZIMUTH_STEPS 16         // dirt's fixed pattern (`_dirtmode 0`)
#define BT_DIRT_ELEVATION_STEPS 3
#define BT_DIRT_SAMPLE_LIFT 1.0f         // the compiler's sample points sit 1 unit off the face
#define BT_LIGHT_ANGLE_EPSILON 0.01f      // GetSurfaceLighting: a radiosity point this little (in cosine) behind still lights
#define BT_SUN_ANGLE_EPSILON 0.001f       // LightFace_Sky (ANGLE_EPSILON): a sun this little (in cosine) behind a face still lights it
#define BT_SUN_SAMPLES 64               // `-sunsamples`: the suns a sky dome or a sun's penumbra becomes
#define BT_NEAREST_LIGHT 0.1f            // GetLightContrib: a nearer light is this far, straight up (+z)
#define BT_VIS_BOX_EPSILON 0.001f        // CullLight: a light's and a face's boxes this near still touch
#define BT_VIS_RAYS 1024                 // EstimateVisibleBoundsAtPoint: 32 x 32 rays from each light
#define BT_VIS_RAY_LENGTH 65536.0f       // ... each this long at most
#define BT_VIS_BOX_GROWTH 0.25f          // ... whose bounds grow by this share of their size on each side

// q3map2 (faithful mode of Quake 3 levels, lighting/q3map2_light.h).
#define BT_Q3_HOTSPOT_CLAMP 16.0f        // LightContributionToSample: a point or spot light is never nearer than this
#define BT_Q3_SPOT_EDGE 32.0f            // ... and a spotlight's cone fades to 0 over its last 32 units of radius

// Physical mode.
#define BT_NEAR_LIST_PROBABILITY 0.9f    // light selection: a pick from the cell's near list
#define BT_SPECULAR_LOBE_PROBABILITY 0.5f
#define BT_HORIZON_MARGIN 0.01f          // shading normals: Iray's margin above the face's plane
#define BT_PHYSICAL_LIGHT_UNIT 128.0f    // Quake light units per physical unit (point: x pi, sun: / pi)
// What the game shows of a light, in linear terms, over the light itself at a typical lightmap
// value: the engine multiplies texture x lightmap / 128 in the display's gamma space, so lightmap
// fraction L shows about L^2.2 where linear light gives L. Matched at L0 = 0.65, the lightmap
// whose display is the mean display of e1m1's and lqdm5's compiled lightmaps (0.60, 0.70):
// L0^1.2 = 0.60 (lighting/README.md, "Physical mode", the display match).
#define BT_PHYSICAL_DISPLAY_MATCH 0.6f
#define BT_PHYSICAL_REACH_THRESHOLD 1.0f // light units: where an inverse-formula light ends in physical mode
#define BT_CLAMP_INDIRECT_DEFAULT 32.0f  // units: --clamp-indirect's default (lighting/README.md, "Fireflies")

// Physical mode's low-discrepancy dimensions (lighting/sampling.h Rng::at): where each draw of a
// path's sample sits in the pixel's scrambled Sobol sequence. The camera's subpixel first, then
// a block per surface, each group at a fixed place in it so that a pixel's samples stratify the
// same decision together whatever the draws before it; a 2D draw starts at an even dimension
// (a Sobol pair). Draws outside the groups (liquids, suns' cones) take the PCG stream.
#define BT_DIM_CAMERA 0u                 // 0-1: subpixel
#define BT_DIM_FIRST_SURFACE 2u
#define BT_DIMS_PER_SURFACE 14u
#define BT_DIM_LIGHT_PICK 0u             // 0-1: near list or not, which light (the tree: 0)
#define BT_DIM_LIGHT_POINT 2u            // 2-4: the picked light's _deviance jitter
#define BT_DIM_EMITTER 5u                // 5: which emitter triangle, 6-7: the point on it
#define BT_DIM_BSDF 8u                   // 8: the lobe (specular materials), 8-9 or 10-11: the direction
#define BT_DIM_ROULETTE 12u              // 12: Russian roulette
#define BT_DIM_PCG 0x3ffu                // not a dimension: the draw takes the PCG stream
#define BT_DIM_BITS 10u                  // Rng keeps the dimension in its low 10 bits (at most 65 surfaces)

#endif

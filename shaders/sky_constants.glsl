// Quake's two-layer sky as QuakeSpasm draws it (Quake/gl_sky.c), one source for both tracers:
// lighting/sky.cpp includes this file as C++, shaders/sky.glsl as GLSL. Hence only
// #defines of literals (floats with the f suffix), which both languages read alike.
#ifndef BT_SKY_CONSTANTS
#define BT_SKY_CONSTANTS

// Sky_GetTexCoord: the direction from the eye, z scaled by 3 ("flatten the sphere"), scaled to
// a length of 6*63, over 128: texture repeats of each 128x128 layer (plus the scroll, 0 at time 0).
#define BT_SKY_FLATTEN 3.0f
#define BT_SKY_RADIUS 378.0f       // 6*63
#define BT_SKY_LAYER_SCALE 128.0f  // the 1.0/128 of Sky_GetTexCoord

// Sky boxes (QuakeSpasm Sky_EmitSkyBoxVertex; Quake 2's R_DrawSkyBox, gl_warp.c, has the same
// tables): side i of the box holds the points whose world axis j is the sign of k times b[|k|-1],
// k = st_to_vec[i][j], b = (s, t, 1) times the distance, s and t in [-1, 1]; it shows image
// skytexorder[i] of the suffixes rt, bk, lf, ft, up, dn. Sides: +x, -x, +y, -y, +z, -z.
#define BT_SKY_ST_TO_VEC 3, -1, 2, -3, 1, 2, 1, 3, 2, -1, -3, 2, -2, -1, 3, 2, -1, -3
#define BT_SKY_TEX_ORDER 0, 2, 1, 3, 4, 5

// The baked sky (lighting/sky.h SkyMap, shaders/sky.glsl): texels along a cube face's edge, and
// the floor of a direction's largest component (a zero direction reads a texel, not a NaN).
#define BT_SKY_MAP_LAYERS_SIZE 512 // Quake's 128x128 layers, magnified about 2x across the up face
#define BT_SKY_MAP_MIN_SIZE 256    // a sky box's largest side, within these bounds
#define BT_SKY_MAP_MAX_SIZE 1024
#define BT_SKY_MAP_TINY 1e-30f

#endif

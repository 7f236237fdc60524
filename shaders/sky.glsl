// The sky as lighting/sky.h bakes it (QuakeSpasm, Quake/gl_sky.c; ioquake3 tr_sky.c): a sky face
// of a level with sky images (world.skySize > 0) shows them by the ray's direction, the same on
// every sky face, whatever point of it the ray meets. Comes after scene_buffers.glsl.
//
// The CPU runs the engine's rule once per texel of a cube map at load (SkyMap); here a direction
// names a texel of it and is read with one texelFetch. The material sampling code of
// textures.glsl is not called: each call site of it is another inlined copy of the bindless or
// array sampling for NVIDIA's compiler, which costs registers and occupancy in the whole path
// tracer, levels without sky included (bench/README.md). A path meets the sky once, where the
// hit is read (pathtrace.comp advance), as a miss would.
#include "sky_constants.glsl"

layout(binding = BT_TEXTURE_SKY) uniform sampler2DArray skyMap; // six faces: +x, -x, +y, -y, +z, -z

// lighting/sky.cpp skyMapTexel, step for step: the largest component picks the face (ties to x,
// then y), the next two components cyclically over it are u, v in [-1, 1], and the texel is the
// one they fall in (nearest: no filtering).
ivec3 skyMapTexel(vec3 dir, int size) {
  vec3 a = abs(dir);
  int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
  vec3 p = axis == 0 ? dir : axis == 1 ? dir.yzx : dir.zxy;
  float major = max(abs(p.x), BT_SKY_MAP_TINY);
  float halfSize = 0.5 * float(size);
  ivec2 ij = clamp(ivec2(floor((p.yz / major + 1.0) * halfSize)), ivec2(0), ivec2(size - 1));
  return ivec3(ij, 2 * axis + (p.x < 0.0 ? 1 : 0));
}

// The level's sky along dir, linear radiance.
vec3 skyRadiance(vec3 dir) {
  return texelFetch(skyMap, skyMapTexel(dir, int(world.skySize)), 0).rgb;
}

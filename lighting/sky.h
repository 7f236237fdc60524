// What a ray that meets a sky face sees where the level has sky images (Scene::sky), as the
// engine draws its sky: Quake's two layers (QuakeSpasm, Quake/gl_sky.c) or a sky box, by the
// ray's direction alone.
//
// The tracers do not run the engine's rule per ray: buildRenderScene bakes it once into a
// SkyMap, six square faces addressed by direction (a cube map), and both tracers read one texel
// of it (skyRadiance here, shaders/sky.glsl on the GPU). Reading the material textures from
// the path tracer's kernels costs every level registers and occupancy on NVIDIA's compiler,
// sky or none (bench/README.md, session 12); one fetch from one fixed texture does not.
#pragma once

#include "scene/scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace bt {

// Sky_GetTexCoord at time 0: the texture coordinates (in repeats of a 128x128 layer) of the
// layers seen along `dir` (from the eye; any length).
glm::vec2 skyLayerUv(const glm::vec3& dir);

// Sky boxes (QuakeSpasm Sky_DrawSkyBox, Quake 2 R_DrawSkyBox, ioquake3 DrawSkyBox): the side a
// direction meets (+x, -x, +y, -y, +z, -z, as Sky_ProjectPoly picks it) and where it meets that
// side's image, in repeats of a width x height image: pulled in by half a texel
// (Sky_EmitSkyBoxVertex), or with `clamped` held to the edge texels' centres (Quake 3's clamp
// to edge).
int skyBoxSide(const glm::vec3& dir);
glm::vec2 skyBoxUv(int side, const glm::vec3& dir, int width, int height, bool clamped = false);

// The level's sky seen along `dir`, sRGB-encoded as stored. Needs scene.sky.
glm::vec3 skyColor(const Scene& scene, const glm::vec3& dir);

// The level's sky baked by direction: face f (+x, -x, +y, -y, +z, -z) holds the directions
// whose largest component is along its axis; texel (i, j) of it the engine's sky along the
// direction through its centre. Linear radiance (the sRGB images decoded), as half floats, which
// the GPU's RGBA16F texture holds bit for bit, so both tracers read the same numbers.
struct SkyMap {
  int size = 0;                 // texels along a face's edge; 0 = the level has no sky images
  std::vector<uint16_t> texels; // RGBA half floats, face by face, rows of `size` texels
};

// The resolution that keeps the images' texels: a sky box's largest side (at least 256, at most
// 1024 a face); Quake's 128x128 layers 512 a face (a layer repeats about twice across the up
// face, magnified ~2x; towards the horizon the engine's own view compresses them).
int skyMapSize(const Scene& scene);
// skyColor at the centre of every texel; an empty map (size 0) without scene.sky.
SkyMap bakeSkyMap(const Scene& scene, unsigned threads = 0);

// The texel (i, j) of face f = .z a direction reads (shaders/sky.glsl skyMapTexel, the same
// arithmetic: nearest texel, no filtering), and the direction through a texel's centre.
glm::ivec3 skyMapTexel(const glm::vec3& dir, int size);
glm::vec3 skyMapTexelDirection(const glm::ivec3& texel, int size);
// The sky's linear radiance along dir: the texel skyMapTexel names. Needs map.size > 0.
glm::vec3 skyRadiance(const SkyMap& map, const glm::vec3& dir);

} // namespace bt

// What a ray that meets a sky face sees where the level has sky images (Scene::sky), as the
// engine draws its sky: Quake's two layers (QuakeSpasm, Quake/gl_sky.c) or a sky box, by the
// ray's direction alone. The integrator asks for it once, on meeting a sky face, before any
// surface shading (as a miss); shaders/sky.glsl computes the same on the GPU.
#pragma once

#include "scene/scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

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

} // namespace bt

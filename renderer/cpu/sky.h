// What a ray that meets a sky face sees, as the engine draws the sky: the level's sky box, else
// Quake's two layers, by the ray's direction (QuakeSpasm, Quake/gl_sky.c), else the face's own
// texture as before.
// shaders/textures.glsl (skyLayerUv, baseOrSkyColor) computes the same on the GPU.
#pragma once

#include "lighting/render_scene.h"
#include "scene/material.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>

namespace bt {

// Sky_GetTexCoord at time 0: the texture coordinates (in repeats of a 128x128 layer) of the
// layers seen along `dir` (from the eye; any length).
glm::vec2 skyLayerUv(const glm::vec3& dir);

// The front layer drawn over the back layer (GL_DECAL), sRGB-encoded as stored, a = 1.
glm::vec4 skyLayersColor(const Material& sky, const glm::vec3& dir);

// Sky boxes (QuakeSpasm Sky_DrawSkyBox, Quake 2 R_DrawSkyBox): the side a direction meets
// (+x, -x, +y, -y, +z, -z, as Sky_ProjectPoly picks it), where it meets that side's image (in
// repeats of a width x height image: Sky_EmitSkyBoxVertex's coordinates), and the colour seen
// (sRGB-encoded, a = 1). skyBoxColor needs scene.skyBox.
int skyBoxSide(const glm::vec3& dir);
glm::vec2 skyBoxUv(int side, const glm::vec3& dir, int width, int height);
glm::vec4 skyBoxColor(const Scene& scene, const glm::vec3& dir);

// The colour a ray along `dir` sees at p on `face`: the sky's layers where the face is sky with
// a sky box (Scene::skyBox), else its layers where its texture has them, else the face's base colour (baseColorAt). sRGB-encoded, a = coverage.
glm::vec4 baseOrSkyColor(const RenderScene& rs, uint32_t face, const glm::vec3& p, const glm::vec3& dir);

} // namespace bt

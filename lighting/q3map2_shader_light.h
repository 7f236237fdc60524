// q3map2's light from Quake 3 shaders (scene/material.h Material::q3, read by the importers):
// surface lights (`q3map_surfacelight`, light.c CreateSurfaceLights, light_bounce.c
// RadSubdivideDiffuseLight), sky shaders' suns (`q3map_sun`, `q3map_sunExt`: CreateSunLight) and
// sky lights (`q3map_skylight`: CreateSkyLights), turned into the GpuLights both tracers already
// evaluate. lighting/README.md ("Quake 3 in faithful mode") gives each key and formula.
#pragma once

#include "bvh/trace_scene.h"
#include "lighting/lights.h"
#include "lighting/qbsp_faces.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <vector>

namespace bt::q3map2 {

// light.c's globals: a surface light is cut until no piece is wider than defaultLightSubdivide
// (or the shader's q3map_lightSubdivide) on any axis, and each piece carries value × area ×
// areaScale photons (light_bounce.c RadSubdivideDiffuseLight).
inline constexpr float kDefaultLightSubdivide = 120.0f;
inline constexpr float kAreaScale = 0.25f;
// A piece's light sits this far off its face (RadSubdivideDiffuseLight "nudge it off the plane").
inline constexpr float kAreaLightLift = 1.0f;
// More surface-light pieces than this make the level's light list absurd: the rest are left out, with a warning.
inline constexpr size_t kMaxShaderLights = 65536;

// The directions towards the sky of CreateSkyLights (q3map2 2.5.17): iterations − 1 rings of
// 4 × (iterations − 1) suns, the first at half an elevation step (90° / iterations) and each ring
// turned by a step / rings, plus one straight up.
std::vector<glm::vec3> skyLightDirections(int iterations);

// The direction towards a q3map_sun: (cos a cos e, sin a cos e, sin e).
glm::vec3 sunDirection(float degrees, float elevation);

// The suns of every shader of the level's materials: each q3map_sun / q3map_sunExt line
// (CreateSunLight; the colour normalised to unit length, as ParseShaderFile does) and the
// q3map_skylight dome (value / suns each, in the shader's light colour). Appended to out.lights.
void addShaderSuns(const Scene& scene, SceneLights& out);

// The surface lights of the faces whose shader has q3map_surfacelight: what the compiler keeps of
// each face (visibleFragments; nothing that looks into the void), triangulated, each triangle
// cut at the middle of its bounds until it fits the subdivision, each piece a LightFormula::Q3Area
// light at its bounds' centre, and its backsplash point light (q3map_backsplash: fraction ×
// photons, `distance` units further out). Mesh triangles (curves) emit from their front side.
std::vector<GpuLight> shaderSurfaceLights(const Scene& scene, const std::vector<BrushContents>& contents, const TraceScene& tracer,
                                          Diagnostics& diagnostics);

// The classes a face takes from its shader: surfaceparm sky (and q3map_sun) make it sky, nodraw
// hidden, a first stage's blendFunc a liquid (drawn blended: lighting/liquids.h).
uint32_t shaderFaceFlags(const Material& material);

} // namespace bt::q3map2

// Lights, emitters and shading parameters as flat std430 structs: the CPU tracer reads them
// from std::vectors and the GL tracer from shader storage buffers, so both see the same bytes.
// (To be appended to scene/gpu_structs.h once that header lands; kept here so the renderer
// builds on its own.)
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>

namespace bt {

// ericw-tools' `delay` key: how a point light's value falls off with distance.
enum class LightFormula : uint32_t {
  Linear = 0,       // value - dist * wait           (Quake's own, the default)
  Inverse = 1,      // value * 128 / (dist * wait)
  Inverse2 = 2,     // value * 128^2 / (dist * wait)^2
  Infinite = 3,     // value, at any distance
  LocalMin = 4,     // value, at any distance, but as a floor (like worldspawn minlight)
  Inverse2A = 5,    // value * 128^2 / (dist * wait + 128)^2: inverse square without the pole
};

enum class LightType : uint32_t {
  Point = 0,  // light entity, with a cone when `spotCosOuter > -1`
  Sun = 1,    // worldspawn _sunlight: parallel light that must reach a sky face
  Dome = 2,   // worldspawn _sunlight2 (upper) / _sunlight3 (lower): sky-dome light from sky faces
};

// One light. Values are in Quake light units (the `light` key); colours are 0..1.
struct GpuLight {
  glm::vec3 origin{0.0f};      // point: position; sun/dome: unused
  uint32_t type = 0;           // LightType
  glm::vec3 color{1.0f};       // _color normalised to 0..1
  float value = 300.0f;        // `light`, or _sunlight/_sunlight2/_sunlight3
  glm::vec3 direction{0.0f, 0.0f, -1.0f}; // spot axis / direction the sun shines (unit); dome: +z upper, -z lower
  float cosOuter = -2.0f;      // spotlights: cos(angle / 2); below -1 = no cone
  uint32_t formula = 0;        // LightFormula (point lights)
  float atten = 1.0f;          // `wait`: scales distance in the falloff formulas
  float falloff = 0.0f;        // `_falloff`: linear falloff to zero at this distance (0 = off)
  float anglescale = 0.5f;     // `_anglescale`: 0 ignores the incidence angle, 1 is Lambert
  float cosInner = -2.0f;      // spotlights: cos(_softangle / 2), full brightness inside
  float deviance = 0.0f;       // `_deviance` (point) or _sunlight_penumbra in radians (sun): soft shadow radius
  uint32_t flags = 0;          // kLightFlag*
  uint32_t surfaceMaterial = 0xffffffffu; // _surface template: the emitting material, else ~0
};
static_assert(sizeof(GpuLight) == 80);
static_assert(offsetof(GpuLight, cosInner) == 64);
static_assert(offsetof(GpuLight, color) == 16);
static_assert(offsetof(GpuLight, direction) == 32);
static_assert(offsetof(GpuLight, formula) == 48);

constexpr uint32_t kLightFlagStartOff = 1u;  // spawnflags & 1 on a styled light: dark by default
constexpr uint32_t kLightFlagBleed = 2u;     // `_bleed`: lights surfaces behind it too

// Face classes, one uint32 per scene face (RenderScene::faceFlags); the geometry and texture
// frame of a face are the bvh part's GpuFace (scene/gpu_structs.h).
constexpr uint32_t kFaceHidden = 1u;     // clip, trigger, skip, hint, origin, common/*: never seen
constexpr uint32_t kFaceSky = 2u;        // sky*: the environment, and where sunlight comes from
constexpr uint32_t kFaceLiquid = 4u;     // '*' textures / Q2 liquid contents: unlit unless _litwater
constexpr uint32_t kFaceNoShadow = 8u;   // faithful mode: does not block light (brush entity without _shadow)
constexpr uint32_t kFaceEmissive = 16u;  // has emissive texels or is a _surface template

// Per-material parameters; the images themselves travel as textures.
struct GpuMaterial {
  glm::vec4 averageAlbedo{0.5f}; // linear RGB mean of the base colour, a = coverage
  glm::vec4 emission{0.0f};      // rgb: radiance scale for emissive texels (physical), a: _surface radiance
  glm::vec2 size{64.0f};         // texels: texture coordinates divide by it
  float roughness = 0.8f;
  float metallic = 0.0f;
  uint32_t flags = 0;            // kMaterial*
  uint32_t pad[3] = {0, 0, 0};
};
static_assert(sizeof(GpuMaterial) == 64);

constexpr uint32_t kMaterialSpecular = 1u; // has a PBR set (roughness/metallic map): GGX + diffuse
constexpr uint32_t kMaterialEmissive = 2u; // has an emissive map with lit texels

// One triangle of an emitting face, for next-event estimation by area.
struct GpuEmitter {
  glm::vec3 v0{0.0f};
  uint32_t face = 0;
  glm::vec3 v1{0.0f};
  float area = 0.0f;
  glm::vec3 v2{0.0f};
  float cdf = 0.0f;             // running sum of areas / total, the last one is 1
};
static_assert(sizeof(GpuEmitter) == 48);

} // namespace bt

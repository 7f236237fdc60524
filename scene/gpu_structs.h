// The structs that the CPU tracer and the GL compute tracer share, byte for byte.
//
// Every struct here is uploaded as-is into a std430 shader storage buffer, so each one is made
// of 4-byte scalars laid out in 16-byte rows (a vec3 followed by one 4-byte scalar, as std430
// packs `vec3 a; uint b;`). The static_asserts pin the size and every offset; the GLSL
// declaration that matches is written beside each struct. Other parts append their own
// sections (materials, lights, ...) below, in the same style.
#pragma once

#include "shaders/scene_constants.glsl" // the flag bits and codes, shared with the shaders

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>

namespace bt {

// "No face": an unused slot in GpuBrush::axialFace.
inline constexpr uint32_t kNoFace = BT_NO_FACE;

// ---------------------------------------------------------------------------------------------
// BVH (bvh/trace_scene.h builds these)
// ---------------------------------------------------------------------------------------------

// No leaf of a TraceScene BVH is deeper than this (root = depth 0), so a traversal stack of
// kBvhMaxDepth entries never overflows.
inline constexpr uint32_t kBvhMaxDepth = 64;

// One node of the flattened brush BVH, 32 bytes. nodes[0] is the root.
//   count == 0: interior node; its children are nodes[leftFirst] and nodes[leftFirst + 1].
//   count >  0: leaf; it holds brushes[leftFirst .. leftFirst + count) of TraceScene::brushes().
// A scene with no traceable brush has no nodes at all (check the node count before traversal).
// The bounds are rounded outward from the brush bounds, so they always contain their brushes.
//
//   struct BvhNode { vec3 boundsMin; uint leftFirst; vec3 boundsMax; uint count; };
struct GpuBvhNode {
  float boundsMin[3];
  uint32_t leftFirst;
  float boundsMax[3];
  uint32_t count;
};
static_assert(sizeof(GpuBvhNode) == 32);
static_assert(offsetof(GpuBvhNode, boundsMin) == 0);
static_assert(offsetof(GpuBvhNode, leftFirst) == 12);
static_assert(offsetof(GpuBvhNode, boundsMax) == 16);
static_assert(offsetof(GpuBvhNode, count) == 28);

// One brush, 64 bytes, in BVH leaf order (not Scene order: sceneBrush maps back).
//
// A brush is the intersection of the half-spaces behind its faces' planes. The ray test
// (Haines' convex polyhedron clip) takes the axial planes from the bounds instead of from the
// faces, the way Quake 3's collision code keeps brush sides axial-first: a box brush then costs
// one slab test and nothing else. So:
//   - boundsMin/boundsMax: the brush's bounding box. A side of the box that carries an axial
//     face sits exactly at that face's plane (float(dist)); the other sides come from the
//     windings, rounded outward.
//   - axialFace[6]: the face lying on each side of the box, in the order -X, +X, -Y, +Y, -Z, +Z,
//     or kNoFace where no face of the brush lies on that side (only an edge or a vertex of the
//     brush touches it).
//   - sides[firstSide .. firstSide + sideCount) of TraceScene::sides(): the face indices of the
//     remaining (non-axial) faces, whose planes the test clips against one by one.
// Face indices index TraceScene::faces() and Scene::faces alike.
//
//   struct Brush { vec3 boundsMin; uint firstSide; vec3 boundsMax; uint sideCount;
//                  uint axialFace[6]; uint sceneBrush; uint pad; };
struct GpuBrush {
  float boundsMin[3];
  uint32_t firstSide;
  float boundsMax[3];
  uint32_t sideCount;
  uint32_t axialFace[6];
  uint32_t sceneBrush; // index into Scene::brushes
  uint32_t pad;        // zero in the TraceScene; the GL upload puts the rule-from-inside channel bits here (gl_scene.cpp)
};
static_assert(sizeof(GpuBrush) == 64);
static_assert(offsetof(GpuBrush, boundsMin) == 0);
static_assert(offsetof(GpuBrush, firstSide) == 12);
static_assert(offsetof(GpuBrush, boundsMax) == 16);
static_assert(offsetof(GpuBrush, sideCount) == 28);
static_assert(offsetof(GpuBrush, axialFace) == 32);
static_assert(offsetof(GpuBrush, sceneBrush) == 56);
static_assert(offsetof(GpuBrush, pad) == 60);

// One face (brush side), 64 bytes, in Scene::faces order: faces[i] is Scene::faces[i].
//   plane:  normal xyz (unit, pointing out of the brush) and dist w; p is on the plane when
//           dot(normal, p) == dist.
//   origin, tangent, bitangent: the texture frame of scene.h, in texels:
//           s = dot(p - origin, tangent), t = dot(p - origin, bitangent);
//           the texture is sampled at (s / material width, t / material height).
//   material: index into Scene::materials; brush: index into Scene::brushes.
// Faces with an empty winding (redundant planes) are never hit.
//
//   struct Face { vec4 plane; vec3 origin; uint material; vec3 tangent; uint brush;
//                 vec3 bitangent; uint pad; };
struct GpuFace {
  float plane[4];
  float origin[3];
  uint32_t material;
  float tangent[3];
  uint32_t brush;
  float bitangent[3];
  // zero here; the GL upload writes a Quake 2 glass face's alpha there, as a float's bits
  // (RenderScene::glassAlpha, renderer/gl/gl_scene.cpp), for the faithful path tracer
  uint32_t pad;
};
static_assert(sizeof(GpuFace) == 64);
static_assert(offsetof(GpuFace, plane) == 0);
static_assert(offsetof(GpuFace, origin) == 16);
static_assert(offsetof(GpuFace, material) == 28);
static_assert(offsetof(GpuFace, tangent) == 32);
static_assert(offsetof(GpuFace, brush) == 44);
static_assert(offsetof(GpuFace, bitangent) == 48);
static_assert(offsetof(GpuFace, pad) == 60);

// One mesh triangle (scene.h Mesh), 48 bytes, in the order of the triangle BVH's leaves.
// Triangles have a BVH of their own (TraceScene::triangleNodes(), GpuBvhNode as above, its
// leaves holding triangles[leftFirst .. + count)), traversed after the brush BVH, so that a level
// without meshes traces its brushes exactly as before. The ray test is Moller-Trumbore with the
// barycentric bounds widened by kTriangleEdgeEpsilon (neighbours overlap by a hair instead of
// leaving cracks a ray slips through); a hit is double-sided and meets face `face` (the front
// side, Scene::faces) when the ray comes from the front (det > 0), else face + 1 (the back side).
//
//   struct Triangle { vec3 v0; uint face; vec3 v1; uint pad0; vec3 v2; uint pad1; };
struct GpuTriangle {
  float v0[3];
  uint32_t face;
  float v1[3];
  uint32_t pad0; // zero
  float v2[3];
  uint32_t pad1; // zero
};
static_assert(sizeof(GpuTriangle) == 48);
static_assert(offsetof(GpuTriangle, v0) == 0);
static_assert(offsetof(GpuTriangle, face) == 12);
static_assert(offsetof(GpuTriangle, v1) == 16);
static_assert(offsetof(GpuTriangle, pad0) == 28);
static_assert(offsetof(GpuTriangle, v2) == 32);
static_assert(offsetof(GpuTriangle, pad1) == 44);

// How far outside a triangle, in barycentric units, a ray still hits it (see GpuTriangle): 2^-20.
// The shaders get the inverse as BT_TRIANGLE_EDGE_EPSILON_INVERSE (renderer/gl reads it from here).
inline constexpr uint32_t kTriangleEdgeEpsilonInverse = 1048576;
inline constexpr float kTriangleEdgeEpsilon = 1.0f / float(kTriangleEdgeEpsilonInverse);

// ---------------------------------------------------------------------------------------------
// Lighting and shading (renderer/cpu builds these; renderer/gl uploads them unchanged)
// Lights, emitters and shading parameters: the CPU tracer reads them from std::vectors and the
// GL tracer from shader storage buffers (shaders/structs.glsl), so both see the same bytes.
// ---------------------------------------------------------------------------------------------
// ericw-tools' `delay` key: how a point light's value falls off with distance.
enum class LightFormula : uint32_t {
  Linear = BT_FORMULA_LINEAR,       // value - dist * wait           (Quake's own, the default)
  Inverse = BT_FORMULA_INVERSE,     // value * 128 / (dist * wait)
  Inverse2 = BT_FORMULA_INVERSE2,   // value * 128^2 / (dist * wait)^2
  Infinite = BT_FORMULA_INFINITE,   // value, at any distance
  LocalMin = BT_FORMULA_LOCAL_MIN,  // value, at any distance, but as a floor (like worldspawn minlight)
  Inverse2A = BT_FORMULA_INVERSE2A, // value * 128^2 / (dist * wait + 128)^2: inverse square without the pole
  // Not a `delay` value: one point of an ericw-tools radiosity surface light (_surface with
  // _surface_radiosity 1): value / max(dist, 16)^2, times a half-Lambert term on both the
  // emitting face (`direction` is its normal) and the receiving one.
  SurfaceRadiosity = BT_FORMULA_SURFACE_RADIOSITY,
  // Not a `delay` value either: one ericw-tools bounce light (lighting/bounce.h), a lit face
  // re-emitting its mean direct light: value / max(dist, 128)^2, times the cosine on the emitting
  // face (`direction` is its normal) and on the receiving one (anglescale 1).
  Bounce = BT_FORMULA_BOUNCE,
  // Quake 3's q3map2 (lighting/q3map2_light.h): value × 128² / max(dist, 16)², 0 from `falloff`
  // (q3map2's envelope) on; `value` is q3map2's photons / 128², so physical mode reads it as an
  // inverse-square light of the same brightness.
  Q3Point = BT_FORMULA_Q3_POINT,
  // q3map2's linear light (spawnflags 1): value - max(dist, 16) × atten (`fade`), 0 from `falloff` on.
  Q3Linear = BT_FORMULA_Q3_LINEAR,
  // One piece of a q3map2 surface light (`q3map_surfacelight`), as its area light's `-faster`
  // approximation: Q3Point's law times the cosine on the emitting face (`direction` is its normal).
  Q3Area = BT_FORMULA_Q3_AREA,
};

enum class LightType : uint32_t {
  Point = BT_LIGHT_POINT, // light entity, with a cone when `spotCosOuter > -1`
  Sun = BT_LIGHT_SUN,     // worldspawn _sunlight: parallel light that must reach a sky face
  Dome = BT_LIGHT_DOME,   // worldspawn _sunlight2 (upper) / _sunlight3 (lower): sky-dome light from sky faces
};

// ericw-tools' CHANNEL_MASK_DEFAULT: the lighting channel of every light, face and ray that sets none.
constexpr uint32_t kDefaultChannels = 1;

// One light. Values are in Quake light units (the `light` key); colours are 0..1.
struct GpuLight {
  glm::vec3 origin{0.0f};                 // point: position; sun/dome: unused
  uint32_t type = 0;                      // LightType
  glm::vec3 color{1.0f};                  // _color normalised to 0..1
  float value = 300.0f;                   // `light`, or _sunlight/_sunlight2/_sunlight3
  glm::vec3 direction{0.0f, 0.0f, -1.0f}; // spot axis / direction the sun shines (unit); dome: +z upper, -z lower
  float cosOuter = -2.0f;                 // spotlights: cos(angle / 2); below -1 = no cone
  uint32_t formula = 0;                   // LightFormula (point lights)
  float atten = 1.0f;                     // `wait`: scales distance in the falloff formulas
  float falloff = 0.0f;                   // `_falloff`: linear falloff to zero at this distance (0 = off)
  float anglescale = 0.5f;                // `_anglescale`: 0 ignores the incidence angle, 1 is Lambert
  float cosInner = -2.0f;                 // spotlights: cos(_softangle / 2), full brightness inside; with
                                          // kLightFlagQ3Spot q3map2's radiusByDist (cone radius per unit along the axis)
  float deviance = 0.0f;                  // `_deviance` (point) or _sunlight_penumbra in radians (sun): soft shadow radius
  uint32_t flags = 0;                     // kLightFlag*
  float faithfulScale = 1.0f;             // faithful mode uses value * this: ericw-tools' count of jittered copies of a
                                          // linear light (each keeps the full value); on a per-material _surface
                                          // template with kLightFlagFaceMinlight, the face minlight scale
  // Faithful dirt (ambient occlusion), read only with kLightFlagDirt: the light's own
  // `_dirtscale` / `_dirtgain` (or the worldspawn's), and with kLightFlagDirtRadius the distances
  // `_dirt_off_radius` / `_dirt_on_radius` between which dirt ramps in (lighting/faithful.h).
  float dirtScale = 1.0f;
  float dirtGain = 1.0f;
  float dirtOffRadius = 0.0f;
  float dirtOnRadius = 0.0f;
  // Suns with `_suntexture`: 1 + the material of the sky faces they shine through (a sun ray that
  // reaches sky of another texture is blocked); 0: any sky.
  uint32_t skyMaterial = 0;
  // ericw-tools' lighting channels: a point light lights only
  // faces whose object mask (`_object_channel_mask`) shares a bit with `_light_channel_mask`, and
  // only such faces of `_shadow_channel_mask` (default: the light mask) block its rays.
  uint32_t lightChannels = kDefaultChannels;
  uint32_t shadowChannels = kDefaultChannels;
  // With kLightFlagSunTable (a sun with a penumbra): where its kSunSamples directions begin in
  // RenderScene::sunTable, the compiler's own suns (lighting/penumbra_suns.h).
  uint32_t sunTable = 0;
  // Physical mode's windowed inverse-square light (lighting/physical_light.h), set once per light
  // by physical::prepare so that the tracers' light loops do not re-derive it per sample:
  // intensity in light units x distance^2, and 1 / the light's reach (0: it never ends).
  float physicalIntensity = 0.0f;
  float physicalInvReach = 0.0f;
  // ericw-tools' light culling without vis data (lighting/vis_approx.h): 1 + the light's box in
  // RenderScene::visBoxes, which a face whose compiled bounds lie apart from it gets no light
  // from; 0: never culled.
  uint32_t visBox = 0;
  // Physical mode's light selection weighs a light by the colour it emits (physical::colour):
  // the sum of its hue's channels (physical::hueSum, 1 to 3), set by physical::prepare, so that
  // the tracers' near lists need no pow per light. The last 4 bytes of 128, so that no light
  // straddles a 128-byte cache line.
  float physicalHueSum = 0.0f;
};
static_assert(sizeof(GpuLight) == 128);
static_assert(offsetof(GpuLight, origin) == 0);
static_assert(offsetof(GpuLight, type) == 12);
static_assert(offsetof(GpuLight, color) == 16);
static_assert(offsetof(GpuLight, value) == 28);
static_assert(offsetof(GpuLight, direction) == 32);
static_assert(offsetof(GpuLight, cosOuter) == 44);
static_assert(offsetof(GpuLight, formula) == 48);
static_assert(offsetof(GpuLight, atten) == 52);
static_assert(offsetof(GpuLight, falloff) == 56);
static_assert(offsetof(GpuLight, anglescale) == 60);
static_assert(offsetof(GpuLight, cosInner) == 64);
static_assert(offsetof(GpuLight, deviance) == 68);
static_assert(offsetof(GpuLight, flags) == 72);
static_assert(offsetof(GpuLight, faithfulScale) == 76);
static_assert(offsetof(GpuLight, dirtScale) == 80);
static_assert(offsetof(GpuLight, dirtGain) == 84);
static_assert(offsetof(GpuLight, dirtOffRadius) == 88);
static_assert(offsetof(GpuLight, dirtOnRadius) == 92);
static_assert(offsetof(GpuLight, skyMaterial) == 96);
static_assert(offsetof(GpuLight, lightChannels) == 100);
static_assert(offsetof(GpuLight, shadowChannels) == 104);
static_assert(offsetof(GpuLight, sunTable) == 108);
static_assert(offsetof(GpuLight, physicalIntensity) == 112);
static_assert(offsetof(GpuLight, physicalInvReach) == 116);
static_assert(offsetof(GpuLight, visBox) == 120);
static_assert(offsetof(GpuLight, physicalHueSum) == 124);

constexpr uint32_t kLightFlagStartOff = BT_LIGHT_FLAG_START_OFF; // spawnflags & 1 on a styled light: dark by default
constexpr uint32_t kLightFlagBleed = BT_LIGHT_FLAG_BLEED;        // `_bleed`: lights surfaces behind it too
constexpr uint32_t kLightFlagFromSurface =
    BT_LIGHT_FLAG_FROM_SURFACE; // faithful-only point light: a _surface template's point, or a bounce light
                                // (physical mode lights those faces as area emitters instead)
constexpr uint32_t kLightFlagFaceMinlight = BT_LIGHT_FLAG_FACE_MINLIGHT; // per-material _surface template (radiosity kind): in faithful
                                                                         // mode its faces get value * faithfulScale * colour as minlight
constexpr uint32_t kLightFlagDirt = BT_LIGHT_FLAG_DIRT;              // faithful: dimmed by dirt (worldspawn _dirt, or the light's _dirt 1)
constexpr uint32_t kLightFlagDirtRadius = BT_LIGHT_FLAG_DIRT_RADIUS; // ... only beyond _dirt_off_radius, fully beyond _dirt_on_radius
constexpr uint32_t kLightFlagQ3Spot = BT_LIGHT_FLAG_Q3_SPOT;         // q3map2 spotlight: cone of radius cosInner (its radiusByDist) x the
                                                                     // distance along `direction`, fading over the last 32 units
constexpr uint32_t kLightFlagSunTable =
    BT_LIGHT_FLAG_SUN_TABLE; // a penumbra sun whose luxel samples are the compiler's directions (sunTable)

// Face classes, one uint32 per scene face (RenderScene::faceFlags); the geometry and texture
// frame of a face are the bvh part's GpuFace (scene/gpu_structs.h).
constexpr uint32_t kFaceHidden = BT_FACE_HIDDEN;      // clip, trigger, skip, hint, origin, common/*: never seen
constexpr uint32_t kFaceSky = BT_FACE_SKY;            // sky*: the environment, and where sunlight comes from
constexpr uint32_t kFaceLiquid = BT_FACE_LIQUID;      // '*' textures / Q2 liquid contents: unlit unless _litwater
constexpr uint32_t kFaceNoShadow = BT_FACE_NO_SHADOW; // faithful mode: does not block light (brush entity without _shadow)
constexpr uint32_t kFaceEmissive = BT_FACE_EMISSIVE;  // has emissive texels or is a _surface template
// Alpha-tested faces: a point where the base colour's filtered alpha fails the test is a hole
// for every ray. The test is alpha >= 0.5 ('{' textures, images with alpha, alphaFunc GE128),
// or with one of the two flags after it Quake 3's alphaFunc GT0 / LT128.
constexpr uint32_t kFaceMasked = BT_FACE_MASKED;
constexpr uint32_t kFaceMaskGt0 = BT_FACE_MASK_GT0;
constexpr uint32_t kFaceMaskLt128 = BT_FACE_MASK_LT128;

// A face's word in the GL tracer's face buffer: its kFace* classes, its lighting channels
// (`_object_channel_mask`) and the bit every face has (shaders/scene_constants.glsl).
constexpr uint32_t gpuFaceWord(uint32_t faceFlags, uint32_t channels) {
  return faceFlags | ((channels << BT_FACE_CHANNEL_SHIFT) & BT_FACE_CHANNEL_BITS) | BT_FACE_ANY_CHANNEL;
}

// Per-material parameters; the images themselves travel as textures.
struct GpuMaterial {
  glm::vec4 averageAlbedo{0.5f}; // linear RGB mean of the base colour, a = coverage
  glm::vec4 emission{0.0f};      // rgb: radiance scale for emissive texels (physical), a: _surface radiance
  glm::vec2 size{64.0f};         // texels: texture coordinates divide by it
  float roughness = 0.8f;
  float metallic = 0.0f;
  uint32_t flags = 0; // kMaterial*
  // A liquid's blend with what lies behind it (lighting/liquids.h): its own colour's weight
  // (the engine's alpha); what lies behind weighs 1 - opacity, or 1 with kMaterialBlendAdd, or
  // its own colour with kMaterialBlendFilter.
  // Read on kFaceLiquid faces only; 1 = opaque. Faithful mode reads `opacity`, physical mode
  // `physicalOpacity` (physicalOpacityOfAlpha of the map's alpha, else the liquid's physical default).
  float opacity = 1.0f;
  float physicalOpacity = 1.0f;
  uint32_t pad = 0;
};
static_assert(sizeof(GpuMaterial) == 64);
static_assert(offsetof(GpuMaterial, averageAlbedo) == 0);
static_assert(offsetof(GpuMaterial, emission) == 16);
static_assert(offsetof(GpuMaterial, size) == 32);
static_assert(offsetof(GpuMaterial, roughness) == 40);
static_assert(offsetof(GpuMaterial, metallic) == 44);
static_assert(offsetof(GpuMaterial, flags) == 48);
static_assert(offsetof(GpuMaterial, opacity) == 52);
static_assert(offsetof(GpuMaterial, physicalOpacity) == 56);
static_assert(offsetof(GpuMaterial, pad) == 60);

constexpr uint32_t kMaterialSpecular = 1u;    // has a PBR set (roughness/metallic map): GGX + diffuse
constexpr uint32_t kMaterialEmissive = 2u;    // has an emissive map with lit texels
constexpr uint32_t kMaterialBlendAdd = 4u;    // a liquid drawn additively (Quake 3 blendFunc add): behind weighs 1
constexpr uint32_t kMaterialBlendFilter = 8u; // a liquid that multiplies what lies behind (blendFunc filter): self weighs 0

// One triangle of an emitting face, for next-event estimation by area.
struct GpuEmitter {
  glm::vec3 v0{0.0f};
  uint32_t face = 0;
  glm::vec3 v1{0.0f};
  float area = 0.0f;
  glm::vec3 v2{0.0f};
  float cdf = 0.0f; // running sum of areas / total, the last one is 1
};
static_assert(sizeof(GpuEmitter) == 48);
static_assert(offsetof(GpuEmitter, v0) == 0);
static_assert(offsetof(GpuEmitter, face) == 12);
static_assert(offsetof(GpuEmitter, v1) == 16);
static_assert(offsetof(GpuEmitter, area) == 28);
static_assert(offsetof(GpuEmitter, v2) == 32);
static_assert(offsetof(GpuEmitter, cdf) == 44);

// ---------------------------------------------------------------------------------------------
// Light selection (lighting/light_grid.h builds these; renderer/gl uploads them unchanged)
// A uniform grid over the level; each cell lists the point lights whose faithful-mode reach
// touches it. All lists are ranges of one uint array of indices into the light list:
//   [0, fixedCount)                          suns, domes and local-minlight lights: every point
//                                            evaluates all of them, one by one;
//   [globalFirst, globalFirst + globalCount) faithful point lights with infinite reach
//                                            (inverse, inverse-square, infinite formulas);
//   [physicalFirst, ... + physicalCount)     physical mode's candidates (every positive point
//                                            light);
//   cells[i].first .. + count                faithful point lights of finite reach near cell i;
//   cells[cellCount + i].first .. + count    physical mode's most important lights for cell i
//                                            (at most kPhysicalNearLights, a subset of the
//                                            physical list), cellCount = dims.x * dims.y * dims.z;
//   cells[2 * cellCount + i].first .. + count the other physical candidates whose windowed reach
//                                            touches cell i (the pick's uniform draw).
// Cell (x, y, z) is i = x + dims.x * (y + dims.y * z); a point outside the grid uses the
// nearest cell, whose list covers everything beyond the grid's side (see light_grid.cpp).
//
//   struct LightGrid { vec3 origin; float cellSize; uvec3 dims; uint fixedCount;
//                      uint globalFirst; uint globalCount; uint physicalFirst; uint physicalCount; };
//   struct LightCell { uint first; uint count; };
// ---------------------------------------------------------------------------------------------
struct GpuLightGrid {
  glm::vec3 origin{0.0f}; // min corner of cell (0, 0, 0)
  float cellSize = 1.0f;  // cubic cells, Quake units
  uint32_t dims[3] = {1, 1, 1};
  uint32_t fixedCount = 0;
  uint32_t globalFirst = 0;
  uint32_t globalCount = 0;
  uint32_t physicalFirst = 0;
  uint32_t physicalCount = 0;
};
static_assert(sizeof(GpuLightGrid) == 48);
static_assert(offsetof(GpuLightGrid, cellSize) == 12);
static_assert(offsetof(GpuLightGrid, dims) == 16);
static_assert(offsetof(GpuLightGrid, fixedCount) == 28);
static_assert(offsetof(GpuLightGrid, globalFirst) == 32);
static_assert(offsetof(GpuLightGrid, physicalCount) == 44);

struct GpuLightCell {
  uint32_t first = 0; // into the index array
  uint32_t count = 0;
};
static_assert(sizeof(GpuLightCell) == 8);
static_assert(offsetof(GpuLightCell, count) == 4);

// ---------------------------------------------------------------------------------------------
// Lightmaps (lighting/lightmaps.h bakes them; renderer/gl uploads them unchanged)
// Faithful mode shows the light as the engine does: one luxel every 16 texels on each compiled
// face, filtered bilinearly. A scene face (brush side) holds the compiled faces qbsp makes of it
// (its fragments: CSG pieces, 240-texel subdivisions), each with its own luxel grid. A point of
// the face is shown from the fragment whose polygon holds it, else from the one it lies least
// outside of (the nearest, measured along the violated edge lines).
//   faceLightmaps[face] = uvec2(first fragment, fragment count): count 0 = not baked (the
//                         tracers then evaluate the light at the point itself);
//   fragment edges: edges[firstEdge .. + edgeCount) are lines (a, b, c, 0) in texel space,
//                   a·s + b·t + c >= 0 inside;
//   luxels[firstLuxel + y * width + x]: RGBA8 (r in the low byte), the stored lightmap value
//                   (light × _range, clamped as the compiler clamps, 0..255), alpha unused.
// Luxel (x, y) is centred where u = x and v = y, with u = luxelU·(s, t, 1) - minS and v likewise
// (the scene face's texel coordinates s, t). Faithful mode's grid, Quake's, is the default
// luxelU = (1/16, 0, 0): luxel (x, y) on texel (16 (minS + x), 16 (minT + y)). A compiled .bsp's
// own lightmaps (--lighting compiled) set them from the file: BSPX LMSHIFT's per-face luxel size,
// DECOUPLED_LM's own axes, or a compiled face whose texture frame is not the scene face's.
// The GL tracer reads all of it from one uint buffer (packLightmaps; shaders/lightmaps.glsl):
//   [0] first fragment word, [1] first edge word, [2] first luxel word, [3] face count F,
//   [4] the display scale (float bits: shown = texture × luxel × scale), [5] the first word of
//   GoldSrc's luxel table, [6] the luxels' display (lighting/luxel_display.h), [7] zero;
//   [8 + 2 face], [9 + 2 face]: the face's (first fragment, count); then the fragments (16 words
//   each, this struct), the edges (4 float words each), the luxels (1 word each), the table
//   (BT_LUXEL_TABLE_SIZE float words).
// ---------------------------------------------------------------------------------------------
struct GpuLightmapFragment {
  int32_t minS = 0;
  int32_t minT = 0;
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t firstLuxel = 0;
  uint32_t firstEdge = 0;
  uint32_t edgeCount = 0;
  uint32_t pad = 0;                                   // zero
  float luxelU[4] = {1.0f / 16.0f, 0.0f, 0.0f, 0.0f}; // (a, b, c, 0): u + minS = a s + b t + c
  float luxelV[4] = {0.0f, 1.0f / 16.0f, 0.0f, 0.0f};
};
static_assert(sizeof(GpuLightmapFragment) == 64);
static_assert(offsetof(GpuLightmapFragment, minT) == 4);
static_assert(offsetof(GpuLightmapFragment, width) == 8);
static_assert(offsetof(GpuLightmapFragment, height) == 12);
static_assert(offsetof(GpuLightmapFragment, firstLuxel) == 16);
static_assert(offsetof(GpuLightmapFragment, firstEdge) == 20);
static_assert(offsetof(GpuLightmapFragment, edgeCount) == 24);
static_assert(offsetof(GpuLightmapFragment, luxelU) == 32);
static_assert(offsetof(GpuLightmapFragment, luxelV) == 48);

// One sample point of faithful mode's bake (lighting/lightmap_bake.h): where the compiler
// samples a luxel, found on the CPU, lit by either tracer (shaders/bake.comp). Sample
// luxel * extra^2 + k is the k-th of luxel's extra x extra points (luxel: its index in the
// luxels array).
// An axis-aligned box as the GPU reads it: two vec4 rows (w unused). The bounds of what a light's
// rays reach, or of a compiled face, for ericw-tools' visapprox cull (lighting/vis_approx.h).
struct GpuVisBox {
  glm::vec4 mins{0.0f};
  glm::vec4 maxs{0.0f};
};
static_assert(sizeof(GpuVisBox) == 32);

struct GpuLuxelSample {
  float position[3]{};
  uint32_t face = 0;       // scene face: its plane's normal faces the light
  float faceMinlight[3]{}; // integrator.h faithfulFaceMinlight of the face
  uint32_t flags = 0;      // kLuxelSample* bits
};
inline constexpr uint32_t kLuxelSampleOccluded = BT_LUXEL_SAMPLE_OCCLUDED;  // in solid or off the face: the floors only
inline constexpr uint32_t kLuxelSampleTwoSided = BT_LUXEL_SAMPLE_TWO_SIDED; // a lit liquid, lit from both sides
// flags >> this: 1 + the sample's compiled face in LuxelBakeJob::receiverBoxes (its bounds, which
// the visapprox cull compares with a light's), 0 none.
inline constexpr uint32_t kLuxelSampleBoxShift = BT_LUXEL_SAMPLE_BOX_SHIFT;
static_assert(sizeof(GpuLuxelSample) == 32);
static_assert(offsetof(GpuLuxelSample, face) == 12);
static_assert(offsetof(GpuLuxelSample, faceMinlight) == 16);
static_assert(offsetof(GpuLuxelSample, flags) == 28);

} // namespace bt

// Everything the light models and both tracers read, as flat arrays of the structs in
// scene/gpu_structs.h: per-face shading data, per-material parameters, lights and emitter
// triangles, plus the ray tracer.
#pragma once

#include "bvh/trace_scene.h"
#include "scene/gpu_structs.h"
#include "lighting/game_rules.h"
#include "lighting/light_grid.h"
#include "lighting/liquid_csg.h"
#include "lighting/liquids.h"
#include "lighting/lightmaps.h"
#include "lighting/lights.h"
#include "lighting/qbsp_tree.h"
#include "lighting/sky.h"
#include "lighting/surface_lights.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace bt {

struct RenderSceneOptions {
  LightOptions lights;
  bool showHidden = false; // draw clip/trigger/skip/hint/origin faces instead of skipping them
  // Faithful mode's `_bounce` lights (bounce.h), made when the level asks for them: the direct
  // light at the level's luxels first (bounded by BounceBudget: ~2 s on lq_e3m1's `_bounce 3`). A render
  // that never lights faithfully (physical mode, AOVs only) leaves them out.
  bool bounceLights = true;
  // The boxes of ericw-tools' light culling without vis data (vis_approx.h), which faithful
  // mode's bakes read: 1,024 rays a light (lqdm5: 2.6 s on two cores).
  //   Cpu  computed here, on all cores, for the CPU's bakes;
  //   Gpu  only the lights numbered (RenderScene::visBoxLights): the GL bake computes their
  //        boxes before its first pass (renderer/gl/gl_bake.h), off the preparation; a CPU bake
  //        of such a scene computes them as it starts. A level that bounces gets them here all
  //        the same: its bounce pass, here, culls with them;
  //   Off  a render that never lights faithfully.
  enum class VisBoxes { Off, Cpu, Gpu };
  VisBoxes visApproxBoxes = VisBoxes::Cpu;
};

struct RenderScene {
  const Scene* scene = nullptr;    // images are read from scene->materials
  std::vector<uint32_t> faceFlags; // kFace* per scene face
  // ericw-tools' `_object_channel_mask` per scene face (objectChannels); empty when every face
  // is on the default channel.
  std::vector<uint32_t> faceChannels;
  std::vector<GpuMaterial> materials; // parallel to scene->materials
  std::vector<GpuLight> lights;
  std::vector<glm::vec3> sunTable; // the compiler's directions of each penumbra sun (GpuLight::sunTable)
  // The lights the compiler culls without vis data (vis_approx.h): their indices in `lights`
  // (GpuLight::visBox = 1 + the place here), and their boxes in the same order, empty where
  // RenderSceneOptions::VisBoxes::Gpu leaves them to the GL bake.
  std::vector<uint32_t> visBoxLights;
  std::vector<GpuVisBox> visBoxes;
  LightGrid lightGrid;                 // which lights a point looks at (light_grid.h)
  std::vector<GpuLight> surfaceLights; // per material: the _surface template (value 0 = none)
  std::vector<GpuEmitter> emitters;    // triangles of emitting faces, cdf by area
  float emitterArea = 0.0f;
  // The CPU's emitter pick (integrator.cpp pickEmitter) starts from here: for K + 1 entries (K a
  // power of two), entry k is the first emitter whose cdf reaches k / K (the last emitter where
  // none does), so the one for u lies between entries floor(u K) and the next, a few emitters
  // apart instead of a search of the whole array (its cache misses: a twentieth of a physical
  // path's time). Empty: search it all. Made with the emitters (makeEmitterGuide).
  std::vector<uint32_t> emitterGuide;
  WorldLighting world;
  LightKinds lightKinds; // what collectLights found (before _surface and _bounce lights)
  TraceScene tracer;     // the brushes that are ever visible, in a BVH
  // Which hits on liquid faces qbsp's CSG of overlapping liquids leaves drawn (liquid_csg.h);
  // empty for a level without overlapping liquids.
  LiquidCsg liquidCsg;
  // Per TraceScene brush slot, 1 where faithful shadow rays that leave the brush are blocked as
  // those that enter it: a Quake 2 liquid brush with a face that blocks light (drawn as a wall:
  // no SURF_WARP). qbsp gives a liquid brush's faces on both sides (its inside is open space) and
  // ericw-tools' Embree hits its solid faces from either side, so a light's ray from inside the
  // water leaves through a wall (q2_light_visapprox2). Empty where no brush is such.
  std::vector<uint8_t> blocksFromInside;
  // qbsp's tree of the whole world (qbsp_faces.h worldTree), which cuts a Quake 2 world's sides
  // into the compiler's faces for the bounce lights, the surface lights and the luxel layout:
  // grown once here; empty for every other game (their sides are cut by per-surface trees).
  QbspTree worldTree;
  // Quake 2's glass as the engine draws it (game_rules.h engineGlassAlpha): per scene face, its
  // alpha, 1 for every other face; empty for a level without glass.
  std::vector<float> glassAlpha;
  // Faithful mode's luxels (lightmap_bake.h): a face baked here is shown from them, as the game
  // shows its lightmaps; any other face has its light evaluated at the shown point.
  Lightmaps lightmaps;
  // The level's sky images baked by direction (sky.h), what a sky face shows in both tracers;
  // size 0 without sky images (a sky face then shows its own texture, as any face).
  SkyMap sky;
};

inline const GpuFace& gpuFace(const RenderScene& rs, uint32_t face) {
  return rs.tracer.faces()[face];
}
// The lighting channels a face is on: those of the lights that light it and of the rays it blocks.
inline uint32_t objectChannels(const RenderScene& rs, uint32_t face) {
  return face < rs.faceChannels.size() ? rs.faceChannels[face] : kDefaultChannels;
}
inline glm::vec3 faceNormal(const RenderScene& rs, uint32_t face) {
  const float* p = gpuFace(rs, face).plane;
  return {p[0], p[1], p[2]};
}

// Quake 2's glass alpha of a face (RenderScene::glassAlpha), 1 for any other face.
inline float glassAlpha(const RenderScene& rs, uint32_t face) {
  return face < rs.glassAlpha.size() ? rs.glassAlpha[face] : 1.0f;
}
// Whether the engine draws the face without its lightmap, at its texture's own colour: sky, a
// liquid without `_litwater`, Quake 2's glass (which the compiler lights all the same).
inline bool engineDrawsUnlit(const RenderScene& rs, uint32_t face) {
  const uint32_t flags = rs.faceFlags[face];
  return (flags & kFaceSky) || ((flags & kFaceLiquid) && !rs.world.litwater) || glassAlpha(rs, face) < 1.0f;
}
// How the engine blends the face over what lies behind it, in faithful mode and the compiled
// view: a translucent liquid's material blend (lighting/liquids.h), Quake 2's glass at its alpha;
// opaque for every other face.
inline LiquidBlend engineBlend(const RenderScene& rs, uint32_t face) {
  if (rs.faceFlags[face] & kFaceLiquid) return liquidBlend(rs.materials[gpuFace(rs, face).material]);
  const float alpha = glassAlpha(rs, face);
  return {alpha, 1.0f - alpha};
}

// RenderScene::emitterGuide of `emitters`.
std::vector<uint32_t> makeEmitterGuide(std::span<const GpuEmitter> emitters);

// Classifies faces by texture name (Quake conventions, see README), reads the lights, and
// builds the tracer. `scene` must outlive the result.
RenderScene buildRenderScene(const Scene& scene, const RenderSceneOptions& options, Diagnostics& diagnostics);

// The parts of a level that decide, beside its LightKinds, which GL program it needs: known
// from its brushes and faces alone, long before it is prepared, so that the front ends start
// compiling the one program the level needs (renderer/gl/gl_level.h).
struct LevelParts {
  bool liquidCsg = false;        // RenderScene::liquidCsg is not empty
  bool blocksFromInside = false; // RenderScene::blocksFromInside is not empty
  bool glass = false;            // RenderScene::glassAlpha is not empty
  bool operator==(const LevelParts&) const = default;
};
// Those buildRenderScene(scene, options) will find; the scene's textures need not be loaded.
LevelParts levelParts(const Scene& scene, const RenderSceneOptions& options);
// Those a prepared level has.
LevelParts levelParts(const RenderScene& rs);

// What each brush of `scene` is to qbsp's CSG (surface_lights.h BrushContents): world brushes
// are solid, or liquid where a face is a liquid; brushes with a hidden face, and brush entities
// that keep their own model, carve nothing.
std::vector<BrushContents> brushContents(const Scene& scene);

// Brush entities that qbsp merges into the world (worldspawn, func_group, func_detail*): they
// cast shadows in `light`; the others are models of their own.
bool mergedIntoWorld(std::string_view classname);

// Face classification from a texture name and its Q2/Q3 surface attributes, read as `game`
// reads them (the games share the bits but Quake 3's SURF_LADDER, Quake 2's SURF_WARP).
uint32_t classifyTexture(std::string_view texture, const std::optional<SurfaceAttributes>& surface, Game game);

} // namespace bt

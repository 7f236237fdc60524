#include "lighting/render_scene.h"
#include "lighting/bounce.h"
#include "lighting/game_rules.h"
#include "lighting/liquids.h"
#include "lighting/physical_light.h"
#include "lighting/physical_reference.h"
#include "lighting/q3map2_shader_light.h"
#include "lighting/surface_lights.h"
#include "lighting/vis_approx.h"
#include "quake/bspfile_q2.h"
#include "quake/entity_keys.h"
#include "scene/names.h"

#include "scene/color.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <future>
#include <span>
#include <stdexcept>

namespace bt {

namespace {

// srgbToLinear(byte / 255) for every byte: a level's textures hold millions of texels.
std::array<float, 256> srgbByteToLinear() {
  std::array<float, 256> table;
  for (int i = 0; i < 256; ++i) table[size_t(i)] = srgbToLinear(float(i) / 255.0f);
  return table;
}

GpuMaterial materialParams(const Material& m, const std::array<float, 256>& toLinear) {
  GpuMaterial g;
  g.size = {float(std::max(m.width, 1)), float(std::max(m.height, 1))};
  g.roughness = m.roughnessValue;
  g.metallic = m.metallicValue;
  if (!m.roughness.empty() || !m.metallic.empty()) g.flags |= kMaterialSpecular;
  glm::dvec4 sum(0.0);
  const Image& base = m.baseColor;
  if (!base.empty()) {
    for (int y = 0; y < base.height; ++y)
      for (int x = 0; x < base.width; ++x) {
        const uint8_t* p = base.texel(x, y);
        sum += glm::dvec4(toLinear[p[0]], toLinear[p[1]], toLinear[p[2]], p[3] / 255.0);
      }
    g.averageAlbedo = glm::vec4(sum / double(base.width * base.height));
  }
  const Image& e = m.emissive;
  for (size_t i = 0; i + 3 < e.rgba.size(); i += 4)
    if (e.rgba[i] | e.rgba[i + 1] | e.rgba[i + 2]) {
      g.flags |= kMaterialEmissive;
      g.emission = glm::vec4(1.0f, 1.0f, 1.0f, 0.0f);
      break;
    }
  return g;
}

// The kFaceMask* flags a material's faces get (gpu_structs.h).
uint32_t alphaTestFlags(const Material& m) {
  switch (m.alphaTest) {
  case AlphaTest::None: return 0u;
  case AlphaTest::Gt0: return kFaceMasked | kFaceMaskGt0;
  case AlphaTest::Lt128: return kFaceMasked | kFaceMaskLt128;
  case AlphaTest::Ge128: return kFaceMasked;
  case AlphaTest::FromImage: break;
  }
  for (size_t i = 3; i < m.baseColor.rgba.size(); i += 4)
    if (m.baseColor.rgba[i] != 255) return kFaceMasked;
  return 0u;
}

} // namespace

bool mergedIntoWorld(std::string_view classname) {
  return classname == "worldspawn" || classname == "func_group" || classname.starts_with("func_detail");
}

uint32_t classifyTexture(std::string_view texture, const std::optional<SurfaceAttributes>& surface, Game game) {
  const std::string name = lowercase(texture);
  // The last path component: Quake 2/3 names carry folders ("e1u1/clip", "common/caulk").
  const std::string_view base = std::string_view(name).substr(name.find_last_of('/') + 1);
  uint32_t flags = 0;
  static constexpr std::string_view kHidden[] = {"clip", "trigger", "skip", "hint", "hintskip", "origin", "nodraw", "null", "aaatrigger",
                                                 "playerclip", "monsterclip",
                                                 // qbsp's skip names for liquids: the brush stays water, unseen
                                                 "*waterskip", "*slimeskip", "*lavaskip"};
  for (std::string_view h : kHidden)
    if (base == h) flags |= kFaceHidden;
  if (name.starts_with("common/") || name.starts_with("textures/common/")) flags |= kFaceHidden;
  if (base.starts_with("sky") || name.starts_with("skies/") || name.starts_with("textures/skies/")) flags |= kFaceSky;
  if (base.starts_with("*") || base.starts_with("!")) flags |= kFaceLiquid;
  if (surface) {
    // Quake 2's bits; Quake 3's surfaceparms share them (quake/bspfile_q3.h) but for 0x8, which
    // is Quake 3's SURF_LADDER: a ladder is no liquid.
    using namespace quake::q2;
    const bool warp = game != Game::Quake3 && (surface->flags & SURF_WARP);
    if (surface->flags & (SURF_NODRAW | SURF_HINT | SURF_SKIP)) flags |= kFaceHidden;
    if (surface->contents & MASK_CLIP) flags |= kFaceHidden;
    if (surface->flags & SURF_SKY) flags |= kFaceSky;
    if (warp || (surface->contents & MASK_LIQUID)) flags |= kFaceLiquid;
  }
  if (flags & kFaceSky) flags &= ~kFaceHidden; // "common/sky" style names stay visible as sky
  return flags;
}

std::vector<BrushContents> brushContents(const Scene& scene) {
  std::vector<BrushContents> contents(scene.brushes.size(), BrushContents::Empty);
  const Game game = gameOf(scene);
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    const Brush& brush = scene.brushes[b];
    if (brush.entity >= scene.entities.size() || !mergedIntoWorld(scene.entities[brush.entity].classname())) continue;
    uint32_t classes = 0;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
      classes |= classifyTexture(scene.faces[f].texture, scene.faces[f].surface, game);
    if (classes & kFaceHidden) continue;
    contents[b] = (classes & kFaceLiquid) ? BrushContents::Liquid : BrushContents::Solid;
  }
  return contents;
}

namespace {

// ericw-tools' FixLightsOnFaces: a light in the world's solid or on one of its faces is moved 2
// units along the first axis direction (-x, +x, -y, +y, -z, +z) that leaves it outside; luxels
// are sampled 1 unit off faces, so the light does not end up on a sample point.
void nudgeLightsOffFaces(RenderScene& rs, const std::vector<BrushContents>& contents) {
  auto solid = [&](uint32_t brush) { return contents[brush] == BrushContents::Solid; };
  for (GpuLight& light : rs.lights) {
    if (light.type != uint32_t(LightType::Point) || light.value == 0.0f) continue;
    if (!rs.tracer.inside(light.origin, solid, true)) continue;
    for (int i = 0; i < 6; ++i) {
      glm::vec3 moved = light.origin;
      moved[i / 2] += (i % 2) ? 2.0f : -2.0f;
      if (!rs.tracer.inside(moved, solid, true)) {
        light.origin = moved;
        break;
      }
    }
  }
}

// _surface templates: every material with the template's texture name emits.
void applySurfaceTemplates(RenderScene& rs, const std::vector<SurfaceTemplate>& templates) {
  const Scene& scene = *rs.scene;
  rs.surfaceLights.assign(scene.materials.size(), GpuLight{});
  for (GpuLight& l : rs.surfaceLights) l.value = 0.0f;
  for (const SurfaceTemplate& t : templates)
    if (auto m = scene.findMaterial(t.texture)) {
      GpuLight& tmpl = rs.surfaceLights[*m];
      tmpl = t.light;
      // ericw-tools lights the faces of a radiosity surface light at least at its own value.
      tmpl.faithfulScale = t.radiosity ? std::max(t.minlightScale, 0.0f) : 0.0f;
      if (tmpl.faithfulScale > 0.0f) tmpl.flags |= kLightFlagFaceMinlight;
    }
}

// Quake 2 draws a face by its surface flags alone (ref_gl R_RenderBrushPoly): warped without a
// lightmap with SURF_WARP, sky with SURF_SKY, whatever its name or contents. A liquid brush's
// face without SURF_WARP is lit and drawn with its lightmap (qbsp and light give it one:
// q2_csg_water_water_current90), and to the compiler it is a wall: ericw-tools' Embree_TraceInit
// passes only translucent faces (SURF_WARP, SURF_TRANS33/66) and puts the others among its solid
// faces, which cast shadows and stop the visapprox rays. The oracle's logs count them there:
// q2_light_visapprox2's 8 water faces without SURF_WARP among its "50 solid faces" of 50, and
// q2_dirt's 10 with SURF_WARP outside its "66 solid faces" of 76. Glass passes (compilerGlass).
uint32_t quake2DrawnAs(uint32_t flags, const SurfaceAttributes& surface) {
  using namespace quake::q2;
  flags &= ~(kFaceLiquid | kFaceSky);
  if (surface.flags & SURF_WARP) flags |= kFaceLiquid;
  if (surface.flags & SURF_SKY) flags |= kFaceSky;
  return flags;
}

// An entity's `_object_channel_mask`; what qbsp merges into the world falls back on the
// worldspawn's, as the world model reads it.
uint32_t entityChannels(const Scene& scene, const Entity& ent) {
  const Entity* world = mergedIntoWorld(ent.classname()) ? scene.worldspawn() : nullptr;
  const int fallback = world ? quake::EntityKeys(*world).integer("_object_channel_mask", int(kDefaultChannels)) : int(kDefaultChannels);
  return uint32_t(quake::EntityKeys(ent).integer("_object_channel_mask", fallback));
}

// Each face's class (kFace*): its texture's, its entity's (shadows, what the game hides), and
// whether it emits.
void classifyFaces(RenderScene& rs, const RenderSceneOptions& options) {
  const Scene& scene = *rs.scene;
  std::vector<uint32_t> materialMasks;
  for (const Material& m : scene.materials) materialMasks.push_back(alphaTestFlags(m) | q3map2::shaderFaceFlags(m));
  rs.faceFlags.resize(scene.faces.size());
  rs.faceChannels.clear();
  rs.glassAlpha.clear();
  const Game game = gameOf(scene);
  for (size_t i = 0; i < scene.faces.size(); ++i) {
    const Face& f = scene.faces[i];
    uint32_t& flags = rs.faceFlags[i];
    flags = classifyTexture(f.texture, f.surface, game) | materialMasks[f.material];
    if (flags & kFaceSky) flags &= ~kFaceHidden; // a Quake 3 sky shader on a common/ name
    if (game == Game::Quake2 && f.surface) flags = quake2DrawnAs(flags, *f.surface);
    // Glass passes the light (game_rules.h compilerGlass): whole, as the compiler passes it
    // through a texture it has no pixels for; its tint by the texels it does have is not modelled.
    if (compilerGlass(f, game)) flags |= kFaceNoShadow;
    if (const float alpha = engineGlassAlpha(f, game); alpha < 1.0f) {
      if (rs.glassAlpha.empty()) rs.glassAlpha.assign(scene.faces.size(), 1.0f);
      rs.glassAlpha[i] = alpha;
    }
    {
      const uint32_t e = scene.faceEntity(uint32_t(i)); // a brush's or a mesh's
      if (e < scene.entities.size()) {
        const Entity& ent = scene.entities[e];
        const bool shadowKey = quake::EntityKeys(ent).number("_shadow", 0.0f) != 0.0f;
        const uint32_t channels = entityChannels(scene, ent);
        if (channels != kDefaultChannels) {
          if (rs.faceChannels.empty()) rs.faceChannels.assign(scene.faces.size(), kDefaultChannels);
          rs.faceChannels[i] = channels;
        }
        // A model on channels of its own casts shadows without `_shadow` (trace_embree.cc).
        if (!mergedIntoWorld(ent.classname()) && !shadowKey && channels == kDefaultChannels) flags |= kFaceNoShadow;
        // What the game never draws is not in the compiled lighting either, `_shadow` or not.
        if (gameHidesEntity(ent, game)) flags |= kFaceHidden | kFaceNoShadow;
      }
    }
    if (options.showHidden) flags &= ~kFaceHidden;
    const uint32_t m = f.material;
    if (m < rs.materials.size() && ((rs.materials[m].flags & kMaterialEmissive) || rs.surfaceLights[m].value != 0.0f) &&
        !(flags & (kFaceHidden | kFaceSky)))
      flags |= kFaceEmissive;
  }
}

// Emitter triangles: a fan over each emitting face's winding.
void addEmitters(RenderScene& rs) {
  const Scene& scene = *rs.scene;
  for (size_t i = 0; i < scene.faces.size(); ++i) {
    if (!(rs.faceFlags[i] & kFaceEmissive)) continue;
    const std::vector<dvec3>& w = scene.faces[i].winding;
    for (size_t k = 1; k + 1 < w.size(); ++k) {
      GpuEmitter e;
      e.v0 = glm::vec3(w[0]);
      e.v1 = glm::vec3(w[k]);
      e.v2 = glm::vec3(w[k + 1]);
      e.face = uint32_t(i);
      e.area = 0.5f * glm::length(glm::cross(e.v1 - e.v0, e.v2 - e.v0));
      if (e.area <= 0.0f) continue;
      rs.emitterArea += e.area;
      e.cdf = rs.emitterArea;
      rs.emitters.push_back(e);
    }
  }
  for (GpuEmitter& e : rs.emitters) e.cdf /= rs.emitterArea;
  if (!rs.emitters.empty()) rs.emitters.back().cdf = 1.0f;
  rs.emitterGuide = makeEmitterGuide(rs.emitters);
}

} // namespace

std::vector<uint32_t> makeEmitterGuide(std::span<const GpuEmitter> emitters) {
  if (emitters.empty()) return {};
  // About one emitter a bucket; k / K and u K are exact in float for a power of two.
  const uint32_t buckets = std::min<uint32_t>(std::bit_ceil(uint32_t(emitters.size())), 1u << 16);
  std::vector<uint32_t> guide(buckets + 1);
  const uint32_t last = uint32_t(emitters.size()) - 1;
  uint32_t i = 0;
  for (uint32_t k = 0; k <= buckets; ++k) {
    const float threshold = float(k) / float(buckets);
    while (i < last && emitters[i].cdf < threshold) ++i;
    guide[k] = i;
  }
  return guide;
}

namespace {

// The BVH over what can block a ray: brushes whose every face is hidden (clip, trigger, ...) and
// hidden meshes are left out.
TraceScene buildTracer(const RenderScene& rs) {
  const Scene& scene = *rs.scene;
  BvhBuildOptions bvh;
  bvh.includeBrush.resize(scene.brushes.size());
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    const Brush& brush = scene.brushes[b];
    bool visible = false;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) visible |= !(rs.faceFlags[f] & kFaceHidden);
    bvh.includeBrush[b] = visible;
  }
  // A mesh has one material, so its faces are all hidden or none.
  for (const Mesh& mesh : scene.meshes) bvh.includeMesh.push_back(mesh.faceCount > 0 && !(rs.faceFlags[mesh.firstFace] & kFaceHidden));
  return TraceScene::build(scene, bvh);
}

// Whether faithful shadow rays leaving brush `b` are blocked (RenderScene::blocksFromInside): a
// Quake 2 liquid brush (by contents, before quake2DrawnAs) with a face that blocks faithful
// light, whose faces the compiler has on both sides.
bool blocksFromInside(const RenderScene& rs, const std::vector<BrushContents>& contents, uint32_t b) {
  if (b >= contents.size() || contents[b] != BrushContents::Liquid) return false;
  const Brush& brush = rs.scene->brushes[b];
  for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
    if (!(rs.faceFlags[f] & (kFaceHidden | kFaceLiquid | kFaceNoShadow))) return true;
  return false;
}

// RenderScene::blocksFromInside, per tracer slot.
std::vector<uint8_t> brushesBlockingFromInside(const RenderScene& rs, const std::vector<BrushContents>& contents) {
  if (gameOf(*rs.scene) != Game::Quake2) return {};
  const std::span<const GpuBrush> brushes = rs.tracer.brushes();
  std::vector<uint8_t> blocks(brushes.size(), 0);
  bool any = false;
  for (size_t slot = 0; slot < brushes.size(); ++slot) {
    blocks[slot] = blocksFromInside(rs, contents, brushes[slot].sceneBrush);
    any |= blocks[slot] != 0;
  }
  if (!any) blocks.clear();
  return blocks;
}

// `_bounce`: the compiler's bounce lights, made from the direct light the grid gives, with their
// boxes where the bakes cull lights (`visBoxes`), and the grid of every light extended from that
// of the direct lights (physical mode's lists stay).
void addBounceLights(RenderScene& rs, const std::vector<BrushContents>& contents, bool visBoxes, Diagnostics& diagnostics) {
  const BounceLights bounced = makeBounceLights(rs, contents);
  const uint32_t direct = uint32_t(rs.lights.size());
  rs.lights.insert(rs.lights.end(), bounced.lights.begin(), bounced.lights.end());
  if (visBoxes) assignBounceVisBoxes(rs, direct);
  if (!bounced.exact())
    diagnostics.push_back({Severity::Note, rs.scene->sourcePath, 0, 0,
                           "_bounce estimated from " + std::to_string(bounced.sampledLuxels) + " of " + std::to_string(bounced.luxels) +
                               " luxels per pass" + (bounced.sampledLights ? " (later passes draw among the bounce lights)" : "") + ", " +
                               std::to_string(bounced.madeLights) + " bounce lights merged into " + std::to_string(bounced.lights.size()) +
                               " to keep the preview fast"});
  rs.lightGrid = extendLightGrid(rs.lightGrid, rs.lights, direct, rs.tracer.bounds(), rs.world.scaledist);
}

} // namespace

RenderScene buildRenderScene(const Scene& scene, const RenderSceneOptions& options, Diagnostics& diagnostics) {
  RenderScene rs;
  rs.scene = &scene;
  SceneLights lights = collectLights(scene, options.lights, diagnostics);
  rs.lightKinds = lightKinds(scene, lights, options.bounceLights);
  rs.lights = std::move(lights.lights);
  rs.world = lights.world;
  rs.sunTable = std::move(lights.sunTable);

  // Every lookup below indexes materials by face; a scene that breaks that is a bug upstream.
  for (const Face& f : scene.faces)
    if (f.material >= scene.materials.size()) throw std::invalid_argument("buildRenderScene: face material index out of range");
  rs.materials.reserve(scene.materials.size());
  const std::array<float, 256> toLinear = srgbByteToLinear();
  for (const Material& m : scene.materials) rs.materials.push_back(materialParams(m, toLinear));
  applySurfaceTemplates(rs, lights.surfaceTemplates);
  classifyFaces(rs, options);
  applyLiquidBlends(scene, rs.faceFlags, rs.materials);
  addEmitters(rs);

  const std::vector<BrushContents> contents = brushContents(scene);
  rs.tracer = buildTracer(rs);
  rs.liquidCsg = LiquidCsg(scene);
  rs.blocksFromInside = brushesBlockingFromInside(rs, contents);
  rs.worldTree = worldTree(scene, contents);
  nudgeLightsOffFaces(rs, contents);
  // Faithful mode's _surface lights: point lights spread over the template faces, after the
  // tracer (the compiler drops template faces that look into the void). A Quake 1 level's spread
  // grows the compiler's world tree, mostly on one core, so it runs beside the other lights'
  // landings below; it reads neither those lights nor what the landings write.
  std::future<std::vector<GpuLight>> surfaceLights = std::async(std::launch::async, [&] {
    return spreadSurfaceLights(scene, lights.surfaceTemplates, contents, rs.worldTree, rs.world, rs.tracer, diagnostics);
  });
  // Physical mode's intensities, each Quake light matched over the surfaces its light lands on
  // (after the tracer and the nudge off faces: the rays start where the light stands). The lights
  // added below are never matched so (physical::matchedWhereItLands: _surface points are
  // faithful-only, q3map2's keep the fixed rule), so their landings need not wait for them.
  physical::prepareWhereTheyLand(rs, rs.lights);
  for (const GpuLight& l : surfaceLights.get()) rs.lights.push_back(l);
  if (gameOf(scene) == Game::Quake3)
    for (const GpuLight& l : q3map2::shaderSurfaceLights(scene, contents, rs.tracer, diagnostics)) rs.lights.push_back(l);
  // Where the lights stand for good, before the bounce pass lights with them.
  const bool bounces = rs.world.bounces > 0 && options.bounceLights;
  using VisBoxes = RenderSceneOptions::VisBoxes;
  if (options.visApproxBoxes == VisBoxes::Cpu || (options.visApproxBoxes == VisBoxes::Gpu && bounces))
    assignVisBoxes(rs);
  else if (options.visApproxBoxes == VisBoxes::Gpu)
    numberVisBoxLights(rs);
  rs.lightGrid = buildLightGrid(rs.lights, rs.tracer.bounds(), rs.world.scaledist);
  if (bounces) addBounceLights(rs, contents, options.visApproxBoxes != VisBoxes::Off, diagnostics); // prepared too
  if (scene.sky) rs.sky = bakeSkyMap(scene);
  return rs;
}

LevelParts levelParts(const Scene& scene, const RenderSceneOptions& options) {
  RenderScene rs;
  rs.scene = &scene;
  classifyFaces(rs, options); // without materials: no face is classed emissive, which no part reads
  const std::vector<BrushContents> contents = brushContents(scene);
  // A brush with a face that blocks light has a face the game draws, so it is in the tracer.
  bool blocks = false;
  if (gameOf(scene) == Game::Quake2)
    for (uint32_t b = 0; b < scene.brushes.size() && !blocks; ++b) blocks = blocksFromInside(rs, contents, b);
  return {.liquidCsg = !LiquidCsg(scene).empty(), .blocksFromInside = blocks, .glass = !rs.glassAlpha.empty()};
}

LevelParts levelParts(const RenderScene& rs) {
  return {.liquidCsg = !rs.liquidCsg.empty(), .blocksFromInside = !rs.blocksFromInside.empty(), .glass = !rs.glassAlpha.empty()};
}

} // namespace bt

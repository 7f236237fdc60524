#include "renderer/cpu/render_scene.h"

#include "renderer/cpu/color.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cctype>

namespace bt {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Quake 2 surface flags and contents that decide how a face is drawn.
constexpr int32_t kQ2SurfSky = 0x4, kQ2SurfWarp = 0x8, kQ2SurfHint = 0x100, kQ2SurfSkip = 0x200, kQ2SurfNodraw = 0x80;
constexpr int32_t kQ2ContentsLiquid = 8 | 16 | 32; // lava, slime, water
constexpr int32_t kQ2ContentsClip = 0x10000 | 0x20000; // player clip, monster clip

// Brush entities that qbsp merges into the world and that therefore cast shadows in `light`.
bool mergedIntoWorld(std::string_view classname) {
  return classname == "worldspawn" || classname == "func_group" || classname.starts_with("func_detail");
}

GpuMaterial materialParams(const Material& m) {
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
        sum += glm::dvec4(srgbToLinear(p[0] / 255.0f), srgbToLinear(p[1] / 255.0f), srgbToLinear(p[2] / 255.0f), p[3] / 255.0);
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

} // namespace

uint32_t classifyTexture(std::string_view texture, const std::optional<SurfaceAttributes>& surface) {
  const std::string name = lower(texture);
  // The last path component: Quake 2/3 names carry folders ("e1u1/clip", "common/caulk").
  const std::string_view base = std::string_view(name).substr(name.find_last_of('/') + 1);
  uint32_t flags = 0;
  static constexpr std::string_view kHidden[] = {"clip", "trigger", "skip", "hint", "hintskip", "origin",
                                                 "nodraw", "null", "aaatrigger", "playerclip", "monsterclip"};
  for (std::string_view h : kHidden)
    if (base == h) flags |= kFaceHidden;
  if (name.starts_with("common/") || name.starts_with("textures/common/")) flags |= kFaceHidden;
  if (base.starts_with("sky") || name.starts_with("skies/") || name.starts_with("textures/skies/")) flags |= kFaceSky;
  if (base.starts_with("*") || base.starts_with("!")) flags |= kFaceLiquid;
  if (surface) {
    if (surface->flags & (kQ2SurfNodraw | kQ2SurfHint | kQ2SurfSkip)) flags |= kFaceHidden;
    if (surface->contents & kQ2ContentsClip) flags |= kFaceHidden;
    if (surface->flags & kQ2SurfSky) flags |= kFaceSky;
    if ((surface->flags & kQ2SurfWarp) || (surface->contents & kQ2ContentsLiquid)) flags |= kFaceLiquid;
  }
  if (flags & kFaceSky) flags &= ~kFaceHidden; // "common/sky" style names stay visible as sky
  return flags;
}

RenderScene buildRenderScene(const Scene& scene, const RenderSceneOptions& options, Diagnostics& diagnostics) {
  RenderScene rs;
  rs.scene = &scene;
  SceneLights lights = collectLights(scene, options.lights, diagnostics);
  rs.lights = std::move(lights.lights);
  rs.world = lights.world;

  rs.materials.reserve(scene.materials.size());
  for (const Material& m : scene.materials) rs.materials.push_back(materialParams(m));

  // _surface templates: every material with the template's texture name emits.
  rs.surfaceLights.assign(scene.materials.size(), GpuLight{});
  for (GpuLight& l : rs.surfaceLights) l.value = 0.0f;
  for (const SurfaceTemplate& t : lights.surfaceTemplates)
    if (auto m = scene.findMaterial(t.texture)) {
      rs.surfaceLights[*m] = t.light;
      rs.surfaceLights[*m].surfaceMaterial = *m;
    }

  rs.faces.resize(scene.faces.size());
  for (size_t i = 0; i < scene.faces.size(); ++i) {
    const Face& f = scene.faces[i];
    GpuShadeFace& g = rs.faces[i];
    g.plane = glm::vec4(glm::vec3(f.plane.normal), float(f.plane.dist));
    // s = dot(p - origin, tangent) = dot(p, tangent) - dot(origin, tangent)
    g.sAxis = glm::vec4(glm::vec3(f.frame.tangent), float(-glm::dot(f.frame.origin, f.frame.tangent)));
    g.tAxis = glm::vec4(glm::vec3(f.frame.bitangent), float(-glm::dot(f.frame.origin, f.frame.bitangent)));
    g.material = f.material < scene.materials.size() ? f.material : 0;
    g.brush = f.brush;
    g.flags = classifyTexture(f.texture, f.surface);
    if (options.showHidden) g.flags &= ~kFaceHidden;
    if (f.brush < scene.brushes.size()) {
      const uint32_t e = scene.brushes[f.brush].entity;
      if (e < scene.entities.size()) {
        const Entity& ent = scene.entities[e];
        const bool shadowKey = std::atof(std::string(ent.value("_shadow", "0")).c_str()) != 0.0;
        if (!mergedIntoWorld(ent.classname()) && !shadowKey) g.flags |= kFaceNoShadow;
      }
    }
    const bool hasMaterial = g.material < rs.materials.size();
    if (hasMaterial && ((rs.materials[g.material].flags & kMaterialEmissive) || rs.surfaceLights[g.material].value != 0.0f) &&
        !(g.flags & (kFaceHidden | kFaceSky)))
      g.flags |= kFaceEmissive;
  }

  // Emitter triangles: a fan over each emitting face's winding.
  for (size_t i = 0; i < scene.faces.size(); ++i) {
    if (!(rs.faces[i].flags & kFaceEmissive)) continue;
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

  // Brushes whose every face is hidden (clip, trigger, ...) are left out of the tracer.
  rs.tracer = std::make_unique<BrushTracer>(scene, [&](uint32_t b) {
    const Brush& brush = scene.brushes[b];
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
      if (!(rs.faces[f].flags & kFaceHidden)) return true;
    return false;
  });
  return rs;
}

} // namespace bt

#include "lighting/compiled_lightmaps.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string_view>

namespace bt {

namespace {

// The first letter of each style string the game code sets at worldspawn (Quake's world.qc,
// Half-Life's world.cpp, Quake 2's g_spawn.c SP_worldspawn: the same twelve strings, and style
// 63 "a"): what each style shows at time 0.
constexpr std::string_view kPresetStylesAtLoad = "mmammjnmmama";
constexpr int kTestingStyle = 63;
constexpr int kFirstSwitchableStyle = 32;

float letterValue(LightmapEngine engine, char letter) {
  const int k = letter - 'a';
  return engine == LightmapEngine::Quake2 ? float(k) / float('m' - 'a') : float(k * 22);
}

glm::dvec3 vec(const float* v) {
  return {v[0], v[1], v[2]};
}

// How far a compiled face may lie from the brush side it is drawn on: q3map2 leaves some
// surfaces an eighth of a unit off their side (a panel on a ceiling); Quake's faces lie on it.
constexpr double kPlaneSlack = 0.25;

// The compiled faces by entity and plane distance (1-unit buckets), for finding those that lie
// on a scene face.
class CompiledFaceIndex {
public:
  explicit CompiledFaceIndex(const CompiledLighting& cl) : cl_(cl) {
    for (uint32_t i = 0; i < cl.faces.size(); ++i) {
      const LightmappedFace& f = cl.faces[i];
      if (f.polygon.size() < 3) continue;
      buckets_[{f.entity, int64_t(std::floor(glm::dot(f.normal, f.polygon[0])))}].push_back(i);
    }
  }

  // The compiled faces of `entity` on `plane` whose bounds overlap those of `winding`; for a side
  // the compiler drew nothing of (one hidden in the game), those that touch it: a ray that
  // grazes its edge shows their light, as the engine shows the face beside it.
  std::vector<uint32_t> on(uint32_t entity, const Plane& plane, const std::vector<dvec3>& winding) const {
    Bounds box;
    for (const dvec3& p : winding) box.grow(p);
    std::vector<uint32_t> out = overlapping(entity, plane, box, kTouch);
    return out.empty() ? overlapping(entity, plane, box, -kTouch) : out;
  }

private:
  // Shrunk by `margin` (grown where negative): faces that only touch along an edge do not overlap.
  static constexpr double kTouch = 0.05;

  std::vector<uint32_t> overlapping(uint32_t entity, const Plane& plane, const Bounds& box, double margin) const {
    std::vector<uint32_t> out;
    const int64_t cell = int64_t(std::floor(plane.dist));
    for (int64_t c = cell - 1; c <= cell + 1; ++c) {
      const auto it = buckets_.find({entity, c});
      if (it == buckets_.end()) continue;
      for (uint32_t i : it->second) {
        const LightmappedFace& f = cl_.faces[i];
        if (glm::dot(f.normal, plane.normal) < 0.999 || std::abs(glm::dot(f.normal, f.polygon[0]) - plane.dist) > kPlaneSlack) continue;
        Bounds fb;
        for (const dvec3& p : f.polygon) fb.grow(p);
        if (overlap(fb, box, plane.normal, margin)) out.push_back(i);
      }
    }
    return out;
  }

  // Along the plane's own axis (a flat box) both boxes lie at the same place.
  static bool overlap(const Bounds& a, const Bounds& b, const dvec3& normal, double margin) {
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(normal[axis]) > 0.999) continue;
      if (a.min[axis] > b.max[axis] - margin || a.max[axis] < b.min[axis] + margin) return false;
    }
    return true;
  }

  const CompiledLighting& cl_;
  std::map<std::pair<uint32_t, int64_t>, std::vector<uint32_t>> buckets_;
};

// The affine map from a scene face's texel coordinates (s, t) to world points on its plane.
struct FaceFrame {
  dvec3 origin{0.0}, tangent{0.0}, bitangent{0.0};
  dvec3 p0{0.0}, ps{0.0}, pt{0.0}; // p(s, t) = p0 + s ps + t pt
  bool valid = false;

  explicit FaceFrame(const GpuFace& g) : origin(vec(g.origin)), tangent(vec(g.tangent)), bitangent(vec(g.bitangent)) {
    const dvec3 n = vec(g.plane);
    const glm::dmat3 m = glm::transpose(glm::dmat3(n, tangent, bitangent)); // rows n, T, B
    if (std::abs(glm::determinant(m)) < 1e-12) return;
    const glm::dmat3 inv = glm::inverse(m);
    p0 = inv * dvec3(double(g.plane[3]), glm::dot(origin, tangent), glm::dot(origin, bitangent));
    ps = inv * dvec3(0.0, 1.0, 0.0);
    pt = inv * dvec3(0.0, 0.0, 1.0);
    valid = true;
  }
  glm::dvec2 st(const dvec3& p) const { return {glm::dot(p - origin, tangent), glm::dot(p - origin, bitangent)}; }
};

// Edge lines of `polygon` in the face's texel space, a s + b t + c >= 0 inside (in texels).
void addEdges(const FaceFrame& frame, const std::vector<dvec3>& polygon, Lightmaps& lm, GpuLightmapFragment& g) {
  std::vector<glm::dvec2> st;
  for (const dvec3& p : polygon) st.push_back(frame.st(p));
  double area = 0.0;
  for (size_t i = 0; i < st.size(); ++i) {
    const glm::dvec2 &a = st[i], &b = st[(i + 1) % st.size()];
    area += a.x * b.y - b.x * a.y;
  }
  const double turn = area < 0.0 ? -1.0 : 1.0;
  g.firstEdge = uint32_t(lm.edges.size());
  for (size_t i = 0; i < st.size(); ++i) {
    const glm::dvec2 &a = st[i], &b = st[(i + 1) % st.size()];
    const glm::dvec2 e = b - a;
    const double len = glm::length(e);
    if (len < 1e-6) continue;
    const glm::dvec2 inward = turn * glm::dvec2(-e.y, e.x) / len;
    lm.edges.emplace_back(float(inward.x), float(inward.y), float(-glm::dot(inward, a)), 0.0f);
  }
  g.edgeCount = uint32_t(lm.edges.size()) - g.firstEdge;
}

struct LuxelRule {
  LightmapEngine engine;
  std::array<float, 256> styleValues;
};

// One compiled face as a fragment of the scene face seen through `frame`.
void addFragment(const FaceFrame& frame, const LightmappedFace& f, const LuxelRule& rule, uint32_t face, Lightmaps& lm) {
  GpuLightmapFragment g;
  g.width = uint32_t(f.width);
  g.height = uint32_t(f.height);
  g.firstLuxel = uint32_t(lm.luxels.size());
  // u = dot(p(s, t), luxelS) + luxelSOffset, an affine function of (s, t).
  const auto axis = [&](const dvec3& luxelAxis, double offset, float(&out)[4]) {
    out[0] = float(glm::dot(frame.ps, luxelAxis));
    out[1] = float(glm::dot(frame.pt, luxelAxis));
    out[2] = float(glm::dot(frame.p0, luxelAxis) + offset);
    out[3] = 0.0f;
  };
  axis(f.luxelS, f.luxelSOffset, g.luxelU);
  axis(f.luxelT, f.luxelTOffset, g.luxelV);
  const size_t luxels = size_t(f.width) * size_t(f.height);
  for (size_t k = 0; k < luxels; ++k) {
    std::array<glm::vec3, 4> stored{};
    for (size_t s = 0; s < 4 && f.styles[s] != 255; ++s)
      for (int c = 0; c < 3; ++c) stored[s][c] = float(f.rgb[(s * luxels + k) * 3 + size_t(c)]);
    lm.luxels.push_back(packLuxel(engineLuxel(rule.engine, rule.styleValues, f.styles, stored)));
  }
  // Quake 3's surfaces are triangles that need not make a convex polygon: one fragment each,
  // all reading the surface's one block of luxels.
  const auto add = [&](const std::vector<dvec3>& polygon) {
    addEdges(frame, polygon, lm, g);
    lm.fragments.push_back(g);
    lm.polygons.push_back(polygon);
    lm.fragmentFace.push_back(face);
  };
  if (f.triangles.empty()) return add(f.polygon);
  for (size_t i = 0; i + 2 < f.triangles.size(); i += 3)
    add({f.polygon[f.triangles[i]], f.polygon[f.triangles[i + 1]], f.polygon[f.triangles[i + 2]]});
}

// A face the engine draws without a lightmap in a lit level: black (its light is never added).
void addUnlitFragment(uint32_t face, Lightmaps& lm) {
  GpuLightmapFragment g;
  g.width = g.height = 1;
  g.firstLuxel = uint32_t(lm.luxels.size());
  g.firstEdge = uint32_t(lm.edges.size());
  lm.luxels.push_back(packLuxel(glm::vec3(0.0f)));
  lm.fragments.push_back(g);
  lm.polygons.emplace_back();
  lm.fragmentFace.push_back(face);
}

} // namespace

std::optional<LightmapEngine> lightmapEngineNamed(const std::string& name) {
  if (name == "quake") return LightmapEngine::Quake;
  if (name == "hexen2") return LightmapEngine::Hexen2;
  if (name == "halflife") return LightmapEngine::HalfLife;
  if (name == "quake2") return LightmapEngine::Quake2;
  if (name == "quake3") return LightmapEngine::Quake3;
  return std::nullopt;
}

std::array<float, 256> styleValuesAtLoad(LightmapEngine engine, const Scene& scene) {
  std::array<float, 256> values;
  values.fill(engine == LightmapEngine::Quake2 ? 1.0f : 256.0f); // a style no string was set for
  for (size_t s = 0; s < kPresetStylesAtLoad.size(); ++s) values[s] = letterValue(engine, kPresetStylesAtLoad[s]);
  values[kTestingStyle] = letterValue(engine, 'a');
  for (const Entity& e : scene.entities) {
    if (!e.classname().starts_with("light")) continue;
    const std::string* style = e.find("style");
    if (!style) continue;
    const int s = std::atoi(style->c_str());
    if (s < kFirstSwitchableStyle || s >= kTestingStyle) continue;
    const bool startOff = std::atoi(std::string(e.value("spawnflags", "0")).c_str()) & 1;
    values[size_t(s)] = letterValue(engine, startOff ? 'a' : 'm');
  }
  return values;
}

glm::vec3 engineLuxel(LightmapEngine engine, const std::array<float, 256>& styleValues, const std::array<uint8_t, 4>& styles,
                      const std::array<glm::vec3, 4>& stored) {
  if (engine == LightmapEngine::Quake3) { // one style; R_ColorShiftLightingBytes by 2 - 1 bits
    glm::ivec3 v = glm::ivec3(stored[0]) << 1;
    const int peak = std::max({v.x, v.y, v.z});
    if (peak > 255) v = v * 255 / peak;
    return glm::vec3(v);
  }
  if (engine == LightmapEngine::Quake2) {
    glm::vec3 sum(0.0f);
    for (size_t s = 0; s < 4 && styles[s] != 255; ++s) sum += stored[s] * styleValues[styles[s]];
    glm::ivec3 v(sum); // Q_ftol
    const int peak = std::max({v.x, v.y, v.z});
    if (peak > 255) v = glm::ivec3(glm::vec3(v) * (255.0f / float(peak)));
    return glm::vec3(v);
  }
  glm::ivec3 sum(0);
  for (size_t s = 0; s < 4 && styles[s] != 255; ++s) sum += glm::ivec3(stored[s]) * int(styleValues[styles[s]]);
  // GoldSrc: the sum as a value stored at style 'm', which Lightmaps::luxelDisplay's table takes
  // through R_BuildLightMap's scale and gamma (exact for luxels of style 0 alone).
  if (engine == LightmapEngine::HalfLife) return glm::vec3(glm::min(sum / BT_GOLDSRC_STYLE_M, glm::ivec3(255)));
  const int shift = engine == LightmapEngine::Hexen2 ? 7 : 8;
  return glm::vec3(glm::min(sum >> shift, glm::ivec3(255)));
}

float engineDisplayScale(LightmapEngine engine) {
  // QuakeSpasm's overbright and Quake 3's gamma ramp double the picture.
  return engine == LightmapEngine::Quake || engine == LightmapEngine::Quake3 ? 2.0f / 255.0f : 1.0f / 255.0f;
}

CompiledLightmaps buildCompiledLightmaps(const Scene& scene, const RenderScene& rs, LightmapEngine engine,
                                         const std::array<float, 256>* styleScale) {
  CompiledLightmaps out;
  const CompiledLighting* cl = scene.compiledLighting.get();
  if (!cl) return out;
  out.compiledFaces = size_t(std::count_if(cl->faces.begin(), cl->faces.end(), [](const LightmappedFace& f) { return f.width > 0; }));
  if (out.compiledFaces == 0) return out;
  const CompiledFaceIndex index(*cl);
  LuxelRule rule{engine, styleValuesAtLoad(engine, scene)};
  if (styleScale)
    for (size_t s = 0; s < rule.styleValues.size(); ++s) rule.styleValues[s] *= (*styleScale)[s];
  Lightmaps& lm = out.lightmaps;
  lm.displayScale = engineDisplayScale(engine);
  if (engine == LightmapEngine::HalfLife) lm.luxelDisplay = BT_LUXEL_DISPLAY_GOLDSRC;
  lm.faceRanges.assign(scene.faces.size(), glm::uvec2(0));
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    // Mesh triangles (Quake 3 curves and soups) lie on no brush side: lit at each point, as in
    // faithful mode, until the view maps their own lightmap coordinates.
    if (face.brush == kNoBrush) continue;
    const std::vector<uint32_t> on = index.on(scene.brushes[face.brush].entity, face.plane, face.winding);
    const FaceFrame frame(gpuFace(rs, f));
    if (on.empty() || !frame.valid) continue;
    const uint32_t first = uint32_t(lm.fragments.size());
    for (uint32_t i : on)
      if (cl->faces[i].width > 0) addFragment(frame, cl->faces[i], rule, f, lm);
    if (lm.fragments.size() == first) {
      addUnlitFragment(f, lm);
      ++out.facesUnlit;
    } else {
      ++out.facesShown;
    }
    lm.faceRanges[f] = glm::uvec2(first, uint32_t(lm.fragments.size()) - first);
  }
  return out;
}

std::string showCompiledLightmaps(const Scene& scene, RenderScene& rs, const std::string& game, const std::array<float, 256>* styleScale) {
  const CompiledLighting* cl = scene.compiledLighting.get();
  if (!cl) return "the level is not a compiled .bsp, so it has no lightmaps";
  const std::optional<LightmapEngine> engine = lightmapEngineNamed(game.empty() || !lightmapEngineNamed(game) ? cl->engine : game);
  if (!engine) return "no display rule for the engine '" + cl->engine + "'";
  CompiledLightmaps compiled = buildCompiledLightmaps(scene, rs, *engine, styleScale);
  if (compiled.compiledFaces == 0) return "the level has no lightmaps (compiled without light)";
  rs.lightmaps = std::move(compiled.lightmaps);
  return {};
}

} // namespace bt

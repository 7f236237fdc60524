#include "lighting/bounce.h"
#include "lighting/vis_approx.h"

#include "lighting/faithful_light.h"
#include "lighting/lightmap_bake.h"
#include "lighting/physical_light.h"
#include "lighting/qbsp_tjunc.h"
#include "quake/entity_keys.h"
#include "scene/parallel_for.h"
#include "scene/winding.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <map>
#include <span>
#include <string>

namespace bt {

namespace {

constexpr float kLuxelTexels = 16.0f;                                // Quake 1 lightmaps: one luxel every 16 texels
constexpr double kBounceLift = 1.0;                                  // bounce.cc lifts the light 1 unit off its face
constexpr double kSampleLift = 1.0;                                  // ltface.cc sampleOffPlaneDist: luxels are sampled 1 unit off the face
constexpr double kMinBounceArea = 1.0;                               // bounce.cc skips smaller faces
constexpr size_t kMaxFragmentsToSplit = 256;                         // see bounceFaces
constexpr uint32_t kBounceSeed = 0x626f756eu;                        // the sampling's own random stream
constexpr float kOccluded = std::numeric_limits<float>::quiet_NaN(); // a luxel the compiler leaves unlit
constexpr double kPointEqualEpsilon = 0.05; // mathlib.hh POINT_EQUAL_EPSILON: on an edge counts as inside, and as behind it
constexpr int kMaxNeighbourSteps = 3;       // CalcPointNormal's recursion depth

dvec3 vertexMean(const std::vector<dvec3>& w) {
  dvec3 sum(0.0);
  for (const dvec3& p : w) sum += p;
  return sum / double(w.size());
}

// Face_EdgeIndexSmoothed without phong shading: across each edge of each bounce face, the bounce
// face of the same plane and side that has the same edge the other way round (qbsp's T-junction
// fix and subdivision leave neighbours sharing their edges exactly), or -1. Edges are matched on
// their end points rounded to 1/256 unit.
std::vector<std::vector<int32_t>> coplanarNeighbours(const Scene& scene, const std::vector<BounceFace>& faces) {
  using Key = std::array<int64_t, 10>;
  auto q = [](double v, double scale) { return int64_t(std::llround(v * scale)); };
  auto keyOf = [&](const Plane& plane, const dvec3& a, const dvec3& b) {
    return Key{q(plane.normal.x, 1e4), q(plane.normal.y, 1e4), q(plane.normal.z, 1e4), q(plane.dist, 256.0), q(a.x, 256.0),
               q(a.y, 256.0),          q(a.z, 256.0),          q(b.x, 256.0),          q(b.y, 256.0),        q(b.z, 256.0)};
  };
  std::map<Key, int32_t> edges;
  for (size_t i = 0; i < faces.size(); ++i) {
    const Winding& w = faces[i].polygon;
    for (size_t k = 0; k < w.size(); ++k) edges.emplace(keyOf(scene.faces[faces[i].face].plane, w[k], w[(k + 1) % w.size()]), int32_t(i));
  }
  std::vector<std::vector<int32_t>> out(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) {
    const Winding& w = faces[i].polygon;
    out[i].assign(w.size(), -1);
    for (size_t k = 0; k < w.size(); ++k)
      if (const auto it = edges.find(keyOf(scene.faces[faces[i].face].plane, w[(k + 1) % w.size()], w[k]));
          it != edges.end() && it->second != int32_t(i))
        out[i][k] = it->second;
  }
  return out;
}

// A luxel's sample point (lifted off its face) and the bounce face it lies on; NaN: occluded.
struct LuxelPoint {
  glm::vec3 p{kOccluded};
  uint32_t face = 0;
};

// Where the compiler samples grid point p (on the plane of bounce face `start`), ltface.cc
// CalcPointNormal without phong shading: p itself inside the face; outside it, on the coplanar
// neighbour across the edge p lies behind (the one p is least past the end points of), up to 3
// faces on; else snapped onto the last face's boundary when that is at most a luxel of the first
// face's grid away, else occluded (no light, but one of the face's luxels). A T-junction fan's
// luxels so take their light where they lie, on the fan's other pieces.
LuxelPoint compilerLuxelPoint(const Scene& scene, const std::vector<BounceFace>& faces, const std::vector<std::vector<int32_t>>& neighbours,
                              uint32_t start, dvec3 p) {
  uint32_t at = start;
  for (int depth = 0;; ++depth) {
    const Winding& w = faces[at].polygon;
    const dvec3 n = scene.faces[faces[at].face].plane.normal;
    const double wound = glm::dot(areaVector(w), n) < 0.0 ? -1.0 : 1.0;
    double inside = std::numeric_limits<double>::infinity(), bestPast = std::numeric_limits<double>::infinity();
    int best = -1;
    for (size_t k = 0; k < w.size(); ++k) {
      const dvec3 a = w[k], edge = w[(k + 1) % w.size()] - a;
      const double length = glm::length(edge);
      if (!(length > 0.0)) continue;
      const double above = glm::dot(p - a, wound * glm::cross(n, edge) / length);
      inside = std::min(inside, above);
      if (above >= kPointEqualEpsilon) continue;
      // FractionOfLine, and how far p lies past the edge's end points along it (t x length past
      // the far end, as the compiler measures it).
      const double t = glm::dot(p - a, edge) / (length * length);
      const double past = t < 0.0 ? -t * length : t > 1.0 ? t * length : 0.0;
      if (past < bestPast) bestPast = past, best = int(k);
    }
    if (inside >= -kPointEqualEpsilon) return {glm::vec3(p + n * kSampleLift), at};
    if (best >= 0 && depth < kMaxNeighbourSteps && neighbours[at][size_t(best)] >= 0) {
      at = uint32_t(neighbours[at][size_t(best)]);
      continue;
    }
    const dvec3 q = nearestOnPolygon(w, n, p);
    const TextureFrame& frame = scene.faces[faces[start].face].frame;
    const double away = glm::length(glm::dvec2(frame.s(q) - frame.s(p), frame.t(q) - frame.t(p))) / kLuxelTexels;
    if (away > 1.0) return {};
    return {glm::vec3(q + n * kSampleLift), at};
  }
}

// The compiler's luxel grid of bounce face i: its texture-space extents (in float, as the
// compiler computes them) floored/ceiled to 16 texels, one luxel every 16 texels, each placed as
// compilerLuxelPoint places it.
std::vector<LuxelPoint> luxelPoints(const Scene& scene, const std::vector<BounceFace>& faces,
                                    const std::vector<std::vector<int32_t>>& neighbours, uint32_t i) {
  const Face& face = scene.faces[faces[i].face];
  const std::vector<dvec3>& polygon = faces[i].polygon;
  const TextureFrame& frame = face.frame;
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (const dvec3& v : polygon) {
    const float st[2] = {float(frame.s(v)), float(frame.t(v))};
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], st[a]), hi[a] = std::max(hi[a], st[a]);
  }
  int first[2], count[2];
  for (int a = 0; a < 2; ++a) {
    first[a] = int(std::floor(lo[a] / kLuxelTexels));
    count[a] = int(std::ceil(hi[a] / kLuxelTexels)) - first[a] + 1;
  }
  // Texture space -> world: rows tangent, bitangent, normal map (p - origin) to (s, t, height).
  const dvec3 n = face.plane.normal;
  const glm::dmat3 toTexture = glm::transpose(glm::dmat3(frame.tangent, frame.bitangent, n));
  const double det = glm::determinant(toTexture);
  if (!(std::abs(det) > 1e-12)) return {LuxelPoint{glm::vec3(vertexMean(polygon)), i}};
  const glm::dmat3 toWorld = glm::inverse(toTexture);
  const double height = face.plane.dist - glm::dot(n, frame.origin);
  // Every luxel: a subset misses a spotlight's bright patch (deprecated/nobounce's pillars), and
  // qbsp's subdivision keeps a face within 17 x 17 luxels.
  std::vector<LuxelPoint> points;
  points.reserve(size_t(count[0]) * size_t(count[1]));
  for (int t = 0; t < count[1]; ++t)
    for (int s = 0; s < count[0]; ++s) {
      const dvec3 st((first[0] + s) * double(kLuxelTexels), (first[1] + t) * double(kLuxelTexels), height);
      points.push_back(compilerLuxelPoint(scene, faces, neighbours, i, frame.origin + toWorld * st));
    }
  return points;
}

// The texture's mean colour in its own (sRGB) bytes, 0..1: ericw-tools' grey when it has no
// pixels (a level compiled with -notex), black for a texture it could not find, as we could not
// (its mean colour is that of an empty image: q2_areaportal's bounce agrees so, 98 % of its
// luxels within 5 %, against 84 % with grey).
glm::vec3 textureMean(const Material& m) {
  if (m.missing()) return glm::vec3(0.0f);
  if (m.baseColor.empty()) return glm::vec3(kBounceGrey);
  glm::dvec3 sum(0.0);
  for (int y = 0; y < m.baseColor.height; ++y)
    for (int x = 0; x < m.baseColor.width; ++x) {
      const uint8_t* p = m.baseColor.texel(x, y);
      sum += glm::dvec3(p[0], p[1], p[2]);
    }
  return glm::vec3(sum / (255.0 * double(m.baseColor.width) * double(m.baseColor.height)));
}

// Face_ShouldBounce, for one brush side.
bool sideBounces(const RenderScene& rs, uint32_t faceIndex) {
  const uint32_t flags = rs.faceFlags[faceIndex];
  if (flags & (kFaceHidden | kFaceSky | kFaceNoShadow)) return false;
  if (objectChannels(rs, faceIndex) != kDefaultChannels) return false; // light.cc: off channel 1, no bounce
  if ((flags & kFaceLiquid) && !rs.world.litwater) return false;       // no lightmap, nothing to bounce
  const Scene& scene = *rs.scene;
  const Face& face = scene.faces[faceIndex];
  if (face.brush == kNoBrush) return false; // a mesh triangle: no lightmap to bounce (faceHasLightmap)
  if (face.material < rs.surfaceLights.size() && rs.surfaceLights[face.material].value != 0.0f) return false;
  // A brush model's `_bounce -1` keeps its faces from bouncing (qbsp's no_bounce texinfo flag).
  // Not on the brush entities qbsp merges into the world: the compiler bounced light off
  // deprecated/nobounce.map's func_detail with `_bounce -1` (its oracle lightmaps), so neither do we.
  if (face.brush < scene.brushes.size()) {
    const uint32_t e = scene.brushes[face.brush].entity;
    if (e < scene.entities.size() && !mergedIntoWorld(scene.entities[e].classname()) &&
        quake::EntityKeys(scene.entities[e]).number("_bounce", 0.0f) == -1.0f)
      return false;
  }
  return true;
}

// The lights of `lights` that can light p, in index order: those `grid` (a grid of them) lists
// for p with the lights of infinite reach merged in (none unless a value is infinite), or every
// light without a grid. `scratch` holds them where they are not a list of the grid.
std::span<const uint32_t> candidatesAt(const std::vector<GpuLight>& lights, const std::optional<LightGrid>& grid, const glm::vec3& p,
                                       std::vector<uint32_t>& scratch) {
  if (!grid) {
    scratch.resize(lights.size());
    for (uint32_t i = 0; i < lights.size(); ++i) scratch[i] = i;
    return scratch;
  }
  const std::span<const uint32_t> cell = grid->cellLights(p), global = grid->globalLights();
  if (global.empty()) return cell;
  scratch.clear();
  std::merge(cell.begin(), cell.end(), global.begin(), global.end(), std::back_inserter(scratch));
  return scratch;
}

// qbsp's T-junction fix of the world's faces (qbsp_tjunc.h), on the bouncing sides' compiled
// faces `perSide`: every drawn face of the world lends its vertices, those that bounce no light
// (sky, liquids, surface lights) too, but not those that look into the void, which qbsp has
// removed by then. A world with a tree of its own (Quake 2) only, whose faces are the compiler's.
void fixWorldTJunctions(const RenderScene& rs, const std::vector<BrushContents>& contents, std::vector<std::vector<Winding>>& perSide,
                        unsigned threads) {
  const Scene& scene = *rs.scene;
  auto inWorld = [&](uint32_t f) {
    const uint32_t brush = scene.faces[f].brush;
    return brush < contents.size() && contents[brush] != BrushContents::Empty && !(rs.faceFlags[f] & kFaceHidden);
  };
  std::vector<std::vector<Winding>> others(scene.faces.size());
  parallelFor(scene.faces.size(), threads, [&](size_t i) {
    if (inWorld(uint32_t(i)) && perSide[i].empty() && !sideBounces(rs, uint32_t(i)))
      others[i] = compiledFacePolygons(scene, uint32_t(i), contents, rs.worldTree);
  });
  const VoidTest voidTest(scene, rs.tracer);
  TJunctionVertices vertices;
  std::vector<uint32_t> groups(scene.faces.size(), 0);
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    if (!inWorld(f)) continue;
    groups[f] = weldGroup(scene, contents, scene.faces[f].brush);
    for (const std::vector<Winding>* faces : {&perSide[f], &others[f]})
      for (const Winding& w : *faces)
        if (!voidTest.inVoid(vertexMean(w) + scene.faces[f].plane.normal * kVoidProbeDistance)) vertices.add(w, groups[f]);
  }
  parallelFor(scene.faces.size(), threads, [&](size_t i) {
    if (!inWorld(uint32_t(i)) || perSide[i].empty()) return;
    std::vector<Winding> fixed;
    for (const Winding& w : perSide[i])
      for (const Winding& piece : fixTJunctions(w, groups[i], vertices)) fixed.push_back(withoutColinearPoints(piece));
    perSide[i] = std::move(fixed);
  });
}

} // namespace

std::vector<BounceFace> bounceFaces(const RenderScene& rs, const std::vector<BrushContents>& contents, unsigned threads) {
  const Scene& scene = *rs.scene;
  // Each side on its own (the qbsp face emulation is most of the cost), then in side order.
  std::vector<std::vector<Winding>> perSide(scene.faces.size());
  parallelFor(scene.faces.size(), threads, [&](size_t i) {
    const uint32_t f = uint32_t(i);
    if (!sideBounces(rs, f)) return;
    // A side cut by thousands of brushes (lq_e4m3's floors: 2 208 fragments) would take a minute
    // to split as qbsp's tree splits it; its CSG fragments stand in for its compiled faces there
    // (the same area and luxels, more and smaller bounce lights).
    std::vector<Winding> fragments = visibleFragments(scene, f, contents);
    perSide[i] = fragments.size() > kMaxFragmentsToSplit ? std::move(fragments) : compiledFacePolygons(scene, f, contents, rs.worldTree);
  });
  if (!rs.worldTree.nodes().empty()) fixWorldTJunctions(rs, contents, perSide, threads);
  std::vector<BounceFace> faces;
  for (uint32_t f = 0; f < perSide.size(); ++f)
    for (Winding& polygon : perSide[f])
      if (area(polygon) >= kMinBounceArea) faces.push_back({f, std::move(polygon)});
  return faces;
}

std::optional<GpuLight> bounceLight(const RenderScene& rs, const BounceFace& face, const glm::vec3& meanLight, const glm::vec3& texture) {
  const Face& side = rs.scene->faces[face.face];
  glm::vec3 color = meanLight * glm::mix(glm::vec3(kBounceGrey), texture, rs.world.bouncecolorscale);
  const float intensity = std::max({color.x, color.y, color.z});
  if (!(intensity > 0.0f)) return std::nullopt;
  if (intensity > 1.0f) color /= intensity;

  GpuLight light;
  light.type = uint32_t(LightType::Point);
  light.formula = uint32_t(LightFormula::Bounce);
  light.origin = glm::vec3(vertexMean(face.polygon) + side.plane.normal * kBounceLift);
  light.direction = glm::vec3(side.plane.normal);
  light.color = color;
  light.value = intensity * float(area(face.polygon)) * rs.world.bouncescale * kBounceScale;
  light.anglescale = 1.0f; // the receiver's plain cosine
  light.flags = kLightFlagFromSurface;
  // Dirt dims bounced light wherever the level uses dirt (Dirt_GetScaleFactor without a light).
  if (rs.world.dirtSettings.enabled) {
    light.flags |= kLightFlagDirt;
    light.dirtScale = rs.world.dirtSettings.scale;
    light.dirtGain = rs.world.dirtSettings.gain;
  }
  return light;
}

size_t bounceSampleCount(size_t count, size_t total, size_t budget) {
  if (total <= budget || count == 0) return count;
  const double share = double(count) * double(budget) / double(total);
  return std::clamp<size_t>(size_t(std::llround(share)), 1, count);
}

std::vector<GpuLight> clusterBounceLights(const std::vector<GpuLight>& lights, const Bounds& bounds, size_t maxLights) {
  if (lights.size() <= maxLights || maxLights == 0 || bounds.empty()) return lights;
  // The key of a light in an n^3 grid: its cell and the axis direction its normal is nearest to.
  auto keyOf = [&](const GpuLight& l, int n) {
    uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double extent = std::max(bounds.max[a] - bounds.min[a], 1.0);
      const int cell = std::clamp(int((double(l.origin[a]) - bounds.min[a]) / extent * n), 0, n - 1);
      key = key * uint64_t(n) + uint64_t(cell);
    }
    const glm::vec3 d = glm::abs(l.direction);
    const int axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    return key * 6 + uint64_t(axis * 2 + (l.direction[axis] < 0.0f ? 1 : 0));
  };
  // The finest grid whose occupied (cell, direction) pairs fit (coarser cells merge across walls).
  // The count is not monotonic in n, so every n from the finest down is tried: each occupied key
  // marked with n in a table of all keys (64^3 x 6), not sorted: sorting each grid cost 5x more.
  constexpr int kFinest = 64;
  std::vector<uint64_t> keys(lights.size());
  std::vector<uint8_t> markedFor(size_t(kFinest) * kFinest * kFinest * 6, 0);
  for (int n = kFinest;; --n) {
    size_t count = 0;
    for (size_t i = 0; i < lights.size(); ++i) {
      keys[i] = keyOf(lights[i], n);
      if (markedFor[keys[i]] != uint8_t(n)) markedFor[keys[i]] = uint8_t(n), ++count;
    }
    if (count <= maxLights || n == 1) break;
  }
  struct Cluster {
    glm::dvec3 emit{0.0}, origin{0.0}, normal{0.0};
    double weight = 0.0;
    const GpuLight* first = nullptr;
  };
  std::vector<uint64_t> order = keys;
  std::sort(order.begin(), order.end());
  order.erase(std::unique(order.begin(), order.end()), order.end());
  std::vector<Cluster> clusters(order.size());
  for (size_t i = 0; i < lights.size(); ++i) {
    const GpuLight& l = lights[i];
    Cluster& c = clusters[size_t(std::lower_bound(order.begin(), order.end(), keys[i]) - order.begin())];
    const glm::dvec3 emit = double(l.value) * glm::dvec3(l.color);
    const double w = std::max({emit.x, emit.y, emit.z});
    c.emit += emit;
    c.origin += w * glm::dvec3(l.origin);
    c.normal += w * glm::dvec3(l.direction);
    c.weight += w;
    if (!c.first) c.first = &l;
  }
  std::vector<GpuLight> out;
  for (const Cluster& c : clusters) {
    if (!(c.weight > 0.0)) continue;
    GpuLight l = *c.first; // type, formula, flags and dirt are those of every bounce light
    const double value = std::max({c.emit.x, c.emit.y, c.emit.z});
    l.value = float(value);
    l.color = glm::vec3(c.emit / value);
    l.origin = glm::vec3(c.origin / c.weight);
    const double len = glm::length(c.normal);
    if (len > 0.0) l.direction = glm::vec3(c.normal / len);
    out.push_back(l);
  }
  return out;
}

namespace {

// `_dirtmode 0`'s occlusion at a luxel is a fixed function of the point (its 48 rays draw no
// random numbers): once cast, its rays serve every later pass that samples the luxel (NaN: not
// cast yet). `_dirtmode 1` draws them from the pass's own numbers: cast again (none kept).
std::vector<std::vector<float>> reusableDirtOcclusion(const RenderScene& rs, const std::vector<std::vector<LuxelPoint>>& luxels,
                                                      const BounceBudget& budget) {
  const DirtSettings& dirt = rs.world.dirtSettings;
  std::vector<std::vector<float>> occlusion;
  if (!budget.reuseDirtOcclusion || !dirt.enabled || dirt.mode == 1) return occlusion;
  occlusion.resize(luxels.size());
  for (size_t i = 0; i < luxels.size(); ++i) occlusion[i].assign(luxels[i].size(), std::numeric_limits<float>::quiet_NaN());
  return occlusion;
}

} // namespace

BounceLights makeBounceLights(const RenderScene& rs, const std::vector<BrushContents>& contents, const BounceBudget& budget) {
  BounceLights out;
  if (rs.world.bounces <= 0) return out;
  const std::vector<BounceFace> faces = bounceFaces(rs, contents, budget.threads);
  const std::vector<std::vector<int32_t>> neighbours = coplanarNeighbours(*rs.scene, faces);
  std::vector<std::vector<LuxelPoint>> luxels(faces.size());
  parallelFor(faces.size(), budget.threads, [&](size_t i) { luxels[i] = luxelPoints(*rs.scene, faces, neighbours, uint32_t(i)); });
  // Where the compiler samples a luxel: a point in (or at) a solid moves out of it as the compiler
  // moves it, or is occluded (PositionSamplePointOnFace). Without this the luxels along a face's
  // edge, which lie on the plane of the wall beside it, see the lights behind that wall (the
  // lit-games areaportal levels: the far rooms' floors bounced the next room's light, 85 % -> 98 %
  // of luxels within 5 %). Found when a pass first samples the luxel (a face is one thread's).
  const VoidTest voids(*rs.scene, rs.tracer);
  std::vector<std::vector<uint8_t>> placed(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) placed[i].assign(luxels[i].size(), 0);
  auto samplePoint = [&](size_t i, size_t k) -> const glm::vec3& {
    LuxelPoint& l = luxels[i][k];
    if (!placed[i][k] && !std::isnan(l.p.x))
      l.p = compilerSamplePoint(rs, contents, voids, faces[l.face].face, dvec3(l.p)).value_or(glm::vec3(kOccluded));
    placed[i][k] = 1;
    return l.p;
  };
  for (const std::vector<LuxelPoint>& points : luxels) out.luxels += points.size();
  out.sampledLuxels = out.luxels;
  // Each material's mean colour once, not once per face and pass.
  const Scene& scene = *rs.scene;
  std::vector<glm::vec3> textureMeans(scene.materials.size());
  parallelFor(scene.materials.size(), budget.threads, [&](size_t m) { textureMeans[m] = textureMean(scene.materials[m]); });
  auto textureOf = [&](const BounceFace& face) {
    const uint32_t m = scene.faces[face.face].material;
    return m < textureMeans.size() ? textureMeans[m] : glm::vec3(kBounceGrey);
  };

  std::vector<std::vector<float>> occlusion = reusableDirtOcclusion(rs, luxels, budget);
  // A later pass draws among the previous pass's lights (LightSet::Given), sweeping only
  // those that can light the luxel: the lists of a light grid of them (see BounceBudget).
  std::vector<GpuLight> previous;
  std::optional<LightGrid> previousGrid;
  for (int pass = 0; pass < rs.world.bounces; ++pass) {
    const size_t passBudget = pass == 0 ? budget.directLuxels : budget.gatherLuxels;
    if (pass > 0 && budget.gatherGridCellsPerAxis > 0)
      previousGrid = buildLightGrid(previous, rs.tracer.bounds(), rs.world.scaledist, budget.gatherGridCellsPerAxis);
    std::atomic<size_t> sampled{0};
    std::atomic<bool> drewLights{false};
    std::vector<std::optional<GpuLight>> made(faces.size());
    // Face i is one thread's in a pass: its luxels' occlusion is read and written there alone.
    parallelFor(faces.size(), budget.threads, [&](size_t i) {
      const BounceFace& face = faces[i];
      const glm::vec3 n(rs.scene->faces[face.face].plane.normal);
      const bool twoSided = rs.faceFlags[face.face] & kFaceLiquid;
      const std::vector<LuxelPoint>& points = luxels[i];
      // The compiler's light cull without vis data dims what a face bounces as it dims its luxels.
      const GpuVisBox box = polygonBounds(face.polygon);
      const VisCull cull{rs.visBoxes.empty() ? nullptr : &box, rs.visBoxes.data()}; // buildRenderScene computed them first
      // An evenly spread, fixed subset: the middle luxel of each of `count` equal runs.
      const size_t count = bounceSampleCount(points.size(), out.luxels, passBudget);
      sampled += count;
      glm::vec3 sum(0.0f);
      std::vector<uint32_t> candidates;
      for (size_t j = 0; j < count; ++j) {
        const size_t k = (2 * j + 1) * points.size() / (2 * count);
        const glm::vec3& at = samplePoint(i, k);
        if (std::isnan(at.x)) continue; // occluded: no light, but one of the face's luxels
        Rng rng = pixelRng(uint32_t(i), uint32_t(k), uint32_t(pass), kBounceSeed);
        std::optional<float> dirt;
        if (!occlusion.empty()) {
          float& known = occlusion[i][k];
          if (std::isnan(known)) known = faithfulDirtOcclusion(rs, at, n, rng);
          dirt = known;
        }
        FaithfulQuery q{.p = at, .n = n, .twoSided = twoSided, .cull = cull, .lights = LightSet::BounceSources, .occlusion = dirt};
        if (pass == 0) {
          sum += faithfulLight(rs, q, rng);
          continue;
        }
        if (previous.size() > budget.gatherShadowRays) drewLights = true;
        const GivenLights given{previous, candidatesAt(previous, previousGrid, at, candidates), budget.gatherShadowRays};
        q.lights = LightSet::Given;
        q.given = &given;
        sum += faithfulLight(rs, q, rng);
      }
      made[i] = bounceLight(rs, face, sum / float(std::max<size_t>(count, 1)), textureOf(face));
    });
    out.sampledLuxels = std::min(out.sampledLuxels, sampled.load());
    out.sampledLights |= drewLights.load();
    previous.clear();
    for (const std::optional<GpuLight>& l : made)
      if (l) previous.push_back(*l);
    if (previous.empty()) break; // "No bounces; indirect lighting halted"
    out.lights.insert(out.lights.end(), previous.begin(), previous.end());
  }
  out.madeLights = out.lights.size();
  out.lights = clusterBounceLights(out.lights, rs.tracer.bounds(), budget.renderLights);
  for (GpuLight& l : out.lights) physical::prepare(l, rs.world.scaledist); // as every light of a RenderScene
  return out;
}

} // namespace bt

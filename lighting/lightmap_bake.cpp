#include "lighting/lightmap_bake.h"

#include "lighting/faithful.h"
#include "lighting/faithful_light.h"
#include "lighting/game_rules.h"
#include "lighting/qbsp_faces.h"
#include "lighting/visibility.h"
#include "lighting/sampling.h"
#include "lighting/surface_lights.h"
#include "lighting/vis_approx.h"
#include "scene/parallel_for.h"
#include "scene/winding.h"

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace bt {

namespace {

constexpr double kSampleLift = 1.0;                      // ltface.cc sampleOffPlaneDist
constexpr double kSolidJitter = 0.5;                     // PositionSamplePointOnFace tries p ± 0.5 on each axis
constexpr float kSolidMargin = 0.1f;                     // Light_PointInSolid: a point this near a BSP plane is tested on both sides
constexpr uint32_t kBakeSeed = 0x6c757865u;              // the bake's own random stream
constexpr int kSoftLightSamples = faithful::kSunSamples; // the compiler's suns per penumbra

// Texture space (s, t, height above the frame's origin along n) <-> world, for one face.
struct FaceFrame {
  glm::dmat3 toWorld{1.0};
  dvec3 origin{0.0};
  double height = 0.0;
  bool valid = false;

  explicit FaceFrame(const Face& face) {
    const dvec3 n = face.plane.normal;
    const glm::dmat3 toTexture = glm::transpose(glm::dmat3(face.frame.tangent, face.frame.bitangent, n));
    if (!(std::abs(glm::determinant(toTexture)) > 1e-12)) return;
    toWorld = glm::inverse(toTexture);
    origin = face.frame.origin;
    height = face.plane.dist - glm::dot(n, origin);
    valid = true;
  }
  dvec3 point(double s, double t) const { return origin + toWorld * dvec3(s, t, height); }
};

// The fragment's edges as texel-space lines, unit (a, b), positive inside.
void appendEdges(const Face& face, const std::vector<dvec3>& polygon, std::vector<glm::vec4>& edges) {
  std::vector<glm::dvec2> st;
  st.reserve(polygon.size());
  for (const dvec3& v : polygon) st.emplace_back(face.frame.s(v), face.frame.t(v));
  double area2 = 0.0;
  for (size_t i = 0; i < st.size(); ++i) {
    const glm::dvec2& a = st[i];
    const glm::dvec2& b = st[(i + 1) % st.size()];
    area2 += a.x * b.y - a.y * b.x;
  }
  const double orientation = area2 < 0.0 ? -1.0 : 1.0;
  for (size_t i = 0; i < st.size(); ++i) {
    const glm::dvec2& a = st[i];
    const glm::dvec2& b = st[(i + 1) % st.size()];
    glm::dvec2 normal = orientation * glm::dvec2(-(b.y - a.y), b.x - a.x);
    const double len = glm::length(normal);
    if (!(len > 1e-9)) continue; // a degenerate edge says nothing
    normal /= len;
    edges.emplace_back(float(normal.x), float(normal.y), float(-glm::dot(normal, a)), 0.0f);
  }
}

// Quake's luxel grid of a polygon on `face` (CalcSurfaceExtents): texture extents in float.
GpuLightmapFragment luxelGrid(const Face& face, const std::vector<dvec3>& polygon) {
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (const dvec3& v : polygon) {
    const float st[2] = {float(face.frame.s(v)), float(face.frame.t(v))};
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], st[a]), hi[a] = std::max(hi[a], st[a]);
  }
  GpuLightmapFragment g;
  const int first[2] = {int(std::floor(lo[0] / float(kLuxelTexels))), int(std::floor(lo[1] / float(kLuxelTexels)))};
  g.minS = first[0];
  g.minT = first[1];
  g.width = uint32_t(int(std::ceil(hi[0] / float(kLuxelTexels))) - first[0] + 1);
  g.height = uint32_t(int(std::ceil(hi[1] / float(kLuxelTexels))) - first[1] + 1);
  return g;
}

// The luxel axes of `_world_units_per_luxel` (ericw-tools common/bsputils.cc, faceextents_t for
// world_units_per_luxel_t; qvec.hh MakeTangentAndBitangentUnnormalized): the face normal snapped
// to its largest axis (the first of equal ones), the other two axes crossed with it, swapped
// unless tangent x bitangent points along the normal, each divided by the luxel size.
std::array<glm::vec3, 2> decoupledAxes(const dvec3& normal, float worldUnitsPerLuxel) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(normal[i]) > std::abs(normal[axis])) axis = i;
  dvec3 snapped(0.0), a(0.0), b(0.0);
  snapped[axis] = normal[axis] > 0.0 ? 1.0 : -1.0;
  a[(axis + 1) % 3] = 1.0;
  b[(axis + 2) % 3] = 1.0;
  dvec3 tangent = glm::cross(snapped, a), bitangent = glm::cross(snapped, b);
  if (glm::dot(glm::cross(tangent, bitangent), snapped) < 0.0) std::swap(tangent, bitangent);
  const float scale = 1.0f / worldUnitsPerLuxel;
  return {glm::vec3(tangent) * scale, glm::vec3(bitangent) * scale};
}

// The decoupled luxel grid of a polygon on `face`: luxel (x, y) centred where the axes' world
// projections are x + min, y + min, the extents floored / ceiled in float as the compiler does;
// written into luxelU / luxelV as functions of the face's texel coordinates, which both tracers
// already read (scene/gpu_structs.h), so that the display filters over this grid unchanged.
GpuLightmapFragment decoupledGrid(const Face& face, const std::vector<dvec3>& polygon, float worldUnitsPerLuxel) {
  const std::array<glm::vec3, 2> axes = decoupledAxes(face.plane.normal, worldUnitsPerLuxel);
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (const dvec3& v : polygon)
    for (int a = 0; a < 2; ++a) {
      const float lm = glm::dot(axes[size_t(a)], glm::vec3(v));
      lo[a] = std::min(lo[a], lm), hi[a] = std::max(hi[a], lm);
    }
  GpuLightmapFragment g;
  g.minS = int(std::floor(lo[0]));
  g.minT = int(std::floor(lo[1]));
  g.width = uint32_t(int(std::ceil(hi[0])) - g.minS + 1);
  g.height = uint32_t(int(std::ceil(hi[1])) - g.minT + 1);
  const FaceFrame frame(face);
  if (!frame.valid) return luxelGrid(face, polygon); // no texel frame to write the grid in
  // u + minS = dot(axis, origin + toWorld (s, t, height)): a s + b t + c.
  const auto write = [&](const glm::vec3& axis, float(&out)[4]) {
    const dvec3 d(axis);
    out[0] = float(glm::dot(frame.toWorld[0], d));
    out[1] = float(glm::dot(frame.toWorld[1], d));
    out[2] = float(glm::dot(frame.origin + frame.toWorld[2] * frame.height, d));
    out[3] = 0.0f;
  };
  write(axes[0], g.luxelU);
  write(axes[1], g.luxelV);
  return g;
}

bool quakeGrid(const GpuLightmapFragment& g) {
  const GpuLightmapFragment quake;
  return std::equal(std::begin(g.luxelU), std::end(g.luxelU), std::begin(quake.luxelU)) &&
      std::equal(std::begin(g.luxelV), std::end(g.luxelV), std::begin(quake.luxelV));
}

// A fragment's luxel coordinates <-> the face's texel coordinates: Quake's 16 texels, or the
// decoupled grid's affine map inverted (in double).
struct LuxelFrame {
  glm::dmat2 toTexel{16.0}; // (s, t) = toTexel ((x, y) + min) + texelOffset
  glm::dvec2 texelOffset{0.0};
  glm::dmat2 toLuxel{1.0 / 16.0};
  glm::dvec2 luxelOffset{0.0};
  glm::dvec2 min{0.0};
  bool quake = true;

  explicit LuxelFrame(const GpuLightmapFragment& g) : min(g.minS, g.minT), quake(quakeGrid(g)) {
    if (quake) return;
    toLuxel = glm::dmat2(glm::dvec2(g.luxelU[0], g.luxelV[0]), glm::dvec2(g.luxelU[1], g.luxelV[1]));
    luxelOffset = glm::dvec2(g.luxelU[2], g.luxelV[2]);
    toTexel = glm::inverse(toLuxel);
    texelOffset = -(toTexel * luxelOffset);
  }
  glm::dvec2 texel(double x, double y) const {
    if (quake) return glm::dvec2((min.x + x) * kLuxelTexels, (min.y + y) * kLuxelTexels);
    return toTexel * (glm::dvec2(x, y) + min) + texelOffset;
  }
  glm::dvec2 luxel(const glm::dvec2& st) const { return toLuxel * st + luxelOffset - min; }
};

// What counts as solid for a sample point (Light_PointInAnySolid): the brushes of the face's own
// model, and those of the world and of the models that cast shadows that are on the same
// lighting channels as the face (the world only for a face on the default channel).
struct SolidTest {
  const RenderScene& rs;
  const std::vector<BrushContents>& contents;
  uint32_t selfEntity;
  uint32_t selfChannels;
  // The space outside a sealed level, solid to the compiler (qbsp fills it); null where the
  // world does not count.
  const VoidTest* voids;

  bool operator()(uint32_t brush) const {
    if (contents[brush] == BrushContents::Solid) return selfChannels == kDefaultChannels;
    if (contents[brush] == BrushContents::Liquid) return false;
    const Brush& b = rs.scene->brushes[brush];
    if (b.faceCount == 0) return false;
    const uint32_t flags = rs.faceFlags[b.firstFace];
    if (flags & (kFaceHidden | kFaceLiquid)) return false;
    return b.entity == selfEntity || (!(flags & kFaceNoShadow) && objectChannels(rs, b.firstFace) == selfChannels);
  }
};

// The point itself lies in front of a face the compiler kept, never in the void; its moved copies may.
// What counts as solid around a sample point of scene face `face`: the world's void only for a face
// on the default channel.
SolidTest solidTestFor(const RenderScene& rs, const std::vector<BrushContents>& contents, const VoidTest& voids, uint32_t face) {
  const uint32_t channels = objectChannels(rs, face);
  return SolidTest{rs, contents, rs.scene->brushes[rs.scene->faces[face].brush].entity, channels,
                   channels == kDefaultChannels ? &voids : nullptr};
}

std::optional<glm::vec3> positionOutOfSolid(const RenderScene& rs, const SolidTest& solid, const dvec3& point) {
  const glm::vec3 p(point);
  if (!rs.tracer.nearInside(p, kSolidMargin, solid)) return p;
  for (int x = -1; x <= 1; x += 2)
    for (int y = -1; y <= 1; y += 2)
      for (int z = -1; z <= 1; z += 2) {
        const dvec3 q = point + kSolidJitter * dvec3(x, y, z);
        if (!rs.tracer.nearInside(glm::vec3(q), kSolidMargin, solid) && !(solid.voids && solid.voids->inVoid(q))) return glm::vec3(q);
      }
  return std::nullopt;
}

// Where the compiler samples the point (x, y) of a fragment's luxel grid (CalcPointNormal,
// PositionSamplePointOnFace): see lightmap_bake.h.
std::optional<glm::vec3> samplePoint(const RenderScene& rs, const SolidTest& solid, const Face& face, const FaceFrame& frame,
                                     const LuxelFrame& grid, const std::vector<dvec3>& polygon, double x, double y) {
  if (!frame.valid) return std::nullopt;
  const dvec3 n = face.plane.normal;
  const glm::dvec2 st = grid.texel(x, y);
  dvec3 p = frame.point(st.x, st.y);
  if (const dvec3 q = nearestOnPolygon(polygon, n, p); q != p) {
    // Off the face: snapped onto its boundary when that is at most a luxel away (in luxels:
    // Quake's 16 texels, or the decoupled grid's own).
    const glm::dvec2 qst(face.frame.s(q), face.frame.t(q));
    const double away = grid.quake ? glm::length(qst - st) / kLuxelTexels : glm::length(grid.luxel(qst) - glm::dvec2(x, y));
    if (away > 1.0) return std::nullopt;
    p = q;
  }
  return positionOutOfSolid(rs, solid, p + n * kSampleLift);
}

// The compiler's store: light × _range, a coloured sum scaled so its brightest channel fits in
// 255 (keeping the hue), truncated to bytes (WriteSingleLightmap's float-to-integer conversion).
uint32_t storedLuxel(const glm::vec3& light, float range) {
  glm::vec3 stored = glm::max(light * range, glm::vec3(0.0f));
  const float peak = std::max({stored.x, stored.y, stored.z});
  if (peak > 255.0f) stored *= 255.0f / peak;
  return packLuxel(glm::floor(stored));
}

int lightSamples(const RenderScene& rs, const LightmapBakeOptions& options) {
  if (options.samples > 0) return options.samples;
  const bool soft = rs.lightKinds.sky || rs.lightKinds.jitter;
  return soft ? kSoftLightSamples : 1;
}

} // namespace

std::optional<glm::vec3> compilerSamplePoint(const RenderScene& rs, const std::vector<BrushContents>& contents, const VoidTest& voids,
                                             uint32_t face, const dvec3& point) {
  return positionOutOfSolid(rs, solidTestFor(rs, contents, voids, face), point);
}

bool faceHasLightmap(const RenderScene& rs, uint32_t face) {
  const uint32_t flags = rs.faceFlags[face];
  if (flags & (kFaceHidden | kFaceSky)) return false;
  if ((flags & kFaceLiquid) && !rs.world.litwater) return false;
  // Mesh triangles (Quake 3 curves) have no compiled lightmap here: lit at each point.
  return !rs.scene->faces[face].winding.empty() && rs.scene->faces[face].brush != kNoBrush;
}

Lightmaps layoutLightmaps(const RenderScene& rs, std::span<const uint32_t> faces, unsigned threads) {
  const Scene& scene = *rs.scene;
  const std::vector<BrushContents> contents = brushContents(scene);
  std::vector<std::vector<std::vector<dvec3>>> pieces(faces.size());
  parallelFor(faces.size(), threads, [&](size_t i) {
    if (faces[i] < scene.faces.size() && faceHasLightmap(rs, faces[i]))
      pieces[i] = compiledFacePolygons(scene, faces[i], contents, rs.worldTree);
  });

  Lightmaps lm;
  lm.faceRanges.assign(scene.faces.size(), glm::uvec2(0));
  uint32_t luxels = 0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const uint32_t face = faces[i];
    if (pieces[i].empty() || lm.faceRanges[face].y > 0) continue;
    const Face& f = scene.faces[face];
    lm.faceRanges[face] = glm::uvec2(uint32_t(lm.fragments.size()), uint32_t(pieces[i].size()));
    for (std::vector<dvec3>& polygon : pieces[i]) {
      const float luxelSize = rs.world.worldUnitsPerLuxel;
      GpuLightmapFragment g = luxelSize > 0.0f ? decoupledGrid(f, polygon, luxelSize) : luxelGrid(f, polygon);
      g.firstLuxel = luxels;
      g.firstEdge = uint32_t(lm.edges.size());
      appendEdges(f, polygon, lm.edges);
      g.edgeCount = uint32_t(lm.edges.size()) - g.firstEdge;
      luxels += g.width * g.height;
      lm.fragments.push_back(g);
      lm.fragmentFace.push_back(face);
      lm.polygons.push_back(std::move(polygon));
    }
  }
  lm.luxels.assign(luxels, 0u);
  lm.displayScale = 1.0f / rs.world.overbrightOne;
  lm.luxelDisplay = rs.world.luxelDisplay;
  return lm;
}

Lightmaps layoutLightmaps(const RenderScene& rs, unsigned threads) {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < rs.scene->faces.size(); ++f)
    if (faceHasLightmap(rs, f)) faces.push_back(f);
  return layoutLightmaps(rs, faces, threads);
}

std::vector<GpuLuxelSample> luxelSamples(const RenderScene& rs, const Lightmaps& lm, int extra, unsigned threads) {
  const Scene& scene = *rs.scene;
  const std::vector<BrushContents> contents = brushContents(scene);
  const VoidTest voids(scene, rs.tracer);
  extra = std::clamp(extra, 1, 4);
  const uint32_t perLuxel = uint32_t(extra * extra);
  std::vector<GpuLuxelSample> samples(lm.luxels.size() * perLuxel);
  parallelFor(lm.fragments.size(), threads, [&](size_t fi) {
    const uint32_t faceIndex = lm.fragmentFace[fi];
    const Face& face = scene.faces[faceIndex];
    const FaceFrame frame(face);
    const GpuLightmapFragment& g = lm.fragments[fi];
    const LuxelFrame grid(g);
    const glm::vec3 faceMinlight = faithfulFaceMinlight(rs, faceIndex);
    // Lit liquids and the compiler's glass take light from both sides (game_rules.h compilerGlass).
    const bool twoSidedFace = (rs.faceFlags[faceIndex] & kFaceLiquid) || compilerGlass(face, gameOf(scene));
    const uint32_t twoSided = twoSidedFace ? kLuxelSampleTwoSided : 0u;
    const SolidTest solid = solidTestFor(rs, contents, voids, faceIndex);
    // The fragment is the compiled face whose bounds the compiler's light cull compares with.
    const uint32_t box = rs.visBoxLights.empty() ? 0u : (uint32_t(fi) + 1u) << kLuxelSampleBoxShift;
    for (uint32_t y = 0; y < g.height; ++y)
      for (uint32_t x = 0; x < g.width; ++x)
        for (int sy = 0; sy < extra; ++sy)
          for (int sx = 0; sx < extra; ++sx) {
            const double ox = -0.5 + (0.5 + sx) / extra, oy = -0.5 + (0.5 + sy) / extra;
            const std::optional<glm::vec3> p = samplePoint(rs, solid, face, frame, grid, lm.polygons[fi], x + ox, y + oy);
            GpuLuxelSample& s = samples[(g.firstLuxel + y * g.width + x) * perLuxel + uint32_t(sy * extra + sx)];
            const glm::vec3 at = p.value_or(glm::vec3(0.0f));
            for (int a = 0; a < 3; ++a) s.position[a] = at[a], s.faceMinlight[a] = faceMinlight[a];
            s.face = faceIndex;
            s.flags = twoSided | (p ? 0u : kLuxelSampleOccluded) | box;
          }
  });
  return samples;
}

LuxelBakeJob luxelBakeJob(const RenderScene& rs, const Lightmaps& lm, const LightmapBakeOptions& options) {
  LuxelBakeJob job;
  const int extra = std::clamp(options.extra, 1, 4);
  job.samples = luxelSamples(rs, lm, extra, options.threads);
  job.samplesPerLuxel = uint32_t(extra * extra);
  job.softSamples = lightSamples(rs, options);
  job.passes = luxelPasses(rs, job.softSamples);
  job.seed = kBakeSeed;
  job.sunTable = rs.sunTable;
  if (!rs.visBoxLights.empty()) {
    for (uint32_t i : rs.visBoxLights) job.boxedLights.push_back(rs.lights[i].origin);
    job.lightBoxes = rs.visBoxes;
    job.receiverBoxes.reserve(lm.polygons.size());
    for (const Winding& polygon : lm.polygons) job.receiverBoxes.push_back(polygonBounds(polygon));
  }
  return job;
}

namespace {

// One luxel's mean light over its sample points (before the store), of the lights of `style`
// (kAllStyles: every light); the floors only in style 0's and in all styles'.
glm::vec3 luxelLight(const RenderScene& rs, const LuxelBakeJob& job, size_t luxel, ShadowCache* cache, int style) {
  const bool floors = style == kAllStyles || style == 0;
  glm::vec3 light(0.0f);
  for (uint32_t k = 0; k < job.samplesPerLuxel; ++k) {
    const uint32_t index = uint32_t(luxel) * job.samplesPerLuxel + k;
    const GpuLuxelSample& s = job.samples[index];
    const glm::vec3 faceMinlight(s.faceMinlight[0], s.faceMinlight[1], s.faceMinlight[2]);
    if (s.flags & kLuxelSampleOccluded) {
      if (floors) light += faithfulLuxelFloor(rs, faceMinlight);
      continue;
    }
    const glm::vec3 p(s.position[0], s.position[1], s.position[2]);
    const glm::vec3 n(rs.scene->faces[s.face].plane.normal);
    LuxelSums sums;
    for (int pass = 0; pass < job.passes; ++pass) {
      Rng rng = pixelRng(index, uint32_t(pass), 0, job.seed);
      faithfulLuxelPass(rs, p, n, s.flags & kLuxelSampleTwoSided, pass, job.softSamples, rng, sums, objectChannels(rs, s.face), cache,
                        job.cull(s), style);
    }
    light += faithfulLuxelLight(rs, sums, job.passes, job.softSamples, faceMinlight, floors);
  }
  return light / float(job.samplesPerLuxel);
}

// The sample points of luxels [begin, end) that cast shadow rays from one side of one face:
// what prepareLuxelGroup takes as a group. Empty when they are not all such. `cull`: the light
// cull of those points where they all share one (job.cull), else none.
std::vector<glm::vec3> shadowGroup(const LuxelBakeJob& job, size_t begin, size_t end, GroupCull& cull) {
  std::vector<glm::vec3> points;
  const GpuLuxelSample& first = job.samples[begin * job.samplesPerLuxel];
  const VisCull shared = job.cull(first);
  cull = {shared.receiver, shared.lights};
  for (size_t i = begin * job.samplesPerLuxel; i < end * job.samplesPerLuxel; ++i) {
    const GpuLuxelSample& s = job.samples[i];
    if (s.face != first.face || (s.flags & kLuxelSampleTwoSided)) return {};
    if (!(s.flags & kLuxelSampleOccluded)) points.emplace_back(s.position[0], s.position[1], s.position[2]);
    const VisCull own = job.cull(s);
    if (own.receiver != shared.receiver || own.lights != shared.lights) cull = {};
  }
  return points;
}

} // namespace

namespace {

// Per scene face, the lowest height along its normal of its sample points (prepareLuxelFace).
std::vector<float> faceNearest(const RenderScene& rs, const LuxelBakeJob& job) {
  std::vector<float> nearest(rs.scene->faces.size(), std::numeric_limits<float>::infinity());
  for (const GpuLuxelSample& s : job.samples) {
    if (s.flags & kLuxelSampleOccluded) continue;
    const glm::vec3 n(rs.scene->faces[s.face].plane.normal);
    nearest[s.face] = std::min(nearest[s.face], glm::dot(n, glm::vec3(s.position[0], s.position[1], s.position[2])));
  }
  return nearest;
}

// The luxels [begin, end) of one run, in fixed groups so that the result does not depend on which
// thread takes which run: with a cache, groups of up to kGroup luxels of one face and one grid cell
// share the lights hidden from or seen by all of them, and a face's light list is made when the
// face begins.
// `store(luxel, cache)` computes and keeps one luxel.
template <class Store> void bakeRun(const RenderScene& rs, const LuxelBakeJob& job, const std::vector<float>& nearest, size_t begin,
                                    size_t end, ShadowCache* cache, const Store& store) {
  constexpr size_t kGroup = 8;
  const auto faceOf = [&](size_t luxel) { return job.samples[luxel * job.samplesPerLuxel].face; };
  const auto cellOf = [&](size_t luxel) {
    const GpuLuxelSample& s = job.samples[luxel * job.samplesPerLuxel];
    return rs.lightGrid.cellLights(glm::vec3(s.position[0], s.position[1], s.position[2]));
  };
  const auto together = [&](size_t a, size_t b) {
    const std::span<const uint32_t> x = cellOf(a), y = cellOf(b);
    return faceOf(a) == faceOf(b) && (x.data() == y.data() || std::equal(x.begin(), x.end(), y.begin(), y.end()));
  };
  uint32_t cacheFace = kNoFace;
  for (size_t group = begin, groupEnd; group < end; group = groupEnd) {
    groupEnd = group + 1;
    while (groupEnd < end && groupEnd - group < kGroup && together(group, groupEnd)) ++groupEnd;
    if (cache) {
      const glm::vec3 n(rs.scene->faces[faceOf(group)].plane.normal);
      if (faceOf(group) != cacheFace) cacheFace = faceOf(group), prepareLuxelFace(rs, n, nearest[cacheFace], *cache);
      GroupCull cull;
      const std::vector<glm::vec3> points = shadowGroup(job, group, groupEnd, cull);
      prepareLuxelGroup(rs, points, n, *cache, cull);
    }
    for (size_t luxel = group; luxel < groupEnd; ++luxel) store(luxel, cache);
  }
}

} // namespace

namespace {

// Every luxel of `job` through `store`, in runs on every core (the same result for any number of threads).
template <class Store>
void bakeLuxels(const RenderScene& rs, const LuxelBakeJob& job, size_t luxels, const LightmapBakeOptions& options, const Store& store) {
  const std::vector<uint8_t> solid = options.shadowCache ? solidBlockers(rs) : std::vector<uint8_t>();
  const std::vector<float> nearest = options.shadowCache ? faceNearest(rs, job) : std::vector<float>();
  // Runs of neighbouring luxels (a face's rows) share a shadow cache.
  constexpr size_t kRun = 256;
  parallelFor((luxels + kRun - 1) / kRun, options.threads, [&](size_t run) {
    std::optional<ShadowCache> cache;
    if (options.shadowCache) cache.emplace(rs, solid);
    bakeRun(rs, job, nearest, run * kRun, std::min(luxels, (run + 1) * kRun), cache ? &*cache : nullptr, store);
  });
}

} // namespace

namespace {

// The job of a bake on the CPU, with the lights' boxes where the RenderScene left them to the GPU.
LuxelBakeJob withLightBoxes(const RenderScene& rs, LuxelBakeJob job, unsigned threads) {
  if (job.lightBoxes.size() != job.boxedLights.size()) job.lightBoxes = computeVisBoxes(rs, threads);
  return job;
}

} // namespace

void bakeLightmaps(const RenderScene& rs, Lightmaps& lm, const LightmapBakeOptions& options) {
  const LuxelBakeJob job = withLightBoxes(rs, luxelBakeJob(rs, lm, options), options.threads);
  bakeLuxels(rs, job, lm.luxels.size(), options, [&](size_t luxel, ShadowCache* cache) {
    lm.luxels[luxel] = storedLuxel(luxelLight(rs, job, luxel, cache, kAllStyles), rs.world.range);
  });
}

std::vector<int> lightStylesOf(const RenderScene& rs) {
  std::vector<int> styles;
  for (const GpuLight& light : rs.lights)
    if (lightStyle(light) != 0) styles.push_back(int(lightStyle(light)));
  std::sort(styles.begin(), styles.end());
  styles.erase(std::unique(styles.begin(), styles.end()), styles.end());
  return styles;
}

StyledLuxels bakeStyledLuxels(const RenderScene& rs, const Lightmaps& lm, const LightmapBakeOptions& options) {
  const LuxelBakeJob job = withLightBoxes(rs, luxelBakeJob(rs, lm, options), options.threads);
  StyledLuxels styled;
  styled.styles.push_back(0);
  for (const int style : lightStylesOf(rs)) styled.styles.push_back(style);
  for (const int style : styled.styles) {
    std::vector<glm::vec3>& light = styled.light.emplace_back(lm.luxels.size());
    bakeLuxels(rs, job, lm.luxels.size(), options,
               [&](size_t luxel, ShadowCache* cache) { light[luxel] = luxelLight(rs, job, luxel, cache, style) * rs.world.range; });
  }
  return styled;
}

std::vector<uint32_t> sumStyles(const StyledLuxels& styled, std::span<const float, 256> weights) {
  std::vector<uint32_t> luxels(styled.light.empty() ? 0 : styled.light[0].size());
  for (size_t i = 0; i < luxels.size(); ++i) {
    glm::vec3 sum(0.0f);
    for (size_t s = 0; s < styled.styles.size(); ++s) sum += weights[size_t(styled.styles[s])] * styled.light[s][i];
    luxels[i] = storedLuxel(sum, 1.0f);
  }
  return luxels;
}

} // namespace bt

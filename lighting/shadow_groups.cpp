#include "lighting/shadow_groups.h"

#include "lighting/faithful.h"
#include "lighting/vis_approx.h"
#include "lighting/visibility.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

// SSE2 (every x86-64) takes the group pass's proofs four lanes at a time: the corners of a
// group's box, the planes of a pyramid. Lane by lane the scalar expressions, so every proof
// answers as the scalar code (kept below for other machines) does, bit for bit.
#if defined(__SSE2__)
#define BT_SSE_GROUP_PROOFS 1
#include <emmintrin.h>
#else
#define BT_SSE_GROUP_PROOFS 0
#endif

namespace bt {

ShadowCache::ShadowCache(const RenderScene& rs, const std::vector<uint8_t>& solidBrushes)
    : solid(&solidBrushes), recent(rs.lights.size() * kRecent, kNoFace), lastSeen(rs.lights.size(), 0), nearLists(rs.lights.size()) {}

namespace {

// The stretch [enter, exit] of the segment c + s (l - c), s in [0, 1], that lies inside brush
// `slot`: Haines' clip in plain arithmetic, no tie rules (trace_scene.h has them for rays).
[[maybe_unused]] bool segmentStretch(const TraceScene& ts, uint32_t slot, const glm::vec3& c, const glm::vec3& l, float& enter,
                                     float& exit) {
  const GpuBrush& b = ts.brushes()[slot];
  const glm::vec3 d = l - c;
  enter = 0.0f, exit = 1.0f;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0f) {
      if (c[a] < b.boundsMin[a] || c[a] > b.boundsMax[a]) return false;
      continue;
    }
    const float t0 = (b.boundsMin[a] - c[a]) / d[a], t1 = (b.boundsMax[a] - c[a]) / d[a];
    enter = std::max(enter, std::min(t0, t1)), exit = std::min(exit, std::max(t0, t1));
  }
  for (uint32_t k = b.firstSide; k < b.firstSide + b.sideCount && enter < exit; ++k) {
    const GpuFace& f = ts.faces()[ts.sides()[k]];
    const glm::vec3 n(f.plane[0], f.plane[1], f.plane[2]);
    const float denom = glm::dot(n, d), num = f.plane[3] - glm::dot(n, c);
    if (denom < 0.0f)
      enter = std::max(enter, num / denom);
    else if (denom > 0.0f)
      exit = std::min(exit, num / denom);
    else if (num < 0.0f)
      return false; // parallel, in front of the plane
  }
  return enter < exit;
}

// A group's ray origins: a box in the frame of their face (u, v in its plane, n off it), 8 corners.
// The corners and the pyramids' base (pyramidTo) are worked out once per group, not per light.
struct OriginBox {
  glm::vec3 u, v, n;
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  Bounds world;
  std::array<glm::vec3, 8> corners;
  float baseHeight = 0.0f;       // the base's height along n, between lo.z and hi.z
  std::array<glm::vec3, 4> base; // its corners, around
  glm::vec3 baseCentre{0.0f};
#if BT_SSE_GROUP_PROOFS
  __m128 cornerLanes[2][3]; // corners 0-3 and 4-7, x, y and z four lanes each
#endif
  glm::vec3 corner(int k) const {
    return u * (k & 1 ? hi.x : lo.x) + v * (k & 2 ? hi.y : lo.y) + n * (k & 4 ? hi.z : lo.z);
  }
};

#if BT_SSE_GROUP_PROOFS
// a ? x : y, lane by lane (a: all ones or all zeros).
inline __m128 select(__m128 a, __m128 x, __m128 y) {
  return _mm_or_ps(_mm_and_ps(a, x), _mm_andnot_ps(a, y));
}

// brushHidesBox's test of four corners c (x, y, z lanes): segmentStretch for each, the same float
// expressions lane by lane (std::max(e, x) is _mm_max_ps(x, e), std::min(e, x) _mm_min_ps(x, e)),
// and the stretch kMargin long at least. The scalar code stops once a segment misses the brush;
// here a lane that misses keeps enter >= exit (enter only grows, exit only shrinks) and fails.
bool stretchesHold(const TraceScene& ts, uint32_t slot, const __m128 (&c)[3], const glm::vec3& l, float margin) {
  const GpuBrush& b = ts.brushes()[slot];
  const __m128 zero = _mm_setzero_ps();
  __m128 d[3], enter = zero, exit = _mm_set1_ps(1.0f), fail = zero;
  for (int a = 0; a < 3; ++a) {
    d[a] = _mm_sub_ps(_mm_set1_ps(l[a]), c[a]);
    const __m128 lo = _mm_set1_ps(b.boundsMin[a]), hi = _mm_set1_ps(b.boundsMax[a]);
    const __m128 flat = _mm_cmpeq_ps(d[a], zero); // the segment lies in the slab or misses it
    fail = _mm_or_ps(fail, _mm_and_ps(flat, _mm_or_ps(_mm_cmplt_ps(c[a], lo), _mm_cmpgt_ps(c[a], hi))));
    const __m128 t0 = _mm_div_ps(_mm_sub_ps(lo, c[a]), d[a]), t1 = _mm_div_ps(_mm_sub_ps(hi, c[a]), d[a]);
    enter = select(flat, enter, _mm_max_ps(_mm_min_ps(t1, t0), enter));
    exit = select(flat, exit, _mm_min_ps(_mm_max_ps(t1, t0), exit));
  }
  for (uint32_t k = b.firstSide; k < b.firstSide + b.sideCount; ++k) {
    if (_mm_movemask_ps(_mm_or_ps(fail, _mm_cmpge_ps(enter, exit))) != 0) return false;
    const GpuFace& f = ts.faces()[ts.sides()[k]];
    const __m128 nx = _mm_set1_ps(f.plane[0]), ny = _mm_set1_ps(f.plane[1]), nz = _mm_set1_ps(f.plane[2]);
    const __m128 denom = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, d[0]), _mm_mul_ps(ny, d[1])), _mm_mul_ps(nz, d[2]));
    const __m128 nc = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, c[0]), _mm_mul_ps(ny, c[1])), _mm_mul_ps(nz, c[2]));
    const __m128 num = _mm_sub_ps(_mm_set1_ps(f.plane[3]), nc), t = _mm_div_ps(num, denom);
    const __m128 entering = _mm_cmplt_ps(denom, zero), leaving = _mm_cmpgt_ps(denom, zero);
    enter = select(entering, _mm_max_ps(t, enter), enter);
    exit = select(leaving, _mm_min_ps(t, exit), exit);
    fail = _mm_or_ps(fail, _mm_and_ps(_mm_cmpeq_ps(denom, zero), _mm_cmplt_ps(num, zero))); // parallel, in front
  }
  const __m128 held = _mm_and_ps(_mm_cmpgt_ps(enter, zero), _mm_cmplt_ps(_mm_add_ps(enter, _mm_set1_ps(margin)), exit));
  return _mm_movemask_ps(_mm_andnot_ps(fail, held)) == 0xf; // enter + margin < exit implies enter < exit
}
#endif

// Whether solid brush `slot` lies clear of the box and holds a stretch of every segment from a
// corner of it to the light (kMargin of the segment at least, far above float rounding).
bool brushHidesBox(const RenderScene& rs, uint32_t slot, const OriginBox& box, const glm::vec3& light) {
  constexpr float kMargin = 1e-3f;
  const GpuBrush& b = rs.tracer.brushes()[slot];
  bool apart = false;
  for (int a = 0; a < 3; ++a) apart = apart || box.world.max[a] < b.boundsMin[a] || box.world.min[a] > b.boundsMax[a];
  if (!apart) return false;
#if BT_SSE_GROUP_PROOFS
  return stretchesHold(rs.tracer, slot, box.cornerLanes[0], light, kMargin) &&
      stretchesHold(rs.tracer, slot, box.cornerLanes[1], light, kMargin);
#else
  for (int k = 0; k < 8; ++k) {
    float enter = 0.0f, exit = 0.0f;
    if (!segmentStretch(rs.tracer, slot, box.corners[size_t(k)], light, enter, exit) || !(enter > 0.0f && enter + kMargin < exit))
      return false;
  }
  return true;
#endif
}

// The pyramid from the box's face (flat: its ray origins on one plane) to a light, as five planes
// (outward normal, offset), and its bounding box.
struct Pyramid {
  std::array<glm::vec4, 5> planes;
  std::array<glm::vec3, 5> vertices; // the base's corners, then the light
  Bounds bounds;
};

Pyramid pyramidTo(const OriginBox& box, const glm::vec3& light) {
  const float z = box.baseHeight;
  const std::array<glm::vec3, 4>& base = box.base;
  const glm::vec3& centre = box.baseCentre;
  Pyramid p;
  for (int k = 0; k < 4; ++k) {
    const glm::vec3& a = base[size_t(k)];
    glm::vec3 m = glm::normalize(glm::cross(base[size_t((k + 1) % 4)] - a, light - a));
    if (glm::dot(m, centre - a) > 0.0f) m = -m;
    p.planes[size_t(k)] = glm::vec4(m, glm::dot(m, a));
    p.vertices[size_t(k)] = a;
    p.bounds.grow(dvec3(a));
  }
  p.planes[4] = glm::vec4(-box.n, -z);
  p.vertices[4] = light;
  p.bounds.grow(dvec3(light));
  return p;
}

// Whether a box lies outside the pyramid by more than `margin` (some plane has it wholly in front).
[[maybe_unused]] bool outside(const Pyramid& p, const float* lo, const float* hi, float margin) {
  for (int a = 0; a < 3; ++a)
    if (lo[a] > p.bounds.max[a] + margin || hi[a] < p.bounds.min[a] - margin) return true;
  for (const glm::vec4& q : p.planes) {
    const glm::vec3 nearest(q.x > 0.0f ? lo[0] : hi[0], q.y > 0.0f ? lo[1] : hi[1], q.z > 0.0f ? lo[2] : hi[2]);
    if (glm::dot(glm::vec3(q), nearest) > q.w + margin) return true;
  }
  return false;
}

// outside(p, lo, hi, margin) for one pyramid and margin, the bounds and planes a register each.
class OutsideTest {
public:
  OutsideTest(const Pyramid& p, float margin) : pyramid_(p), margin_(margin) {
#if BT_SSE_GROUP_PROOFS
    // lo > bounds.max + margin in double holds where lo is above that sum rounded down to float
    // (and hi < bounds.min - margin where hi is below it rounded up): the same comparisons.
    const auto down = [](double x) {
      const float f = float(x);
      return double(f) > x ? std::nextafter(f, -INFINITY) : f;
    };
    const auto up = [](double x) {
      const float f = float(x);
      return double(f) < x ? std::nextafter(f, INFINITY) : f;
    };
    const glm::dvec3 above = p.bounds.max + double(margin), below = p.bounds.min - double(margin);
    boundsMax_ = _mm_setr_ps(down(above.x), down(above.y), down(above.z), INFINITY);
    boundsMin_ = _mm_setr_ps(up(below.x), up(below.y), up(below.z), -INFINITY);
    for (int g = 0; g < 2; ++g) {
      alignas(16) float q[4][4]; // x, y, z, w + margin of up to four planes; a lane without one is never in front
      for (int k = 0; k < 4; ++k) {
        const size_t i = size_t(4 * g + k);
        const glm::vec4 plane = i < p.planes.size() ? p.planes[i] : glm::vec4(0.0f, 0.0f, 0.0f, INFINITY);
        for (int a = 0; a < 3; ++a) q[a][k] = plane[a];
        q[3][k] = i < p.planes.size() ? plane.w + margin : INFINITY;
      }
      for (int a = 0; a < 3; ++a) {
        normal_[g][a] = _mm_load_ps(q[a]);
        positive_[g][a] = _mm_cmpgt_ps(normal_[g][a], _mm_setzero_ps());
      }
      offset_[g] = _mm_load_ps(q[3]);
    }
#endif
  }

  bool operator()(const float* lo, const float* hi) const {
#if BT_SSE_GROUP_PROOFS
    // Each box is a GpuBvhNode's or a GpuBrush's: a fourth word follows lo and hi, masked to 0.
    const __m128 keep = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    const __m128 l = _mm_and_ps(_mm_loadu_ps(lo), keep), h = _mm_and_ps(_mm_loadu_ps(hi), keep);
    if (_mm_movemask_ps(_mm_or_ps(_mm_cmpgt_ps(l, boundsMax_), _mm_cmplt_ps(h, boundsMin_))) != 0) return true;
    const __m128 lx = _mm_shuffle_ps(l, l, 0x00), ly = _mm_shuffle_ps(l, l, 0x55), lz = _mm_shuffle_ps(l, l, 0xaa);
    const __m128 hx = _mm_shuffle_ps(h, h, 0x00), hy = _mm_shuffle_ps(h, h, 0x55), hz = _mm_shuffle_ps(h, h, 0xaa);
    for (int g = 0; g < 2; ++g) {
      const __m128 x = select(positive_[g][0], lx, hx), y = select(positive_[g][1], ly, hy), z = select(positive_[g][2], lz, hz);
      const __m128 dot = _mm_add_ps(_mm_add_ps(_mm_mul_ps(normal_[g][0], x), _mm_mul_ps(normal_[g][1], y)), _mm_mul_ps(normal_[g][2], z));
      if (_mm_movemask_ps(_mm_cmpgt_ps(dot, offset_[g])) != 0) return true;
    }
    return false;
#else
    return outside(pyramid_, lo, hi, margin_);
#endif
  }

private:
  [[maybe_unused]] const Pyramid& pyramid_;
  [[maybe_unused]] float margin_;
#if BT_SSE_GROUP_PROOFS
  __m128 boundsMin_, boundsMax_;
  __m128 normal_[2][3], positive_[2][3], offset_[2]; // planes 0-3, then 4
#endif
};

// Whether the pyramid lies wholly in front of one of brush `slot`'s slanted planes (by more than
// `margin`): the box test above cannot tell a slanted brush's empty corners from the brush.
bool apartFromSlantedPlanes(const TraceScene& ts, uint32_t slot, const Pyramid& p, float margin) {
  const GpuBrush& b = ts.brushes()[slot];
  for (uint32_t k = b.firstSide; k < b.firstSide + b.sideCount; ++k) {
    const GpuFace& f = ts.faces()[ts.sides()[k]];
    const glm::vec3 n(f.plane[0], f.plane[1], f.plane[2]);
    bool allInFront = true;
    for (const glm::vec3& v : p.vertices) allInFront = allInFront && glm::dot(n, v) > f.plane[3] + margin;
    if (allInFront) return true;
  }
  return false;
}

// The brushes that meet the pyramid (or come within `margin` of it), appended to `out`; false
// (and `out` as it was) where there are more than `most`.
bool brushesNear(const TraceScene& ts, const Pyramid& p, float margin, size_t most, std::vector<uint32_t>& out) {
  const OutsideTest outsideOf(p, margin);
  const size_t first = out.size();
  const auto near = [&](const float* lo, const float* hi) { return !outsideOf(lo, hi); };
  const bool tooMany = ts.walkBrushes(near, [&](uint32_t slot) {
    const GpuBrush& b = ts.brushes()[slot];
    if (!near(b.boundsMin, b.boundsMax) || apartFromSlantedPlanes(ts, slot, p, margin)) return false;
    out.push_back(slot);
    return out.size() - first > most;
  });
  if (tooMany) out.resize(first);
  return !tooMany;
}

// The box around the ray origins of sample `points` (offsetRayOrigin, off a face of normal n).
OriginBox originBox(std::span<const glm::vec3> points, const glm::vec3& n) {
  OriginBox box;
  box.n = n;
  box.u = glm::normalize(std::abs(n.x) < 0.6f ? glm::cross(n, glm::vec3(1, 0, 0)) : glm::cross(n, glm::vec3(0, 1, 0)));
  box.v = glm::cross(n, box.u);
  for (const glm::vec3& p : points) {
    const glm::vec3 o = offsetRayOrigin(p, n);
    box.lo = glm::min(box.lo, glm::vec3(glm::dot(box.u, o), glm::dot(box.v, o), glm::dot(n, o)));
    box.hi = glm::max(box.hi, glm::vec3(glm::dot(box.u, o), glm::dot(box.v, o), glm::dot(n, o)));
  }
  box.lo -= glm::vec3(1e-3f), box.hi += glm::vec3(1e-3f); // the frame's own rounding
  for (int k = 0; k < 8; ++k) box.corners[size_t(k)] = box.corner(k), box.world.grow(dvec3(box.corners[size_t(k)]));
#if BT_SSE_GROUP_PROOFS
  for (int h = 0; h < 2; ++h)
    for (int a = 0; a < 3; ++a) {
      const auto& k = box.corners;
      box.cornerLanes[h][a] = _mm_setr_ps(k[size_t(4 * h)][a], k[size_t(4 * h + 1)][a], k[size_t(4 * h + 2)][a], k[size_t(4 * h + 3)][a]);
    }
#endif
  const float z = box.baseHeight = 0.5f * (box.lo.z + box.hi.z);
  box.base = {box.u * box.lo.x + box.v * box.lo.y + box.n * z, box.u * box.hi.x + box.v * box.lo.y + box.n * z,
              box.u * box.hi.x + box.v * box.hi.y + box.n * z, box.u * box.lo.x + box.v * box.hi.y + box.n * z};
  box.baseCentre = 0.25f * (box.base[0] + box.base[1] + box.base[2] + box.base[3]);
  return box;
}

// Whether point light i (no jitter) is hidden from the whole box by the solid brush that last
// blocked a ray toward it: solid brushes block every ray on the default shadow channel.
bool hiddenByRecentBlocker(const RenderScene& rs, const ShadowCache& cache, uint32_t i, const OriginBox& box) {
  const GpuLight& light = rs.lights[i];
  if (light.type != uint32_t(LightType::Point) || light.deviance > 0.0f || light.shadowChannels != kDefaultChannels) return false;
  const uint32_t slot = cache.recent[size_t(i) * ShadowCache::kRecent];
  return slot != kNoFace && (*cache.solid)[slot] && brushHidesBox(rs, slot, box, light.origin);
}

// Behind the plane at height `nearest` along n by far more than rounding: pointLightValue gives 0
// to every point at that height or above.
bool behindAll(const GpuLight& light, const glm::vec3& n, float nearest) {
  return light.type == uint32_t(LightType::Point) && light.deviance <= 0.0f && !(light.flags & kLightFlagBleed) &&
      glm::dot(n, light.origin) < nearest - 1e-2f;
}

} // namespace

void prepareLuxelFace(const RenderScene& rs, const glm::vec3& n, float nearest, ShadowCache& cache) {
  cache.faceLights.clear();
  for (const std::span<const uint32_t> list : {rs.lightGrid.fixedLights(), rs.lightGrid.globalLights()})
    for (uint32_t i : list)
      if (!behindAll(rs.lights[i], n, nearest)) cache.faceLights.push_back(i);
  cache.faceReady = true;
  cache.faceCulledWith = {};
}

void prepareLuxelGroup(const RenderScene& rs, std::span<const glm::vec3> points, const glm::vec3& n, ShadowCache& cache,
                       const GroupCull& cull) {
  cache.groupLights.clear();
  cache.grouped = false;
  cache.groupCulledWith = {};
  cache.nearBrushes.clear();
  ++cache.group; // the previous group's near lists lapse
  if (points.empty()) return;
  const LightGrid& grid = rs.lightGrid;
  const std::span<const uint32_t> cell = grid.cellLights(points.front());
  for (const glm::vec3& p : points) {
    const std::span<const uint32_t> other = grid.cellLights(p);
    if (other.data() != cell.data() && !std::equal(other.begin(), other.end(), cell.begin(), cell.end())) return; // no common list
  }
  const OriginBox box = originBox(points, n);
  float nearest = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : points) nearest = std::min(nearest, glm::dot(n, p));
  // The pyramid's base lies at the middle of the box's height. Flat (the ray origins on one plane
  // to float rounding): the margin covers the rest. Not flat (points moved out of a wall): each
  // segment from the box lies within half the height of one from the base, which the margin adds.
  // Meshes are not in the brush BVH: no pyramid proves their absence.
  const bool provable = rs.tracer.triangleNodes().empty();
  const float height = box.hi.z - box.lo.z;
  constexpr float kNearMargin = 1e-2f;
  const float nearMargin = height <= 4e-3f ? kNearMargin : kNearMargin + 0.5f * height;
  constexpr uint32_t kDropped = ~0u;
  // addFaithfulLight's cull, before the light's random numbers and its shadow rays: a light it
  // culls leaves no trace in the luxel or the cache, so it need not be swept luxel by luxel,
  // nor proved hidden or seen here.
  const auto culled = [&](const GpuLight& light) {
    return cull.receiver && light.visBox && visBoxesApart(cull.lights[light.visBox - 1], *cull.receiver);
  };
  const auto entry = [&](uint32_t i, bool cullTested) -> uint32_t {
    const GpuLight& light = rs.lights[i];
    if (!cullTested && culled(light)) return kDropped;
    if (light.type != uint32_t(LightType::Point) || light.deviance > 0.0f) return i;
    if (behindAll(light, n, nearest) || hiddenByRecentBlocker(rs, cache, i, box)) return kDropped;
    // Tried only where the last ray toward the light was not blocked: a proof that fails costs a
    // traversal, and lights that were blocked a luxel ago mostly are again. More than kMostNear
    // brushes near: the rays cost less walked than tested against each.
    constexpr size_t kMostNear = 16;
    if (provable && cache.lastSeen[i] && glm::dot(n, light.origin) > box.hi.z + 1.0f) {
      const uint32_t first = uint32_t(cache.nearBrushes.size());
      if (!brushesNear(rs.tracer, pyramidTo(box, light.origin), nearMargin, kMostNear, cache.nearBrushes)) return i;
      const uint32_t count = uint32_t(cache.nearBrushes.size()) - first;
      if (count == 0) return i | kSeenByAll;
      cache.nearLists[i] = {cache.group, first, count};
    }
    return i;
  };
  const auto add = [&](std::span<const uint32_t> lights, bool cullTested = false) {
    for (uint32_t i : lights)
      if (const uint32_t e = entry(i, cullTested); e != kDropped) cache.groupLights.push_back(e);
  };
  if (cache.faceReady && cull.receiver) {
    // The face's list culled once for all the groups of one compiled face (one receiver box).
    if (cache.faceCulledWith != cull) {
      cache.faceCulled.clear();
      for (uint32_t i : cache.faceLights)
        if (!culled(rs.lights[i])) cache.faceCulled.push_back(i);
      cache.faceCulledWith = cull;
    }
    add(cache.faceCulled, true);
  } else if (cache.faceReady) {
    add(cache.faceLights);
  } else {
    add(grid.fixedLights());
    add(grid.globalLights());
  }
  add(cell);
  cache.grouped = true;
  cache.groupCulledWith = cull;
}

bool cachedShadowed(const RenderScene& rs, ShadowCache& cache, uint32_t index, const Ray& ray) {
  const uint32_t channels = rs.lights[index].shadowChannels;
  uint32_t* recent = &cache.recent[size_t(index) * ShadowCache::kRecent];
  const RayContext prepared(ray); // once for up to kRecent brush tests and the walk
  bool blocked = false;
  // A solid box on the default channel blocks the ray where the ray enters it (solidBlockers:
  // every face blocks, none has holes): blockedByBrush's answer from the box alone.
  const auto blockedBy = [&](uint32_t slot) {
    if (channels == kDefaultChannels && (*cache.solid)[slot])
      if (const std::optional<bool> enters = rs.tracer.entersBox(prepared, slot)) return *enters;
    return blockedByBrush(rs, ray, prepared, LightingMode::Faithful, slot, channels);
  };
  for (int j = 0; j < ShadowCache::kRecent && recent[j] != kNoFace && !blocked; ++j)
    if (blockedBy(recent[j])) {
      std::rotate(recent, recent + j, recent + j + 1);
      blocked = true;
    }
  // A ray of the group meets no brush but those near it: where none of them is hit, the walk would
  // find nothing; where one is, that hit is the one the walk would find first.
  const ShadowCache::NearList& near = cache.nearLists[index];
  uint32_t found = kNoFace;
  if (!blocked && near.group == cache.group) {
    std::optional<Hit> only;
    int hits = 0;
    for (uint32_t k = near.first; k < near.first + near.count && hits < 2; ++k)
      if (const std::optional<Hit> hit = rs.tracer.intersectBrush(prepared, cache.nearBrushes[k])) only = hit, ++hits;
    blocked = hits < 2 ? occludedAfter(rs, ray, only, LightingMode::Faithful, channels, &found)
                       : occluded(rs, ray, prepared, LightingMode::Faithful, channels, &found);
  } else if (!blocked) {
    blocked = occluded(rs, ray, prepared, LightingMode::Faithful, channels, &found);
  }
  if (found != kNoFace) {
    std::copy_backward(recent, recent + ShadowCache::kRecent - 1, recent + ShadowCache::kRecent);
    recent[0] = found;
  }
  cache.lastSeen[index] = !blocked;
  return blocked;
}

} // namespace bt

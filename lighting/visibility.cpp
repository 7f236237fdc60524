#include "lighting/visibility.h"

#include <array>
#include <optional>
#include <span>

namespace bt {

namespace {

constexpr int kMaxSkips = BT_MAX_SKIPS; // shaders/ray_offsets.glsl

// `channels`: the ray's shadow channels; a face on none of them lets it pass (faithful mode).
bool blocksLight(const RenderScene& rs, uint32_t face, LightingMode mode, uint32_t channels = kDefaultChannels) {
  const uint32_t faceFlags = rs.faceFlags[face];
  if (faceFlags & (kFaceHidden | kFaceLiquid)) return false;
  if (mode == LightingMode::Faithful && ((faceFlags & kFaceNoShadow) || !(objectChannels(rs, face) & channels))) return false;
  return true;
}

// The holes of alpha-tested faces (kFaceMasked), which are holes to every ray as `{` brushes are
// to the compiler.
bool maskedOut(const RenderScene& rs, const Hit& hit, const Ray& ray) {
  const uint32_t flags = rs.faceFlags[hit.face];
  if (!(flags & kFaceMasked)) return false;
  const float a = baseColorAt(rs, hit.face, ray.origin + ray.direction * hit.t).a;
  if (flags & kFaceMaskGt0) return !(a > 0.0f);
  if (flags & kFaceMaskLt128) return !(a < 0.5f);
  return !(a >= 0.5f);
}

// Where a ray goes on past a hit: the far side of a brush it started in, and the holes.
bool passesThrough(const RenderScene& rs, const Hit& hit, const Ray& ray) {
  return hit.inside || maskedOut(rs, hit, ray);
}

// Whether a shadow ray stops at `hit`: a face that blocks it, entered from outside where it has no
// hole; in faithful mode also left, where the brush blocks from inside (RenderScene::blocksFromInside).
bool stopsShadowRay(const RenderScene& rs, const Hit& hit, const Ray& ray, LightingMode mode, uint32_t channels) {
  if (!blocksLight(rs, hit.face, mode, channels)) return false;
  const bool fromInside = mode == LightingMode::Faithful && hit.slot < rs.blocksFromInside.size() && rs.blocksFromInside[hit.slot];
  if (hit.inside && !fromInside) return false; // (a triangle hit is never inside)
  return !maskedOut(rs, hit, ray);
}

} // namespace

glm::vec2 textureUV(const RenderScene& rs, uint32_t face, const glm::vec3& p) {
  const GpuFace& f = gpuFace(rs, face);
  const glm::vec2 st = textureCoordinates(f, p);
  const glm::vec2 size = f.material < rs.materials.size() ? rs.materials[f.material].size : glm::vec2(64.0f);
  return st / size;
}

SurfaceHit traceVisible(const RenderScene& rs, const Ray& ray) {
  Ray r = ray;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return {};
    const uint32_t flags = rs.faceFlags[hit->face];
    bool shown = !passesThrough(rs, *hit, r) && !(flags & kFaceHidden);
    uint32_t face = hit->face;
    const glm::vec3 position = ray.origin + ray.direction * hit->t;
    // A face of a liquid brush that overlaps others: what qbsp's CSG keeps of it, from either
    // side (liquid_csg.h). By the brush's contents: a Quake 2 liquid face without SURF_WARP is
    // drawn as a wall, and merged all the same.
    if (!(flags & kFaceHidden) && rs.liquidCsg.reaches(face)) {
      const LiquidCsg& csg = rs.liquidCsg;
      if (hit->inside)
        shown = csg.drawn(*rs.scene, face, dvec3(position), true);
      else if (shown && !csg.drawn(*rs.scene, face, dvec3(position), false)) {
        const std::optional<uint32_t> kept = csg.keptFaceAt(*rs.scene, rs.faceFlags, face, dvec3(position), dvec3(ray.direction));
        shown = kept.has_value();
        face = kept.value_or(face);
      }
    }
    if (shown) {
      SurfaceHit s;
      s.found = true;
      s.t = hit->t;
      s.face = face;
      s.position = position;
      s.normal = hit->inside ? -faceNormal(rs, face) : faceNormal(rs, face); // the mirrored face, seen from inside
      return s;
    }
    r.tMin = continueRayAfter(hit->t);
  }
  return {};
}

bool occluded(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t channels, uint32_t* blocker) {
  return occluded(rs, ray, RayContext(ray), mode, channels, blocker);
}

bool occluded(const RenderScene& rs, const Ray& ray, const RayContext& prepared, LightingMode mode, uint32_t channels, uint32_t* blocker) {
  // Most shadow rays that are blocked are blocked by any wall on the way: the first hit the
  // traversal meets settles it. Only a hit the ray may pass (a liquid, a hole, a face that casts
  // no shadow) needs the walk from hit to hit in occludedAfter, which gives the same answer.
  return occludedAfter(rs, ray, rs.tracer.anyHit(prepared), mode, channels, blocker);
}

bool occludedAfter(const RenderScene& rs, const Ray& ray, const std::optional<Hit>& any, LightingMode mode, uint32_t channels,
                   uint32_t* blocker) {
  const auto blockedBy = [&](const Hit& hit) {
    if (blocker && hit.brush != kNoBrush) *blocker = hit.slot;
    return true;
  };
  if (!any) return false;
  if (stopsShadowRay(rs, *any, ray, mode, channels)) return blockedBy(*any);
  Ray r = ray;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return false;
    if (stopsShadowRay(rs, *hit, r, mode, channels)) return blockedBy(*hit);
    r.tMin = continueRayAfter(hit->t);
  }
  return true;
}

bool blockedByBrush(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t slot, uint32_t channels) {
  return blockedByBrush(rs, ray, RayContext(ray), mode, slot, channels);
}

bool blockedByBrush(const RenderScene& rs, const Ray& ray, const RayContext& prepared, LightingMode mode, uint32_t slot,
                    uint32_t channels) {
  const std::optional<Hit> hit = rs.tracer.intersectBrush(prepared, slot);
  return hit && !hit->inside && blocksLight(rs, hit->face, mode, channels) && !passesThrough(rs, *hit, ray);
}

namespace {

// reachesSky, the ray's first closest hit given.
bool reachesSkyFrom(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t skyMaterial, std::optional<Hit> hit) {
  Ray r = ray;
  for (int i = 0; i < kMaxSkips; ++i) {
    if (i > 0) hit = rs.tracer.closestHit(r);
    if (!hit) return skyMaterial == 0; // left the level: nothing to stop the sun, unless it needs a texture
    const uint32_t flags = rs.faceFlags[hit->face];
    const bool through = passesThrough(rs, *hit, r);
    if (!through && (flags & kFaceSky)) return skyMaterial == 0 || gpuFace(rs, hit->face).material + 1 == skyMaterial;
    if (!through && blocksLight(rs, hit->face, mode)) return false;
    r.tMin = continueRayAfter(hit->t);
  }
  return false;
}

} // namespace

bool reachesSky(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t skyMaterial) {
  return reachesSkyFrom(rs, ray, mode, skyMaterial, rs.tracer.closestHit(ray));
}

uint64_t reachSky(const RenderScene& rs, std::span<const Ray> rays, LightingMode mode, uint32_t skyMaterial) {
  std::array<std::optional<Hit>, TraceScene::kPacketRays> hits;
  rs.tracer.closestHits(rays, std::span(hits).first(rays.size()));
  uint64_t reached = 0;
  for (size_t i = 0; i < rays.size(); ++i)
    if (reachesSkyFrom(rs, rays[i], mode, skyMaterial, hits[i])) reached |= uint64_t(1) << i;
  return reached;
}

std::vector<uint8_t> solidBlockers(const RenderScene& rs) {
  const std::span<const GpuBrush> brushes = rs.tracer.brushes();
  const std::span<const uint32_t> sides = rs.tracer.sides();
  std::vector<uint8_t> solid(brushes.size(), 0);
  const auto blocks = [&](uint32_t face) { return blocksLight(rs, face, LightingMode::Faithful) && !(rs.faceFlags[face] & kFaceMasked); };
  for (size_t b = 0; b < brushes.size(); ++b) {
    const GpuBrush& brush = brushes[b];
    bool all = true;
    for (uint32_t face : brush.axialFace) all = all && (face == kNoFace || blocks(face));
    for (uint32_t k = brush.firstSide; all && k < brush.firstSide + brush.sideCount; ++k) all = blocks(sides[k]);
    solid[b] = all;
  }
  return solid;
}

glm::vec4 baseColorAt(const RenderScene& rs, uint32_t face, const glm::vec3& p) {
  const uint32_t m = gpuFace(rs, face).material;
  if (m >= rs.scene->materials.size() || rs.scene->materials[m].baseColor.empty()) return glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  const glm::vec2 uv = textureUV(rs, face, p);
  return sampleBilinearRepeat(rs.scene->materials[m].baseColor, uv.x, uv.y);
}

glm::vec3 emissiveAt(const RenderScene& rs, uint32_t face, const glm::vec3& p) {
  const uint32_t m = gpuFace(rs, face).material;
  if (m >= rs.scene->materials.size() || !(rs.materials[m].flags & kMaterialEmissive)) return glm::vec3(0.0f);
  const glm::vec2 uv = textureUV(rs, face, p);
  return glm::vec3(sampleBilinearRepeat(rs.scene->materials[m].emissive, uv.x, uv.y));
}

namespace {

// The first face a ray stops at within `depth`: one that blocks faithful light, or with
// `skyStops` a sky face (else sky ends the ray at `depth`, as for dirt).
float stopDistance(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float depth, bool skyStops) {
  Ray r{origin, 0.0f, dir, depth};
  float lastT = depth;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return depth;
    const uint32_t flags = rs.faceFlags[hit->face];
    const bool through = passesThrough(rs, *hit, r);
    if (!through && (flags & kFaceSky)) return skyStops ? std::min(hit->t, depth) : depth;
    if (!through && blocksLight(rs, hit->face, LightingMode::Faithful)) return std::min(hit->t, depth);
    lastT = hit->t;
    r.tMin = continueRayAfter(hit->t);
  }
  return lastT; // too many faces to pass: blocked where the search stopped
}

} // namespace

float blockedDistance(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float depth) {
  return stopDistance(rs, origin, dir, depth, false);
}

float faceDistance(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float depth) {
  return stopDistance(rs, origin, dir, depth, true);
}

} // namespace bt

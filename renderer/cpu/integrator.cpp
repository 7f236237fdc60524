#include "renderer/cpu/integrator.h"

#include "renderer/cpu/color.h"
#include "renderer/cpu/faithful.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace bt {

namespace {

// Rays leave surfaces this far along the normal: a few float ulps at Quake's 32k extents,
// well under a texel.
constexpr float kSurfaceOffset = 0.03f;
constexpr int kMaxSkips = 64; // hidden faces/back faces skipped along one ray before giving up

glm::vec3 offsetPoint(const glm::vec3& p, const glm::vec3& n) {
  return p + n * kSurfaceOffset;
}

glm::vec2 textureUV(const RenderScene& rs, uint32_t face, const glm::vec3& p) {
  const GpuFace& f = gpuFace(rs, face);
  const glm::vec2 st = textureCoordinates(f, p);
  const glm::vec2 size = f.material < rs.materials.size() ? rs.materials[f.material].size : glm::vec2(64.0f);
  return st / size;
}

bool blocksLight(uint32_t faceFlags, LightingMode mode) {
  if (faceFlags & (kFaceHidden | kFaceLiquid)) return false;
  if (mode == LightingMode::Faithful && (faceFlags & kFaceNoShadow)) return false;
  return true;
}

// Where a ray goes on past a hit: the far side of a brush it started in, and the holes of
// alpha-tested faces (kFaceMasked), which are holes to every ray as `{` brushes are to the compiler.
bool passesThrough(const RenderScene& rs, const Hit& hit, const Ray& ray) {
  if (hit.inside) return true;
  const uint32_t flags = rs.faceFlags[hit.face];
  if (!(flags & kFaceMasked)) return false;
  const float a = baseColorAt(rs, hit.face, ray.origin + ray.direction * hit.t).a;
  if (flags & kFaceMaskGt0) return !(a > 0.0f);
  if (flags & kFaceMaskLt128) return !(a < 0.5f);
  return !(a >= 0.5f);
}

// The emitter triangle whose cdf interval holds u (binary search, GLSL-friendly loop).
uint32_t pickEmitter(const RenderScene& rs, float u) {
  uint32_t lo = 0, hi = uint32_t(rs.emitters.size()) - 1;
  while (lo < hi) {
    const uint32_t mid = (lo + hi) / 2;
    if (rs.emitters[mid].cdf < u)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

// A point light's position for one sample: one of ericw-tools' `_samples` jittered copies,
// uniform in the cube of half-size `_deviance` around the light.
glm::vec3 jitteredOrigin(const GpuLight& light, Rng& rng) {
  if (light.deviance <= 0.0f) return light.origin;
  const glm::vec3 u{rng.next(), rng.next(), rng.next()}; // braces: drawn left to right, as in GLSL
  return light.origin + light.deviance * (2.0f * u - 1.0f);
}

// Domes sit in the light grid's fixed list (suns, domes, local minlights): a bounce ray that
// reaches the sky looks at a handful of lights, not at every light of the level.
glm::vec3 skyDomeRadiance(const RenderScene& rs, const glm::vec3& dir) {
  glm::vec3 l(0.0f);
  for (uint32_t index : rs.lightGrid.fixedLights()) {
    const GpuLight& light = rs.lights[index];
    if (light.type == uint32_t(LightType::Dome) && dir.z * light.direction.z > 0.0f)
      l += light.color * light.value * rs.world.range * kPhysicalSunScale / kPi;
  }
  return l;
}

} // namespace

SurfaceHit traceVisible(const RenderScene& rs, const Ray& ray) {
  Ray r = ray;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return {};
    if (!passesThrough(rs, *hit, r) && !(rs.faceFlags[hit->face] & kFaceHidden)) {
      SurfaceHit s;
      s.found = true;
      s.t = hit->t;
      s.face = hit->face;
      s.position = ray.origin + ray.direction * hit->t;
      s.normal = faceNormal(rs, hit->face);
      return s;
    }
    r.tMin = hit->t + 1e-3f;
  }
  return {};
}

bool occluded(const RenderScene& rs, const Ray& ray, LightingMode mode) {
  // Most shadow rays that are blocked are blocked by any wall on the way: the first hit the
  // traversal meets settles it. Only a hit the ray may pass (a liquid, a hole, a face that casts
  // no shadow) needs the walk from hit to hit below, which gives the same answer.
  const std::optional<Hit> any = rs.tracer.anyHit(ray);
  if (!any) return false;
  if (blocksLight(rs.faceFlags[any->face], mode) && !passesThrough(rs, *any, ray)) return true;
  Ray r = ray;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return false;
    if (blocksLight(rs.faceFlags[hit->face], mode) && !passesThrough(rs, *hit, r)) return true;
    r.tMin = hit->t + 1e-3f;
  }
  return true;
}

bool reachesSky(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t skyMaterial) {
  Ray r = ray;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return skyMaterial == 0; // left the level: nothing to stop the sun, unless it needs a texture
    const uint32_t flags = rs.faceFlags[hit->face];
    const bool through = passesThrough(rs, *hit, r);
    if (!through && (flags & kFaceSky)) return skyMaterial == 0 || gpuFace(rs, hit->face).material + 1 == skyMaterial;
    if (!through && blocksLight(flags, mode)) return false;
    r.tMin = hit->t + 1e-3f;
  }
  return false;
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

// Normal maps (Material::normal, the importer's `_norm`/`_normal` companions) follow the
// convention of DarkPlaces, the engine those companion textures come from: tangent space, red
// along +s (right in the image), green up in the image, blue along the face normal; a texel t
// (0..1, filtered like the base colour) holds 2 t - 1. Up in the image is -t: rows are stored
// top to bottom and t grows with the row (DarkPlaces' Mod_BuildBumpVectors likewise points its
// tvector against t). A texel with no direction gives (0, 0, 0).
glm::vec3 decodeNormalTexel(const glm::vec3& texel) {
  const glm::vec3 n = 2.0f * texel - 1.0f;
  const float length2 = glm::dot(n, n);
  return length2 > 1e-8f ? n / std::sqrt(length2) : glm::vec3(0.0f);
}

// `local` (a decoded texel) in world space on a face with normal n and texture axes s and t
// (TextureFrame's tangent and bitangent: Quake's axes are neither unit nor orthogonal). The
// frame keeps s's direction, takes the second axis orthogonal to it, and keeps the handedness
// the axes have on the face, so a mirrored texture (a negative scale) mirrors its normal map.
// Where s runs along the normal there is no frame, and the face normal stays.
glm::vec3 normalMapToWorld(const glm::vec3& local, const glm::vec3& s, const glm::vec3& t, const glm::vec3& n) {
  glm::vec3 x = s - n * glm::dot(n, s);
  const float length2 = glm::dot(x, x);
  if (!(length2 > 1e-6f * glm::dot(s, s))) return n;
  x /= std::sqrt(length2);
  // (s, -t, n) is right-handed for a texture seen unmirrored from the front of its face.
  const float handedness = glm::dot(glm::cross(s, t), n) > 0.0f ? -1.0f : 1.0f;
  const glm::vec3 y = handedness * glm::cross(n, x);
  return glm::normalize(x * local.x + y * local.y + n * local.z);
}

// A normal map may tilt the shading normal so far that wo falls behind it, or that light
// reflected about it leaves into the face. Iray's fix (Keller et al. 2017, "The Iray Light
// Transport Simulation and Rendering System", shading normals): where wo's mirror direction
// about ns comes within kHorizonMargin of the face's plane or below, it is lifted to that
// height and ns becomes the half vector of wo and the lifted direction. ns then faces wo, stays
// in front of the face, and is left unchanged wherever the map tilts it reasonably.
constexpr float kHorizonMargin = 0.01f;

glm::vec3 keepAboveHorizon(const glm::vec3& ns, const glm::vec3& ng, const glm::vec3& wo) {
  const glm::vec3 mirror = 2.0f * glm::dot(ns, wo) * ns - wo;
  const float height = glm::dot(mirror, ng);
  if (height >= kHorizonMargin) return ns;
  const glm::vec3 lifted = glm::normalize(mirror + ng * (kHorizonMargin - height));
  const glm::vec3 halfway = wo + lifted;
  const float length2 = glm::dot(halfway, halfway);
  return length2 > 1e-12f ? halfway / std::sqrt(length2) : ng;
}

} // namespace

glm::vec3 shadingNormal(const RenderScene& rs, const SurfaceHit& hit, const glm::vec3& wo) {
  const GpuFace& f = gpuFace(rs, hit.face);
  if (f.material >= rs.scene->materials.size() || rs.scene->materials[f.material].normal.empty()) return hit.normal;
  const glm::vec2 uv = textureUV(rs, hit.face, hit.position);
  const glm::vec3 texel(sampleBilinearRepeat(rs.scene->materials[f.material].normal, uv.x, uv.y));
  const glm::vec3 local = decodeNormalTexel(texel);
  if (local == glm::vec3(0.0f)) return hit.normal;
  const glm::vec3 s(f.tangent[0], f.tangent[1], f.tangent[2]), t(f.bitangent[0], f.bitangent[1], f.bitangent[2]);
  return keepAboveHorizon(normalMapToWorld(local, s, t, hit.normal), hit.normal, wo);
}

namespace {

// How far a dirt ray gets: the first face that blocks light, or `depth` when it meets none (or
// the sky: ericw-tools counts only solid hits) within it.
float dirtRayDistance(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float depth) {
  Ray r{origin, 0.0f, dir, depth};
  float lastT = depth;
  for (int i = 0; i < kMaxSkips; ++i) {
    const std::optional<Hit> hit = rs.tracer.closestHit(r);
    if (!hit) return depth;
    const uint32_t flags = rs.faceFlags[hit->face];
    const bool through = passesThrough(rs, *hit, r);
    if (!through && (flags & kFaceSky)) return depth;
    if (!through && blocksLight(flags, LightingMode::Faithful)) return std::min(hit->t, depth);
    lastT = hit->t;
    r.tMin = hit->t + 1e-3f;
  }
  return lastT; // too many faces to pass: blocked where the search stopped
}

// Faithful dirt occlusion at p (0 open .. 1 enclosed), or 0 when the level uses no dirt.
float faithfulOcclusion(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng) {
  const DirtSettings& dirt = rs.world.dirtSettings;
  if (!dirt.enabled) return 0.0f;
  const glm::vec3 origin = p + n * faithful::kDirtSampleLift;
  const float cone = glm::radians(dirt.angle);
  float sum = 0.0f;
  for (int i = 0; i < faithful::kDirtRays; ++i) {
    glm::vec3 v;
    if (dirt.mode == 1) {
      const float u0 = rng.next(), u1 = rng.next(); // in this order, as the GL tracer draws them
      v = faithful::dirtRandomVector(u0, u1, cone);
    } else {
      v = faithful::dirtPatternVector(i, cone);
    }
    sum += dirtRayDistance(rs, origin, faithful::dirtRayDirection(n, v), dirt.depth);
  }
  return faithful::dirtOcclusion(sum, faithful::kDirtRays, dirt.depth);
}

// A faithful receiver: a surface point, its face's normal, and whether light from behind counts.
struct Receiver {
  glm::vec3 p;
  glm::vec3 n;
  bool twoSided; // a lit liquid: ericw-tools lights it from above and below (ltface.cc "twosided")
};

// The normal the receiver turns to light arriving from `toLight`: a two-sided receiver faces
// every light, so the angle term takes |cos| and the shadow ray leaves from the light's side.
glm::vec3 facingNormal(const Receiver& r, const glm::vec3& toLight) {
  return r.twoSided && glm::dot(r.n, toLight) < 0.0f ? -r.n : r.n;
}

// Faithful mode: one light's share of the light sum at the receiver, dimmed by the dirt
// `occlusion` there. Local-minlight lights raise `localMin` instead: they are a floor, not a sum.
void addFaithfulLight(const RenderScene& rs, const GpuLight& light, const Receiver& r, float occlusion, Rng& rng, glm::vec3& sum,
                      glm::vec3& localMin) {
  if (light.type == uint32_t(LightType::Point)) {
    const glm::vec3 pos = jitteredOrigin(light, rng);
    const glm::vec3 d = pos - r.p;
    const float dist = glm::length(d);
    if (dist <= 0.0f) return;
    const glm::vec3 toLight = d / dist;
    const glm::vec3 n = facingNormal(r, toLight);
    const float value =
        faithful::pointLightValue(light, n, toLight, dist, rs.world.scaledist) * faithful::lightDirtFactor(light, occlusion, dist);
    if (value == 0.0f) return;
    const glm::vec3 origin = offsetPoint(r.p, n);
    const glm::vec3 toLightFromOrigin = pos - origin;
    const float len = glm::length(toLightFromOrigin);
    if (occluded(rs, Ray{origin, 0.0f, toLightFromOrigin / len, len}, LightingMode::Faithful)) return;
    if (light.formula == uint32_t(LightFormula::LocalMin))
      localMin = glm::max(localMin, value * light.color);
    else
      sum += value * light.color;
  } else if (light.type == uint32_t(LightType::Sun)) {
    glm::vec3 toSun = -light.direction;
    if (light.deviance > 0.0f) toSun = sampleCone(toSun, light.deviance, rng.next2());
    GpuLight jittered = light;
    jittered.direction = -toSun;
    const glm::vec3 n = facingNormal(r, toSun);
    const float value = faithful::sunValue(jittered, n) * faithful::lightDirtFactor(light, occlusion, 0.0f);
    if (value == 0.0f) return;
    if (!reachesSky(rs, Ray{offsetPoint(r.p, n), 0.0f, toSun, std::numeric_limits<float>::infinity()}, LightingMode::Faithful,
                    light.skyMaterial))
      return;
    sum += value * light.color;
  } else if (light.type == uint32_t(LightType::Dome)) {
    // One direction of the dome per sample, uniform over its hemisphere: the mean over the
    // dome's directions of value * angle term, for those that reach the sky.
    const glm::vec3 dir = sampleUniformHemisphere(light.direction, rng.next2());
    const glm::vec3 n = facingNormal(r, dir);
    const float cosIncidence = glm::dot(dir, n);
    if (cosIncidence <= 0.0f) return;
    if (!reachesSky(rs, Ray{offsetPoint(r.p, n), 0.0f, dir, std::numeric_limits<float>::infinity()}, LightingMode::Faithful)) return;
    sum +=
        light.value * faithful::angleTerm(cosIncidence, light.anglescale) * faithful::lightDirtFactor(light, occlusion, 0.0f) * light.color;
  }
}

// A bounce light's unshadowed share at the receiver (its 0.01 gate applied; dirt comes after
// the draw, the same factor for every bounce light), and the side of the receiver it lights.
// weight, its brightest channel, is what the draw goes by: 0 where it adds nothing.
struct BounceShare {
  glm::vec3 rgb{0.0f};
  float weight = 0.0f;
  float dist = 0.0f;
  glm::vec3 n{0.0f};
};

// Whether the receiver clearly gets nothing of a bounce light `d` away (d from the receiver to
// it): it lies behind the light's face, or the light behind a one-sided receiver, at an angle
// whose cosine is above 1e-4, far beyond float rounding, so pointLightValue would say 0 too. No
// square root: the draw's sweep tests a cell's hundreds of bounce lights at every hit.
bool clearlyUnlit(const GpuLight& light, const Receiver& r, const glm::vec3& d) {
  constexpr float kCos2 = 1e-8f; // (1e-4)^2
  const float d2 = glm::dot(d, d);
  const float away = glm::dot(light.direction, d); // > 0: the receiver is behind the light's face
  if (away > 0.0f && away * away > kCos2 * d2) return true;
  const float facing = glm::dot(r.n, d);
  return !r.twoSided && facing < 0.0f && facing * facing > kCos2 * d2;
}

BounceShare bounceShare(const RenderScene& rs, const GpuLight& light, const Receiver& r) {
  BounceShare s;
  const glm::vec3 d = light.origin - r.p;
  if (clearlyUnlit(light, r, d)) return s;
  s.dist = glm::length(d);
  if (!(s.dist > 0.0f)) return s;
  const glm::vec3 toLight = d / s.dist;
  s.n = facingNormal(r, toLight);
  const float value = faithful::pointLightValue(light, s.n, toLight, s.dist, rs.world.scaledist);
  if (!(value > 0.0f)) return s;
  s.rgb = value * light.color;
  s.weight = std::max(faithful::maxChannel(s.rgb), 0.0f);
  return s;
}

// An unbiased estimate of the sum of `count` bounce lights (point lights without jitter;
// lightAt(i) is the i-th) at the receiver, with at most `shadowRays` shadow rays: the lights'
// shares laid end to end on [0, total), one target drawn in each of `shadowRays` equal strata of
// it (stratified: where every light is visible and of one hue the estimate is exact), and each
// light a target falls on counts share x total / (weight x shadowRays) per target where it is
// visible. A light that several targets fall on is traced once. Two sweeps over the lights (the
// total, then the picks in order) and no list, so the GL tracer does the same in fixed space
// (pathtrace.comp faithfulBounceRay), drawing the same numbers: one per stratum, in order, after
// those of the lights before. Here the second sweep reads the weights the first one kept (the
// sweep over a cell's hundreds of lights is most of the cost). `shadowRaysCast`, when given,
// counts the rays (tests).
template <class LightAt> glm::vec3 sampledBounceSum(const RenderScene& rs, size_t count, const LightAt& lightAt, const Receiver& r,
                                                    float occlusion, Rng& rng, size_t shadowRays, int* shadowRaysCast = nullptr) {
  std::vector<float> weights(count);
  float total = 0.0f;
  size_t last = count; // the last light with a share: rounding may leave targets past the others
  for (size_t i = 0; i < count; ++i) {
    weights[i] = bounceShare(rs, lightAt(i), r).weight;
    if (weights[i] > 0.0f) total += weights[i], last = i;
  }
  if (last == count || shadowRays == 0) return glm::vec3(0.0f);
  const float strata = float(shadowRays);
  glm::vec3 sum(0.0f);
  float cumulative = 0.0f;
  size_t drawn = 0;
  float target = rng.next() / strata * total;
  for (size_t i = 0; i <= last && drawn < shadowRays; ++i) {
    if (!(weights[i] > 0.0f)) continue;
    cumulative += weights[i];
    int picks = 0;
    while (drawn < shadowRays && (target < cumulative || i == last)) {
      ++picks, ++drawn;
      if (drawn < shadowRays) target = (float(drawn) + rng.next()) / strata * total;
    }
    if (picks == 0) continue;
    if (shadowRaysCast) ++*shadowRaysCast;
    const GpuLight& light = lightAt(i);
    const BounceShare s = bounceShare(rs, light, r); // its weight is weights[i]: the same computation
    const glm::vec3 origin = offsetPoint(r.p, s.n);
    const glm::vec3 toLight = light.origin - origin;
    const float len = glm::length(toLight);
    if (occluded(rs, Ray{origin, 0.0f, toLight / len, len}, LightingMode::Faithful)) continue;
    sum += s.rgb * faithful::lightDirtFactor(light, occlusion, s.dist) * (float(picks) * total / (s.weight * strata));
  }
  return sum;
}

// worldspawn minlight, a radiosity template's face minlight and delay-4 lights are floors under
// the sum, not terms of it; with `_minlight_dirt`, dirt dims both minlights (LightFace_Min).
glm::vec3 applyFloors(const RenderScene& rs, const glm::vec3& sum, const glm::vec3& localMin, const glm::vec3& faceMinlight,
                      float occlusion) {
  const DirtSettings& dirt = rs.world.dirtSettings;
  const float minlightDirt = dirt.minlight ? 1.0f - faithful::dirtAmount(occlusion, dirt.gain, dirt.scale) : 1.0f;
  return glm::max(glm::max(sum, localMin), glm::max(rs.world.minlight, faceMinlight) * minlightDirt);
}

// Which lights a faithful sum takes: all of them with the floors (what a surface shows), or what
// ericw-tools' bounce re-emits (ltface.cc: the lights that add to a lightmap's bounce_color in the
// direct pass): positive lights, no local minlight, style 0 unless `_bouncestyled`, no floors.
enum class FaithfulLights { Shown, BounceSources };

bool feedsBounce(const GpuLight& light, const WorldLighting& world) {
  if (light.value <= 0.0f || light.formula == uint32_t(LightFormula::Bounce)) return false;
  if (light.type == uint32_t(LightType::Point) && light.formula == uint32_t(LightFormula::LocalMin)) return false;
  return world.bouncestyled || lightStyle(light) == 0;
}

// Where the light sum comes from: every light of the level (the reference), the grid's lists
// for p, or those lists with the cell's bounce lights drawn (sampledBounceSum) when there are
// more than kBounceShadowRays of them.
enum class LightSource { All, Grid, GridSampledBounce };

// The faithful light sum at p: the dirt occlusion first, then the lights, then the floors.
glm::vec3 faithfulSum(const RenderScene& rs, LightSource source, const Receiver& r, const glm::vec3& faceMinlight, Rng& rng,
                      FaithfulLights which = FaithfulLights::Shown, int* bounceShadowRays = nullptr,
                      std::optional<float> knownOcclusion = std::nullopt) {
  const float occlusion = knownOcclusion ? *knownOcclusion : faithfulOcclusion(rs, r.p, r.n, rng);
  glm::vec3 sum(0.0f), localMin(0.0f);
  auto add = [&](const GpuLight& light) {
    if (which == FaithfulLights::BounceSources && !feedsBounce(light, rs.world)) return;
    if (bounceShadowRays && light.formula == uint32_t(LightFormula::Bounce)) ++*bounceShadowRays; // at most
    addFaithfulLight(rs, light, r, occlusion, rng, sum, localMin);
  };
  if (source == LightSource::All) {
    for (const GpuLight& light : rs.lights) add(light);
  } else {
    const LightGrid& grid = rs.lightGrid;
    for (uint32_t i : grid.fixedLights()) add(rs.lights[i]);
    for (uint32_t i : grid.globalLights()) add(rs.lights[i]);
    const std::span<const uint32_t> cell = grid.cellLights(r.p);
    const size_t bounceCount = trailingBounceLights(rs.lights, cell); // they come last in a cell
    const bool drawBounce = source == LightSource::GridSampledBounce && bounceCount > kBounceShadowRays;
    for (uint32_t i : drawBounce ? cell.first(cell.size() - bounceCount) : cell) add(rs.lights[i]);
    if (drawBounce) {
      const std::span<const uint32_t> bounce = cell.last(bounceCount);
      sum += sampledBounceSum(
          rs, bounce.size(), [&](size_t k) -> const GpuLight& { return rs.lights[bounce[k]]; }, r, occlusion, rng, kBounceShadowRays,
          bounceShadowRays);
    }
  }
  if (which == FaithfulLights::BounceSources) return sum;
  return applyFloors(rs, sum, localMin, faceMinlight, occlusion);
}

} // namespace

float faithfulDirtOcclusion(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng) {
  return faithfulOcclusion(rs, p, n, rng);
}

glm::vec3 faithfulLightAt(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided) {
  return faithfulSum(rs, LightSource::All, Receiver{p, n, twoSided}, glm::vec3(0.0f), rng);
}

glm::vec3 faithfulLightFromGrid(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided) {
  return faithfulSum(rs, LightSource::Grid, Receiver{p, n, twoSided}, glm::vec3(0.0f), rng);
}

glm::vec3 faithfulLightSampled(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided,
                               int* bounceShadowRays) {
  return faithfulSum(rs, LightSource::GridSampledBounce, Receiver{p, n, twoSided}, glm::vec3(0.0f), rng, FaithfulLights::Shown,
                     bounceShadowRays);
}

glm::vec3 faithfulBounceSourceLight(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided,
                                    std::optional<float> occlusion) {
  return faithfulSum(rs, LightSource::Grid, Receiver{p, n, twoSided}, glm::vec3(0.0f), rng, FaithfulLights::BounceSources, nullptr,
                     occlusion);
}

glm::vec3 faithfulLightFrom(const RenderScene& rs, std::span<const GpuLight> lights, const glm::vec3& p, const glm::vec3& n, Rng& rng,
                            bool twoSided) {
  const Receiver r{p, n, twoSided};
  const float occlusion = faithfulOcclusion(rs, p, n, rng);
  glm::vec3 sum(0.0f), localMin(0.0f);
  for (const GpuLight& light : lights) addFaithfulLight(rs, light, r, occlusion, rng, sum, localMin);
  return sum;
}

glm::vec3 faithfulLightFromSampled(const RenderScene& rs, std::span<const GpuLight> lights, const glm::vec3& p, const glm::vec3& n,
                                   Rng& rng, bool twoSided, size_t maxShadowRays) {
  if (lights.size() <= maxShadowRays) return faithfulLightFrom(rs, lights, p, n, rng, twoSided);
  const Receiver r{p, n, twoSided};
  const float occlusion = faithfulOcclusion(rs, p, n, rng);
  return sampledBounceSum(
      rs, lights.size(), [&](size_t i) -> const GpuLight& { return lights[i]; }, r, occlusion, rng, maxShadowRays);
}

glm::vec3 faithfulLightFromSampled(const RenderScene& rs, std::span<const GpuLight> lights, std::span<const uint32_t> candidates,
                                   const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided, size_t maxShadowRays,
                                   std::optional<float> knownOcclusion) {
  const Receiver r{p, n, twoSided};
  const float occlusion = knownOcclusion ? *knownOcclusion : faithfulOcclusion(rs, p, n, rng);
  // Whether to draw goes by every light, as above: a few candidates still take the draw.
  if (lights.size() <= maxShadowRays) {
    glm::vec3 sum(0.0f), localMin(0.0f);
    for (const GpuLight& light : lights) addFaithfulLight(rs, light, r, occlusion, rng, sum, localMin);
    return sum;
  }
  return sampledBounceSum(
      rs, candidates.size(), [&](size_t i) -> const GpuLight& { return lights[candidates[i]]; }, r, occlusion, rng, maxShadowRays);
}

namespace {

const std::vector<glm::vec3>& skyDome() {
  static const std::vector<glm::vec3> dome = faithful::skyDomeDirections(); // a constant table
  return dome;
}

// A light the luxel passes sample: one that draws a direction or a position per sample.
bool softLight(const GpuLight& light) {
  return (light.type == uint32_t(LightType::Point) || light.type == uint32_t(LightType::Sun)) && light.deviance > 0.0f;
}

// The lights a luxel at p takes in `pass`, in the grid's order. After pass 0 only soft lights
// and domes take part: those of the fixed list (suns, domes), unless point lights jitter.
template <class F> void forLuxelLights(const RenderScene& rs, const glm::vec3& p, int pass, const F& f) {
  const LightGrid& grid = rs.lightGrid;
  for (uint32_t i : grid.fixedLights()) f(rs.lights[i]);
  if (pass > 0 && !rs.lightKinds.jitter) return;
  for (uint32_t i : grid.globalLights()) f(rs.lights[i]);
  for (uint32_t i : grid.cellLights(p)) f(rs.lights[i]);
}

// One of the compiler's dome suns, not a random direction: the same luxels, not noise.
glm::vec3 domeSunLight(const RenderScene& rs, const GpuLight& light, const Receiver& r, glm::vec3 toSky, float occlusion) {
  if (light.direction.z < 0.0f) toSky.z = -toSky.z;
  const glm::vec3 facing = facingNormal(r, toSky);
  const float cosIncidence = glm::dot(toSky, facing);
  if (cosIncidence <= 0.0f) return glm::vec3(0.0f);
  if (!reachesSky(rs, Ray{offsetPoint(r.p, facing), 0.0f, toSky, std::numeric_limits<float>::infinity()}, LightingMode::Faithful,
                  light.skyMaterial))
    return glm::vec3(0.0f);
  return light.value * faithful::angleTerm(cosIncidence, light.anglescale) * faithful::lightDirtFactor(light, occlusion, 0.0f) *
      light.color;
}

} // namespace

int luxelPasses(const RenderScene& rs, int softSamples) {
  int passes = 1;
  for (const GpuLight& light : rs.lights) {
    if (light.type == uint32_t(LightType::Dome)) passes = std::max(passes, int(skyDome().size()));
    if (softLight(light)) passes = std::max(passes, softSamples);
  }
  return passes;
}

void faithfulLuxelPass(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, bool twoSided, int pass, int softSamples, Rng& rng,
                       LuxelSums& sums) {
  const Receiver r{p, n, twoSided};
  // Dirt rays start at the compiler's sample point, which p already is.
  if (pass == 0) sums.occlusion = faithfulOcclusion(rs, p - n * faithful::kDirtSampleLift, n, rng);
  forLuxelLights(rs, p, pass, [&](const GpuLight& light) {
    if (light.type == uint32_t(LightType::Dome)) {
      if (pass < int(skyDome().size())) sums.dome += domeSunLight(rs, light, r, skyDome()[size_t(pass)], sums.occlusion);
    } else if (softLight(light)) {
      if (pass < softSamples) addFaithfulLight(rs, light, r, sums.occlusion, rng, sums.soft, sums.localMin);
    } else if (pass == 0) {
      addFaithfulLight(rs, light, r, sums.occlusion, rng, sums.fixed, sums.localMin);
    }
  });
}

glm::vec3 faithfulLuxelLight(const RenderScene& rs, const LuxelSums& sums, int passes, int softSamples, const glm::vec3& faceMinlight) {
  const int domePasses = std::min(passes, int(skyDome().size()));
  const int softPasses = std::min(passes, softSamples);
  glm::vec3 sum = sums.fixed;
  if (domePasses > 0) sum += sums.dome / float(domePasses);
  if (softPasses > 0) sum += sums.soft / float(softPasses);
  return applyFloors(rs, sum, sums.localMin, faceMinlight, sums.occlusion);
}

glm::vec3 faithfulLuxelFloor(const RenderScene& rs, const glm::vec3& faceMinlight) {
  return applyFloors(rs, glm::vec3(0.0f), glm::vec3(0.0f), faceMinlight, 0.0f);
}

glm::vec3 faithfulFaceMinlight(const RenderScene& rs, uint32_t face) {
  const uint32_t m = gpuFace(rs, face).material;
  return m < rs.surfaceLights.size() ? faithful::surfaceFaceMinlight(rs.surfaceLights[m]) : glm::vec3(0.0f);
}

namespace {

// The light sum at a faithful hit: from the grid's lists when rendering, or by the exhaustive
// loop (the reference the grid must reproduce). Lit liquids take light from both sides. A level
// with `_bounce` has its bounce lights among rs.lights (bounce.h), summed like the others.
glm::vec3 faithfulLight(const RenderScene& rs, const IntegratorSettings& settings, const SurfaceHit& hit, const glm::vec3& faceMinlight,
                        Rng& rng) {
  const bool twoSided = rs.faceFlags[hit.face] & kFaceLiquid;
  return faithfulSum(rs, settings.lightSelection ? LightSource::GridSampledBounce : LightSource::All,
                     Receiver{hit.position, hit.normal, twoSided}, faceMinlight, rng);
}

glm::vec3 radianceFaithful(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, Rng& rng) {
  const SurfaceHit hit = traceVisible(rs, ray);
  if (!hit.found) return glm::vec3(0.0f);
  const uint32_t flags = rs.faceFlags[hit.face];
  const glm::vec3 texture = glm::vec3(baseColorAt(rs, hit.face, hit.position));
  // Quake draws sky and (without _litwater) liquids at the texture's own colour, unlit.
  if ((flags & kFaceSky) || ((flags & kFaceLiquid) && !rs.world.litwater)) return srgbToLinear(texture);

  glm::vec3 stored;
  if (const auto baked = lightmapValue(rs.lightmaps, hit.face, textureCoordinates(gpuFace(rs, hit.face), hit.position))) {
    // The game's look: the compiler's luxels through the engine's filter and display.
    const glm::vec3 shown = texture * *baked * rs.lightmaps.displayScale;
    return srgbToLinear(glm::max(shown, emissiveAt(rs, hit.face, hit.position)));
  } else {
    const glm::vec3 light = faithfulLight(rs, settings, hit, faithfulFaceMinlight(rs, hit.face), rng);
    // The compiler scales a coloured sum so its brightest channel fits in 255, keeping the hue.
    stored = light * rs.world.range;
    const float peak = std::max({stored.x, stored.y, stored.z});
    if (peak > 255.0f) stored *= 255.0f / peak;
    stored = glm::max(stored, glm::vec3(0.0f));
  }
  // Engine: texture x lightmap / 128, in the texture's (gamma) space; fullbright texels unlit.
  const glm::vec3 display = glm::max(texture * stored / faithful::kOverbrightOne, emissiveAt(rs, hit.face, hit.position));
  return srgbToLinear(display);
}

// --- physical mode ------------------------------------------------------------------------

struct Bsdf {
  glm::vec3 albedo;
  float roughness;
  float metallic;
  bool specular; // GGX lobe present (materials with a PBR set)
  glm::vec3 n;   // shading normal: the face's, or its normal map's (shadingNormal)
};

float ggxD(float noh, float alpha) {
  const float a2 = alpha * alpha;
  const float d = noh * noh * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}
float smithG1(float nov, float alpha) {
  const float a2 = alpha * alpha;
  return 2.0f * nov / (nov + std::sqrt(a2 + (1.0f - a2) * nov * nov));
}
constexpr float kSpecularLobeProbability = 0.5f;

// ng: the face's own normal. Light from behind the face cannot reach the front, even where a
// normal map turns the shading normal towards it.
glm::vec3 bsdfEval(const Bsdf& b, const glm::vec3& ng, const glm::vec3& wo, const glm::vec3& wi, float& pdf) {
  const glm::vec3& n = b.n;
  const float nol = glm::dot(n, wi);
  const float nov = glm::dot(n, wo);
  pdf = 0.0f;
  if (nol <= 0.0f || nov <= 0.0f || glm::dot(ng, wi) <= 0.0f) return glm::vec3(0.0f);
  if (!b.specular) {
    pdf = nol / kPi;
    return b.albedo / kPi;
  }
  const float alpha = std::max(b.roughness * b.roughness, 1e-3f);
  const glm::vec3 h = glm::normalize(wo + wi);
  const float noh = std::max(glm::dot(n, h), 0.0f), voh = std::max(glm::dot(wo, h), 1e-6f);
  const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), b.albedo, b.metallic);
  const glm::vec3 fresnel = f0 + (1.0f - f0) * std::pow(1.0f - voh, 5.0f);
  const float d = ggxD(noh, alpha);
  const glm::vec3 spec = fresnel * d * smithG1(nol, alpha) * smithG1(nov, alpha) / (4.0f * nol * nov);
  const glm::vec3 diffuse = (1.0f - b.metallic) * b.albedo / kPi;
  pdf = (1.0f - kSpecularLobeProbability) * nol / kPi + kSpecularLobeProbability * d * noh / (4.0f * voh);
  return diffuse + spec;
}

glm::vec3 bsdfSample(const Bsdf& b, const glm::vec3& wo, Rng& rng) {
  const glm::vec3& n = b.n;
  if (!b.specular || rng.next() >= kSpecularLobeProbability) return sampleCosineHemisphere(n, rng.next2());
  // GGX normal distribution sampling, then reflect.
  const float alpha = std::max(b.roughness * b.roughness, 1e-3f);
  const glm::vec2 u = rng.next2();
  const float cosTheta = std::sqrt((1.0f - u.x) / (1.0f + (alpha * alpha - 1.0f) * u.x));
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  const float phi = 2.0f * kPi * u.y;
  const glm::vec3 h = toWorld({sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta}, n);
  return glm::reflect(-wo, h);
}

// Radiance leaving an emitting face at p (physical units): emissive texels plus _surface.
glm::vec3 emittedRadiance(const RenderScene& rs, uint32_t face, const glm::vec3& p) {
  glm::vec3 le = srgbToLinear(emissiveAt(rs, face, p));
  const GpuLight& tmpl = rs.surfaceLights[gpuFace(rs, face).material];
  if (tmpl.value > 0.0f) le += tmpl.color * tmpl.value * rs.world.range * kPhysicalSunScale;
  return le;
}

// A point light's unshadowed contribution to the light leaving towards wo (physical units),
// with wi and the distance of the shadow ray.
glm::vec3 pointLightUnshadowed(const RenderScene& rs, const Bsdf& bsdf, const GpuLight& light, const glm::vec3& pos,
                               const glm::vec3& origin, const glm::vec3& ng, const glm::vec3& wo, glm::vec3& wi, float& dist) {
  const glm::vec3 d = pos - origin;
  const float dist2 = glm::dot(d, d);
  dist = std::sqrt(dist2);
  wi = d / dist;
  float pdf;
  const glm::vec3 f = bsdfEval(bsdf, ng, wo, wi, pdf);
  const float cone = faithful::spotTerm(light, wi);
  if (pdf == 0.0f || cone == 0.0f) return glm::vec3(0.0f);
  const glm::vec3 intensity = light.color * light.value * rs.world.range * kPhysicalPointScale * cone;
  return f * intensity * glm::dot(bsdf.n, wi) / dist2;
}

// How likely light selection picks a point light from the near list: its unshadowed
// irradiance at `origin` on the plane of shading normal n, summed over colour channels (at the
// light's own origin: the pick does not depend on the _deviance jitter).
float selectionWeight(const GpuLight& light, const glm::vec3& origin, const glm::vec3& n) {
  const glm::vec3 d = light.origin - origin;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return 0.0f;
  const glm::vec3 wi = d / std::sqrt(dist2);
  const float cosSurface = glm::dot(n, wi);
  if (cosSurface <= 0.0f) return 0.0f;
  return (light.color.x + light.color.y + light.color.z) * light.value * faithful::spotTerm(light, wi) * cosSurface / dist2;
}

glm::vec3 sunContribution(const RenderScene& rs, const Bsdf& bsdf, const GpuLight& light, const glm::vec3& origin, const glm::vec3& ng,
                          const glm::vec3& wo, Rng& rng) {
  glm::vec3 wi = -light.direction;
  if (light.deviance > 0.0f) wi = sampleCone(wi, light.deviance, rng.next2());
  float pdf;
  const glm::vec3 f = bsdfEval(bsdf, ng, wo, wi, pdf);
  if (pdf == 0.0f) return glm::vec3(0.0f);
  if (!reachesSky(rs, Ray{origin, 0.0f, wi, std::numeric_limits<float>::infinity()}, LightingMode::Physical)) return glm::vec3(0.0f);
  return f * light.color * light.value * rs.world.range * kPhysicalSunScale * glm::dot(bsdf.n, wi);
}

// Every point light and sun, each with its own shadow ray: the reference for selection.
glm::vec3 allLightsExhaustive(const RenderScene& rs, const Bsdf& bsdf, const glm::vec3& origin, const glm::vec3& ng, const glm::vec3& wo,
                              Rng& rng) {
  glm::vec3 l(0.0f);
  for (const GpuLight& light : rs.lights) {
    if (light.value <= 0.0f) continue; // negative lights have no physical meaning
    if (light.type == uint32_t(LightType::Point)) {
      if (light.formula == uint32_t(LightFormula::LocalMin)) continue;
      if (light.flags & kLightFlagFromSurface) continue; // its faces are area emitters here
      const glm::vec3 pos = jitteredOrigin(light, rng);
      glm::vec3 wi;
      float dist;
      const glm::vec3 c = pointLightUnshadowed(rs, bsdf, light, pos, origin, ng, wo, wi, dist);
      if (c == glm::vec3(0.0f) || occluded(rs, Ray{origin, 0.0f, wi, dist}, LightingMode::Physical)) continue;
      l += c;
    } else if (light.type == uint32_t(LightType::Sun)) {
      l += sunContribution(rs, bsdf, light, origin, ng, wo, rng);
    }
  }
  return l;
}

// Light selection's probability of the near list (the rest goes to a uniform pick over every
// physical light, so that a light missing from the near list can still be picked: unbiased).
constexpr float kNearListProbability = 0.9f;

// Suns one by one (there are at most a few), then ONE point light, divided by the probability
// of picking it: an unbiased estimate of the sum over all of them with one shadow ray instead
// of hundreds. The pick mixes two strategies (one-sample mixture, Veach's "balance" pdf):
//   near:    the cell's near list (light_grid.h), by selectionWeight at the hit's origin;
//   uniform: any light of the physical list, 1 / count.
// pdf(light) = P(near) * weight / nearTotal [if listed] + (1 - P(near)) / count.
// Weights use the light's own origin and the shading normal, so the pick does not depend on its _deviance jitter,
// which is drawn for the chosen light only. Random numbers per hit, in order: the suns', the
// strategy, the pick, the chosen light's jitter (3, when soft); light_select.glsl draws the same.
glm::vec3 allLightsSelected(const RenderScene& rs, const Bsdf& bsdf, const glm::vec3& origin, const glm::vec3& ng, const glm::vec3& wo,
                            Rng& rng) {
  glm::vec3 l(0.0f);
  for (uint32_t i : rs.lightGrid.fixedLights()) {
    const GpuLight& light = rs.lights[i];
    if (light.type == uint32_t(LightType::Sun) && light.value > 0.0f) l += sunContribution(rs, bsdf, light, origin, ng, wo, rng);
  }
  const glm::vec3& n = bsdf.n;

  const std::span<const uint32_t> all = rs.lightGrid.physicalLights();
  const std::span<const uint32_t> near = rs.lightGrid.physicalNearLights(origin);
  float nearTotal = 0.0f;
  for (uint32_t i : near) nearTotal += selectionWeight(rs.lights[i], origin, n);
  const float uStrategy = rng.next(), uPick = rng.next();
  if (all.empty()) return l;
  const float nearProbability = nearTotal > 0.0f ? kNearListProbability : 0.0f;

  uint32_t chosen = 0;
  float chosenWeight = 0.0f; // its near-list weight, 0 when not listed
  if (uStrategy < nearProbability) {
    // The entry whose cumulative interval holds the target (the last one with weight when
    // rounding leaves the target past the end).
    const float target = uPick * nearTotal;
    float cumulative = 0.0f;
    for (uint32_t i : near) {
      const float w = selectionWeight(rs.lights[i], origin, n);
      if (w <= 0.0f) continue;
      chosen = i, chosenWeight = w;
      cumulative += w;
      if (cumulative > target) break;
    }
  } else {
    chosen = all[std::min(uint32_t(uPick * float(all.size())), uint32_t(all.size()) - 1)];
    for (uint32_t i : near)
      if (i == chosen) chosenWeight = selectionWeight(rs.lights[i], origin, n);
  }
  const float pdf =
      (nearProbability > 0.0f ? nearProbability * chosenWeight / nearTotal : 0.0f) + (1.0f - nearProbability) / float(all.size());

  const GpuLight& light = rs.lights[chosen];
  const glm::vec3 pos = jitteredOrigin(light, rng);
  glm::vec3 wi;
  float dist;
  const glm::vec3 c = pointLightUnshadowed(rs, bsdf, light, pos, origin, ng, wo, wi, dist);
  if (pdf > 0.0f && c != glm::vec3(0.0f) && !occluded(rs, Ray{origin, 0.0f, wi, dist}, LightingMode::Physical)) l += c / pdf;
  return l;
}

// Direct light at a surface by next-event estimation: point lights and suns, then one emitter
// triangle (MIS-weighted against BSDF sampling). Rays leave from the face (ng), not from where
// a normal map pretends it is.
glm::vec3 directLight(const RenderScene& rs, const IntegratorSettings& settings, const Bsdf& bsdf, const glm::vec3& p, const glm::vec3& ng,
                      const glm::vec3& wo, Rng& rng) {
  const glm::vec3 origin = offsetPoint(p, ng);
  glm::vec3 l =
      settings.lightSelection ? allLightsSelected(rs, bsdf, origin, ng, wo, rng) : allLightsExhaustive(rs, bsdf, origin, ng, wo, rng);

  if (!rs.emitters.empty()) {
    const GpuEmitter& e = rs.emitters[pickEmitter(rs, rng.next())];
    const glm::vec3 q = sampleTriangle(e.v0, e.v1, e.v2, rng.next2());
    const glm::vec3 d = q - origin;
    const float dist2 = glm::dot(d, d);
    const float dist = std::sqrt(dist2);
    const glm::vec3 wi = d / dist;
    const glm::vec3 ln = faceNormal(rs, e.face);
    const float cosLight = -glm::dot(ln, wi);
    float bsdfPdf;
    const glm::vec3 f = bsdfEval(bsdf, ng, wo, wi, bsdfPdf);
    if (cosLight > 0.0f && bsdfPdf > 0.0f) {
      const float lightPdf = dist2 / (cosLight * rs.emitterArea); // solid angle
      // Stop just short of the emitter so that its own face does not count as a blocker.
      if (!occluded(rs, Ray{origin, 0.0f, wi, dist - 2.0f * kSurfaceOffset}, LightingMode::Physical)) {
        const glm::vec3 le = emittedRadiance(rs, e.face, q);
        l += f * le * glm::dot(bsdf.n, wi) * powerHeuristic(lightPdf, bsdfPdf) / lightPdf;
      }
    }
  }
  return l;
}

glm::vec3 radiancePhysical(const RenderScene& rs, const IntegratorSettings& settings, Ray ray, Rng& rng) {
  glm::vec3 l(0.0f), throughput(1.0f);
  float prevBsdfPdf = 0.0f; // 0: camera ray (no MIS weight on what it sees)
  for (int depth = 0;; ++depth) {
    const SurfaceHit hit = traceVisible(rs, ray);
    if (!hit.found) break; // the void outside a level is black
    const uint32_t flags = rs.faceFlags[hit.face];
    if (flags & kFaceSky) {
      l += throughput * (srgbToLinear(glm::vec3(baseColorAt(rs, hit.face, hit.position))) + skyDomeRadiance(rs, ray.direction));
      break;
    }
    const glm::vec3 n = hit.normal;
    const glm::vec3 wo = -ray.direction;
    if (flags & kFaceEmissive) {
      const glm::vec3 le = emittedRadiance(rs, hit.face, hit.position);
      float weight = 1.0f;
      if (prevBsdfPdf > 0.0f) {
        const float cosLight = std::max(glm::dot(n, wo), 1e-6f);
        const float lightPdf = hit.t * hit.t / (cosLight * rs.emitterArea);
        weight = powerHeuristic(prevBsdfPdf, lightPdf);
      }
      l += throughput * le * weight;
    }
    if (depth >= settings.bounces + 1) break;

    const GpuMaterial& m = rs.materials[gpuFace(rs, hit.face).material];
    const Bsdf bsdf{srgbToLinear(glm::vec3(baseColorAt(rs, hit.face, hit.position))), m.roughness, m.metallic,
                    (m.flags & kMaterialSpecular) != 0, shadingNormal(rs, hit, wo)};
    l += throughput * directLight(rs, settings, bsdf, hit.position, n, wo, rng);

    const glm::vec3 wi = bsdfSample(bsdf, wo, rng);
    float pdf;
    const glm::vec3 f = bsdfEval(bsdf, n, wo, wi, pdf);
    if (pdf <= 0.0f) break;
    throughput *= f * glm::dot(bsdf.n, wi) / pdf;
    prevBsdfPdf = pdf;

    // Russian roulette after three bounces, survival by throughput.
    if (depth >= 3) {
      const float survive = std::min(0.95f, std::max({throughput.x, throughput.y, throughput.z}));
      if (rng.next() >= survive) break;
      throughput /= survive;
    }
    ray = Ray{offsetPoint(hit.position, n), 0.0f, wi, std::numeric_limits<float>::infinity()};
  }
  return l;
}

} // namespace

glm::vec3 radiance(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, Rng& rng) {
  if (settings.mode == LightingMode::Faithful) return radianceFaithful(rs, settings, ray, rng);
  return radiancePhysical(rs, settings, ray, rng);
}

} // namespace bt

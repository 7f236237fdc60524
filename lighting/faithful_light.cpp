#include "lighting/faithful_light.h"

#include "lighting/faithful.h"
#include "lighting/vis_approx.h"
#include "lighting/visibility.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace bt {

glm::vec3 jitteredOrigin(const GpuLight& light, Rng& rng) {
  if (light.deviance <= 0.0f) return light.origin;
  const glm::vec3 u{rng.next(), rng.next(), rng.next()}; // braces: drawn left to right, as in GLSL
  return light.origin + light.deviance * (2.0f * u - 1.0f);
}

namespace {

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
    sum += blockedDistance(rs, origin, faithful::dirtRayDirection(n, v), dirt.depth);
  }
  return faithful::dirtOcclusion(sum, faithful::kDirtRays, dirt.depth);
}

// A faithful receiver: a surface point, its face's normal, and whether light from behind counts.
struct Receiver {
  glm::vec3 p;
  glm::vec3 n;
  bool twoSided;                        // a lit liquid: ericw-tools lights it from above and below (ltface.cc "twosided")
  uint32_t channels = kDefaultChannels; // its face's `_object_channel_mask`
  VisCull cull;                         // where the compiler culls lights by their boxes (vis_approx.h)
  // A luxel's sky rays cast ahead (faithfulLuxelPass; null elsewhere), and how many penumbra
  // passes it takes.
  LuxelSky* penumbra = nullptr;
  LuxelSky* dome = nullptr;
  int penumbraPasses = 0;
};

// The normal the receiver turns to light arriving from `toLight`: a two-sided receiver faces
// every light, so the angle term takes |cos| and the shadow ray leaves from the light's side.
glm::vec3 facingNormal(const Receiver& r, const glm::vec3& toLight) {
  return r.twoSided && glm::dot(r.n, toLight) < 0.0f ? -r.n : r.n;
}

// reachesSky for `ray`, the ray of `light`'s pass `pass` (of `passes`), answered from the luxel's
// packets in `sky`: the first pass to ask casts every pass's ray, rayOf(k) (none where pass k
// casts none), kPacketRays at a time. Another such light of the same luxel casts ray by ray.
template <class RayOf> bool packetReachesSky(const RenderScene& rs, const GpuLight& light, LuxelSky& sky, int passes, int pass,
                                             const Ray& ray, const RayOf& rayOf) {
  constexpr int kPacket = int(TraceScene::kPacketRays);
  if (sky.light == nullptr) {
    sky.light = &light;
    for (int first = 0; first < passes; first += kPacket) {
      std::array<Ray, TraceScene::kPacketRays> rays;
      std::array<int, TraceScene::kPacketRays> passOf;
      size_t count = 0;
      for (int k = first; k < std::min(passes, first + kPacket); ++k)
        if (const std::optional<Ray> kth = rayOf(k)) rays[count] = *kth, passOf[count++] = k;
      const uint64_t reached = reachSky(rs, std::span(rays).first(count), LightingMode::Faithful, light.skyMaterial);
      for (size_t i = 0; i < count; ++i)
        if ((reached >> i) & 1u) sky.reaches[size_t(passOf[i] / kPacket)] |= uint64_t(1) << (passOf[i] % kPacket);
    }
  }
  if (sky.light != &light) return reachesSky(rs, ray, LightingMode::Faithful, light.skyMaterial);
  return (sky.reaches[size_t(pass / kPacket)] >> (pass % kPacket)) & 1u;
}

// The penumbra sun's rays, each as the sun branch of addFaithfulLight builds it.
bool penumbraReachesSky(const RenderScene& rs, const GpuLight& light, const Receiver& r, int pass, const Ray& ray) {
  static_assert(faithful::kSunSamples <= int(TraceScene::kPacketRays));
  return packetReachesSky(
      rs, light, *r.penumbra, std::min(r.penumbraPasses, faithful::kSunSamples), pass % faithful::kSunSamples, ray, [&](int k) {
        const glm::vec3 toSun = -rs.sunTable[light.sunTable + uint32_t(k)];
        return std::optional<Ray>(Ray{offsetRayOrigin(r.p, facingNormal(r, toSun)), 0.0f, toSun, std::numeric_limits<float>::infinity()});
      });
}

// Faithful mode: one light's share of the light sum at the receiver, dimmed by the dirt
// `occlusion` there. Local-minlight lights raise `localMin` instead: they are a floor, not a sum.
// `cache`, when given, is the caller's ShadowCache and `light` is rs.lights[index]; `seen`: the
// cache proved that no brush blocks the shadow ray.
// `pass`: a luxel pass (faithfulLuxelPass), in which a penumbra sun takes the compiler's own
// direction of that pass instead of a random one; -1 elsewhere.
void addFaithfulLight(const RenderScene& rs, const GpuLight& light, const Receiver& r, float occlusion, Rng& rng, glm::vec3& sum,
                      glm::vec3& localMin, ShadowCache* cache = nullptr, size_t index = 0, bool seen = false, int pass = -1) {
  // The compiler's lighting channels (ltface.cc): a point light lights only the faces on one of
  // its channels; suns and domes are on the default channel.
  const uint32_t channels = light.type == uint32_t(LightType::Point) ? light.lightChannels : kDefaultChannels;
  if (!(channels & r.channels)) return;
  // ericw-tools' cull without vis data (CullLight): before any of the light's random numbers.
  if (r.cull.receiver && light.visBox && visBoxesApart(r.cull.lights[light.visBox - 1], *r.cull.receiver)) return;
  if (light.type == uint32_t(LightType::Point)) {
    glm::vec3 pos = jitteredOrigin(light, rng);
    const glm::vec3 d = pos - r.p;
    float dist = glm::length(d);
    glm::vec3 toLight = d / dist;
    if (!(dist >= faithful::kNearestLight)) {
      dist = faithful::kNearestLight, toLight = glm::vec3(0.0f, 0.0f, 1.0f);
      pos = r.p + toLight * dist;
    }
    const glm::vec3 n = facingNormal(r, toLight);
    const float value =
        faithful::pointLightValue(light, n, toLight, dist, rs.world.scaledist) * faithful::lightDirtFactor(light, occlusion, dist);
    if (value == 0.0f) return;
    const glm::vec3 origin = offsetRayOrigin(r.p, n);
    const glm::vec3 toLightFromOrigin = pos - origin;
    const float len = glm::length(toLightFromOrigin);
    const Ray ray{origin, 0.0f, toLightFromOrigin / len, len};
    if (!seen &&
        (cache ? cachedShadowed(rs, *cache, uint32_t(index), ray) : occluded(rs, ray, LightingMode::Faithful, light.shadowChannels)))
      return;
    if (light.formula == uint32_t(LightFormula::LocalMin))
      localMin = glm::max(localMin, value * light.color);
    else
      sum += value * light.color;
  } else if (light.type == uint32_t(LightType::Sun)) {
    glm::vec3 toSun = -light.direction;
    if (pass >= 0 && (light.flags & kLightFlagSunTable))
      toSun = -rs.sunTable[light.sunTable + uint32_t(pass % faithful::kSunSamples)];
    else if (light.deviance > 0.0f)
      toSun = sampleCone(toSun, light.deviance, rng.next2());
    GpuLight jittered = light;
    jittered.direction = -toSun;
    const glm::vec3 n = facingNormal(r, toSun);
    const float value = faithful::sunValue(jittered, n) * faithful::lightDirtFactor(light, occlusion, 0.0f);
    if (value == 0.0f) return;
    const Ray ray{offsetRayOrigin(r.p, n), 0.0f, toSun, std::numeric_limits<float>::infinity()};
    const bool packet = r.penumbra && pass >= 0 && (light.flags & kLightFlagSunTable);
    if (!(packet ? penumbraReachesSky(rs, light, r, pass, ray) : reachesSky(rs, ray, LightingMode::Faithful, light.skyMaterial))) return;
    sum += value * light.color;
  } else if (light.type == uint32_t(LightType::Dome)) {
    // One direction of the dome per sample, uniform over its hemisphere: the mean over the
    // dome's directions of value * angle term, for those that reach the sky.
    const glm::vec3 dir = sampleUniformHemisphere(light.direction, rng.next2());
    const glm::vec3 n = facingNormal(r, dir);
    const float cosIncidence = glm::dot(dir, n);
    if (cosIncidence <= 0.0f) return;
    if (!reachesSky(rs, Ray{offsetRayOrigin(r.p, n), 0.0f, dir, std::numeric_limits<float>::infinity()}, LightingMode::Faithful)) return;
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
    const glm::vec3 origin = offsetRayOrigin(r.p, s.n);
    const glm::vec3 toLight = light.origin - origin;
    const float len = glm::length(toLight);
    if (occluded(rs, Ray{origin, 0.0f, toLight / len, len}, LightingMode::Faithful)) continue;
    sum += s.rgb * faithful::lightDirtFactor(light, occlusion, s.dist) * (float(picks) * total / (s.weight * strata));
  }
  return sum;
}

// worldspawn minlight, a radiosity template's face minlight and delay-4 lights are floors under
// the sum, not terms of it; with `_minlight_dirt`, dirt dims both minlights (LightFace_Min). The
// negative lights (faithful::subtractedLight, their sum `negative`) come off after the floors, and
// what goes below 0 is 0 (ltface.cc: positive lights, minlight, negative lights, then the clamp).
glm::vec3 applyFloors(const RenderScene& rs, const glm::vec3& sum, const glm::vec3& localMin, const glm::vec3& faceMinlight,
                      float occlusion, const glm::vec3& negative = glm::vec3(0.0f)) {
  const DirtSettings& dirt = rs.world.dirtSettings;
  const float minlightDirt = dirt.minlight ? 1.0f - faithful::dirtAmount(occlusion, dirt.gain, dirt.scale) : 1.0f;
  const glm::vec3 floored = glm::max(glm::max(sum + rs.world.ambient, localMin), glm::max(rs.world.minlight, faceMinlight) * minlightDirt);
  return glm::max(floored + negative, glm::vec3(0.0f));
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
  glm::vec3 sum(0.0f), localMin(0.0f), negative(0.0f);
  auto add = [&](const GpuLight& light) {
    if (which == FaithfulLights::BounceSources && !feedsBounce(light, rs.world)) return;
    if (bounceShadowRays && light.formula == uint32_t(LightFormula::Bounce)) ++*bounceShadowRays; // at most
    addFaithfulLight(rs, light, r, occlusion, rng, faithful::subtractedLight(light) ? negative : sum, localMin);
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
  return applyFloors(rs, sum, localMin, faceMinlight, occlusion, negative);
}

} // namespace

float faithfulDirtOcclusion(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng) {
  return faithfulOcclusion(rs, p, n, rng);
}

namespace {

glm::vec3 givenLightsSum(const RenderScene& rs, const GivenLights& given, const Receiver& r, std::optional<float> knownOcclusion,
                         Rng& rng) {
  const float occlusion = knownOcclusion ? *knownOcclusion : faithfulOcclusion(rs, r.p, r.n, rng);
  // Whether to draw goes by every light: a few candidates still take the draw.
  if (given.lights.size() <= given.maxShadowRays) {
    glm::vec3 sum(0.0f), localMin(0.0f);
    for (const GpuLight& light : given.lights) addFaithfulLight(rs, light, r, occlusion, rng, sum, localMin);
    return sum;
  }
  // The draw sweeps the candidates only (every light where none are named).
  const auto candidate = [&](size_t i) -> const GpuLight& { return given.lights[given.candidates ? (*given.candidates)[i] : i]; };
  const size_t count = given.candidates ? given.candidates->size() : given.lights.size();
  return sampledBounceSum(rs, count, candidate, r, occlusion, rng, given.maxShadowRays);
}

} // namespace

glm::vec3 faithfulLight(const RenderScene& rs, const FaithfulQuery& q, Rng& rng) {
  const Receiver r{q.p, q.n, q.twoSided, q.channels, q.cull};
  switch (q.lights) {
  case LightSet::All: return faithfulSum(rs, LightSource::All, r, q.faceMinlight, rng);
  case LightSet::Grid: return faithfulSum(rs, LightSource::Grid, r, q.faceMinlight, rng);
  case LightSet::GridSampledBounce:
    return faithfulSum(rs, LightSource::GridSampledBounce, r, q.faceMinlight, rng, FaithfulLights::Shown, q.bounceShadowRays);
  case LightSet::BounceSources:
    return faithfulSum(rs, LightSource::Grid, r, q.faceMinlight, rng, FaithfulLights::BounceSources, nullptr, q.occlusion);
  case LightSet::Given: return q.given ? givenLightsSum(rs, *q.given, r, q.occlusion, rng) : glm::vec3(0.0f);
  }
  return glm::vec3(0.0f);
}

LightShares faithfulLightShares(const RenderScene& rs, const FaithfulQuery& q, int samples, Rng& rng) {
  const Receiver r{q.p, q.n, q.twoSided, q.channels, q.cull};
  LightShares shares;
  shares.occlusion = faithfulOcclusion(rs, r.p, r.n, rng);
  shares.perLight.resize(rs.lights.size(), glm::vec3(0.0f));
  glm::vec3 sum(0.0f), localMin(0.0f), negative(0.0f);
  for (size_t i = 0; i < rs.lights.size(); ++i) {
    const GpuLight& light = rs.lights[i];
    const bool soft = light.type == uint32_t(LightType::Dome) || light.deviance > 0.0f;
    const int draws = soft ? std::max(samples, 1) : 1;
    glm::vec3 share(0.0f), min(0.0f);
    for (int k = 0; k < draws; ++k) addFaithfulLight(rs, light, r, shares.occlusion, rng, share, min);
    shares.perLight[i] = share / float(draws);
    (faithful::subtractedLight(light) ? negative : sum) += shares.perLight[i];
    localMin = glm::max(localMin, min);
  }
  shares.ambient = rs.world.ambient;
  shares.shown = applyFloors(rs, sum, localMin, q.faceMinlight, shares.occlusion, negative);
  shares.floors = shares.shown - sum - negative - shares.ambient;
  return shares;
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

// The dome's ray of `pass` from r and its angle term, or none where the direction gives the
// receiver nothing.
std::optional<Ray> domeRay(const GpuLight& light, const Receiver& r, int pass, float& angle) {
  glm::vec3 toSky = skyDome()[size_t(pass)];
  if (light.direction.z < 0.0f) toSky.z = -toSky.z;
  const glm::vec3 facing = facingNormal(r, toSky);
  // Along the face's plane too (faithful::sunAngleTerm): a wall takes the zenith sun at (1 - a).
  angle = faithful::sunAngleTerm(glm::dot(toSky, facing), light.anglescale);
  if (angle <= 0.0f) return std::nullopt;
  return Ray{offsetRayOrigin(r.p, facing), 0.0f, toSky, std::numeric_limits<float>::infinity()};
}

// The dome's rays in front of the receiver.
bool domeReachesSky(const RenderScene& rs, const GpuLight& light, const Receiver& r, int pass, const Ray& ray) {
  static_assert(faithful::kSunSamples + 1 <= 2 * int(TraceScene::kPacketRays), "LuxelSky::reaches holds the dome's directions");
  return packetReachesSky(rs, light, *r.dome, int(skyDome().size()), pass, ray, [&](int k) {
    float angle = 0.0f;
    return domeRay(light, r, k, angle);
  });
}

// One of the compiler's dome suns, not a random direction: the same luxels, not noise.
glm::vec3 domeSunLight(const RenderScene& rs, const GpuLight& light, const Receiver& r, int pass, float occlusion) {
  float angle = 0.0f;
  const std::optional<Ray> ray = domeRay(light, r, pass, angle);
  if (!ray) return glm::vec3(0.0f);
  if (!(r.dome ? domeReachesSky(rs, light, r, pass, *ray) : reachesSky(rs, *ray, LightingMode::Faithful, light.skyMaterial)))
    return glm::vec3(0.0f);
  return light.value * angle * faithful::lightDirtFactor(light, occlusion, 0.0f) * light.color;
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
                       LuxelSums& sums, uint32_t channels, ShadowCache* cache, VisCull cull, int style) {
  const auto otherStyle = [&](const GpuLight& light) { return style != kAllStyles && int(lightStyle(light)) != style; };
  const auto index = [&](const GpuLight& light) { return size_t(&light - rs.lights.data()); };
  const Receiver r{p, n, twoSided, channels, cull, &sums.penumbraSky, &sums.domeSky, softSamples};
  // Dirt rays start at the compiler's sample point, which p already is.
  if (pass == 0) sums.occlusion = faithfulOcclusion(rs, p - n * faithful::kDirtSampleLift, n, rng);
  const auto each = [&](const GpuLight& light, const Receiver& r) {
    if (otherStyle(light)) return;
    if (light.type == uint32_t(LightType::Dome)) {
      if (pass < int(skyDome().size())) sums.dome += domeSunLight(rs, light, r, pass, sums.occlusion);
    } else if (softLight(light)) {
      if (pass < softSamples)
        addFaithfulLight(rs, light, r, sums.occlusion, rng, sums.soft, sums.localMin, cache, index(light), false, pass);
    } else if (pass == 0) {
      glm::vec3& to = faithful::subtractedLight(light) ? sums.negative : sums.fixed;
      addFaithfulLight(rs, light, r, sums.occlusion, rng, to, sums.localMin, cache, index(light));
    }
  };
  if (pass == 0 && cache && cache->grouped) {
    // The group's list left out the lights that this luxel's cull culls: no need to test them again.
    Receiver grouped = r;
    if (cull.receiver && cull == cache->groupCulledWith) grouped.cull = {};
    for (uint32_t e : cache->groupLights) {
      const uint32_t i = e & ~kSeenByAll;
      if (otherStyle(rs.lights[i])) continue;
      if (e & kSeenByAll)
        addFaithfulLight(rs, rs.lights[i], grouped, sums.occlusion, rng,
                         faithful::subtractedLight(rs.lights[i]) ? sums.negative : sums.fixed, sums.localMin, cache, i, true);
      else
        each(rs.lights[i], grouped);
    }
  } else {
    forLuxelLights(rs, p, pass, [&](const GpuLight& light) { each(light, r); });
  }
}

glm::vec3 faithfulLuxelLight(const RenderScene& rs, const LuxelSums& sums, int passes, int softSamples, const glm::vec3& faceMinlight,
                             bool floors) {
  const int domePasses = std::min(passes, int(skyDome().size()));
  const int softPasses = std::min(passes, softSamples);
  glm::vec3 sum = sums.fixed;
  if (domePasses > 0) sum += sums.dome / float(domePasses);
  if (softPasses > 0) sum += sums.soft / float(softPasses);
  if (!floors) return glm::max(glm::max(sum, sums.localMin) + sums.negative, glm::vec3(0.0f));
  return applyFloors(rs, sum, sums.localMin, faceMinlight, sums.occlusion, sums.negative);
}

glm::vec3 faithfulLuxelFloor(const RenderScene& rs, const glm::vec3& faceMinlight) {
  return applyFloors(rs, glm::vec3(0.0f), glm::vec3(0.0f), faceMinlight, 0.0f);
}

glm::vec3 faithfulFaceMinlight(const RenderScene& rs, uint32_t face) {
  const uint32_t m = gpuFace(rs, face).material;
  return m < rs.surfaceLights.size() ? faithful::surfaceFaceMinlight(rs.surfaceLights[m]) : glm::vec3(0.0f);
}

} // namespace bt

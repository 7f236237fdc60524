#include "renderer/cpu/integrator.h"

#include "lighting/light_tree.h"
#include "lighting/physical_light.h"

#include "lighting/faithful.h"
#include "lighting/liquids.h"
#include "lighting/sky.h"
#include "scene/color.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace bt {

namespace {

// The emitter triangle whose cdf interval holds u: the first whose cdf reaches u, the last when
// none does (light_select.glsl's bisection gives the same). A bisection without branches (Khuong
// and Morin, "Array Layouts for Comparison-Based Searching", 2017): the branchy one's
// mispredictions and misses were a tenth of radiancePhysical's own time.
// The guide (RenderScene::emitterGuide) narrows the search to the emitters between its entries
// for floor(u K) and the next: every emitter before the first has a cdf below k / K <= u, and the
// second's reaches (k + 1) / K > u (or it is the last), so the answer lies between them.
uint32_t pickEmitter(const RenderScene& rs, float u) {
  const GpuEmitter* e = rs.emitters.data();
  uint32_t base = 0, count = uint32_t(rs.emitters.size()) - 1; // the last ends every search untested
  if (const size_t buckets = rs.emitterGuide.size() - 1; !rs.emitterGuide.empty()) {
    const size_t k = std::min(size_t(u * float(buckets)), buckets - 1);
    base = rs.emitterGuide[k];
    count = rs.emitterGuide[k + 1] - base;
  }
  if (count == 0) return base;
  while (count > 1) {
    const uint32_t half = count / 2;
    base = e[base + half].cdf < u ? base + half : base;
    count -= half;
  }
  return base + (e[base].cdf < u ? 1u : 0u);
}

// Domes sit in the light grid's fixed list (suns, domes, local minlights): a bounce ray that
// reaches the sky looks at a handful of lights, not at every light of the level.
glm::vec3 skyDomeRadiance(const RenderScene& rs, const glm::vec3& dir) {
  glm::vec3 l(0.0f);
  for (uint32_t index : rs.lightGrid.fixedLights()) {
    const GpuLight& light = rs.lights[index];
    if (light.type == uint32_t(LightType::Dome) && dir.z * light.direction.z > 0.0f)
      l += physical::colour(light.color) * light.value * rs.world.range * kPhysicalSunScale / kPi;
  }
  return l;
}

} // namespace

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
constexpr float kHorizonMargin = BT_HORIZON_MARGIN;

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

// The light sum at a faithful hit: from the grid's lists when rendering, or by the exhaustive
// loop (the reference the grid must reproduce). Lit liquids take light from both sides. A level
// with `_bounce` has its bounce lights among rs.lights (bounce.h), summed like the others.
glm::vec3 faithfulLightAtHit(const RenderScene& rs, const IntegratorSettings& settings, const SurfaceHit& hit, Rng& rng) {
  FaithfulQuery q;
  q.p = hit.position;
  q.n = hit.normal;
  q.twoSided = rs.faceFlags[hit.face] & kFaceLiquid;
  q.channels = objectChannels(rs, hit.face);
  q.lights = settings.lightSelection ? LightSet::GridSampledBounce : LightSet::All;
  q.faceMinlight = faithfulFaceMinlight(rs, hit.face);
  return faithfulLight(rs, q, rng);
}

// What the compiler stores for `light` light units: light x _range, scaled so that its brightest
// channel fits in 255, keeping the hue.
glm::vec3 storedLuxel(const RenderScene& rs, const glm::vec3& light) {
  glm::vec3 stored = light * rs.world.range;
  const float peak = std::max({stored.x, stored.y, stored.z});
  if (peak > 255.0f) stored *= 255.0f / peak;
  return glm::max(stored, glm::vec3(0.0f));
}

// What the game draws at the camera ray's surface `hit`, linear.
glm::vec3 faithfulSurfaceRadiance(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, const SurfaceHit& hit,
                                  Rng& rng) {
  if (!hit.found) return glm::vec3(0.0f);
  const uint32_t flags = rs.faceFlags[hit.face];
  // A sky face of a level with sky images shows them by the ray's direction, as a miss would.
  if ((flags & kFaceSky) && rs.sky.size > 0) return skyRadiance(rs.sky, ray.direction);
  const glm::vec3 texture = glm::vec3(baseColorAt(rs, hit.face, hit.position));
  // Quake draws sky and (without _litwater) liquids at the texture's own colour, unlit; Quake 2
  // its glass too.
  if (engineDrawsUnlit(rs, hit.face)) return srgbToLinear(texture);

  glm::vec3 stored;
  if (const auto baked = lightmapValue(rs.lightmaps, hit.face, textureCoordinates(gpuFace(rs, hit.face), hit.position))) {
    // The game's look: the compiler's luxels through the engine's filter and display.
    const glm::vec3 shown = texture * *baked * rs.lightmaps.displayScale;
    return srgbToLinear(glm::max(shown, emissiveAt(rs, hit.face, hit.position)));
  } else {
    stored = storedLuxel(rs, faithfulLightAtHit(rs, settings, hit, rng));
  }
  // Engine: texture x lightmap / 128 (Quake's overbright; 255 in Quake 2 and Half-Life), in the
  // texture's (gamma) space; fullbright texels unlit.
  const glm::vec3 display =
      glm::max(texture * shownLuxel(rs.world.luxelDisplay, stored) / rs.world.overbrightOne, emissiveAt(rs, hit.face, hit.position));
  return srgbToLinear(display);
}

// A translucent liquid's blend (lighting/liquids.h) or Quake 2 glass's; opaque for every other face.
LiquidBlend surfaceBlend(const RenderScene& rs, const SurfaceHit& hit) {
  return hit.found ? engineBlend(rs, hit.face) : LiquidBlend{};
}

LiquidBlend physicalSurfaceBlend(const RenderScene& rs, const SurfaceHit& hit) {
  if (!hit.found || !(rs.faceFlags[hit.face] & kFaceLiquid)) return {};
  return physicalLiquidBlend(rs.materials[gpuFace(rs, hit.face).material]);
}

// The camera ray's surface as the game draws it, and where it is a translucent liquid or Quake 2's
// glass, blended over what lies behind as the engine blends it: in the framebuffer's (the
// textures') gamma space, display = self x liquid + behind x what lies behind (x the liquid for a
// filter). The ray goes on behind the liquid along the camera's line through the point it met,
// as pathtrace.comp restarts it.
glm::vec3 radianceFaithful(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, Rng& rng) {
  glm::vec3 veil(0.0f), keep(1.0f);
  bool veiled = false;
  Ray r = ray;
  while (true) {
    const SurfaceHit hit = traceVisible(rs, r);
    const glm::vec3 l = faithfulSurfaceRadiance(rs, settings, r, hit, rng);
    const LiquidBlend blend = surfaceBlend(rs, hit);
    if (!(blend.behind > 0.0f)) return veiled ? srgbToLinear(veil + keep * linearToSrgb(l)) : l;
    veil += keep * blend.self * linearToSrgb(l);
    keep *= behindWeight(blend, linearToSrgb(l));
    veiled = true;
    const glm::vec3 toSurface = hit.position - ray.origin;
    const float t = glm::length(toSurface);
    r = Ray{ray.origin, continueRayAfter(t), toSurface / t, std::numeric_limits<float>::infinity()};
  }
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
constexpr float kSpecularLobeProbability = BT_SPECULAR_LOBE_PROBABILITY;

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
  if (tmpl.value > 0.0f) le += physical::colour(tmpl.color) * tmpl.value * rs.world.range * kPhysicalSunScale;
  return le;
}

// The firefly clamp (IntegratorSettings::clampIndirect): the share of a point light's falloff
// kept when it counts as at least sqrt(minDist2) away, d^2 / R^2 nearer than R and exactly 1
// beyond. Only the inverse square is clamped; the window keeps the true distance, so a light
// whose reach is shorter than R still lights what it reaches. pathtrace.comp computes the same.
float clampedShare(float dist2, float minDist2) {
  return dist2 < minDist2 ? dist2 / minDist2 : 1.0f;
}

// A point light's unshadowed contribution to the light leaving towards wo (physical units),
// with wi and the distance of the shadow ray. The falloff is taken at least minDist2 (squared
// units) from the light: IntegratorSettings::clampIndirect at surfaces after the first, else 0.
glm::vec3 pointLightUnshadowed(const RenderScene& rs, const Bsdf& bsdf, const GpuLight& light, const glm::vec3& pos,
                               const glm::vec3& origin, const glm::vec3& ng, const glm::vec3& wo, float minDist2, glm::vec3& wi,
                               float& dist) {
  const glm::vec3 d = pos - origin;
  const float dist2 = glm::dot(d, d);
  dist = std::sqrt(dist2);
  wi = d / dist;
  float pdf;
  const glm::vec3 f = bsdfEval(bsdf, ng, wo, wi, pdf);
  const float cone = faithful::spotTerm(light, wi);
  if (pdf == 0.0f || cone == 0.0f) return glm::vec3(0.0f);
  const glm::vec3 irradiance = physical::colour(light.color) * physical::falloff(light, dist2) * clampedShare(dist2, minDist2) *
      rs.world.range * kPhysicalPointScale * cone;
  return f * irradiance * glm::dot(bsdf.n, wi);
}

#if defined(__SSE2__)
// physical::selectionWeight of four lights at once, lane by lane its float expressions in its order (SSE's
// add, mul, div and sqrt round as the scalar ones do), so each weight is the same float: a hit
// weighs its cell's 32 near lights, and one at a time they took a fifth of a path's time.
[[gnu::always_inline]] inline __m128 selectionWeights(const std::array<const GpuLight*, 4>& l, const glm::vec3& origin,
                                                      const glm::vec3& n) {
  const auto lanes = [&l](auto field) { return _mm_setr_ps(field(*l[0]), field(*l[1]), field(*l[2]), field(*l[3])); };
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 dx = _mm_sub_ps(lanes([](const GpuLight& g) { return g.origin.x; }), _mm_set1_ps(origin.x));
  const __m128 dy = _mm_sub_ps(lanes([](const GpuLight& g) { return g.origin.y; }), _mm_set1_ps(origin.y));
  const __m128 dz = _mm_sub_ps(lanes([](const GpuLight& g) { return g.origin.z; }), _mm_set1_ps(origin.z));
  const __m128 dist2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
  const __m128 dist = _mm_sqrt_ps(dist2);
  const __m128 wx = _mm_div_ps(dx, dist), wy = _mm_div_ps(dy, dist), wz = _mm_div_ps(dz, dist);
  const auto dot = [&](const __m128& x, const __m128& y, const __m128& z) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, wx), _mm_mul_ps(y, wy)), _mm_mul_ps(z, wz));
  };
  const __m128 cosSurface = dot(_mm_set1_ps(n.x), _mm_set1_ps(n.y), _mm_set1_ps(n.z));
  // physical::falloff: clamp(1 - x2^2, 0, 1) as std::clamp takes it (a NaN stays NaN).
  const __m128 invReach = lanes([](const GpuLight& g) { return g.physicalInvReach; });
  const __m128 x2 = _mm_mul_ps(_mm_mul_ps(dist2, invReach), invReach);
  const __m128 w = _mm_min_ps(one, _mm_max_ps(zero, _mm_sub_ps(one, _mm_mul_ps(x2, x2))));
  const __m128 falloff = _mm_div_ps(_mm_mul_ps(lanes([](const GpuLight& g) { return g.physicalIntensity; }), _mm_mul_ps(w, w)), dist2);
  // faithful::spotTerm's branches as masks. Four lights without a cone (nearly every Quake
  // light) skip the cone's gathers and its division: spotTerm is 1 for each of them.
  const __m128 cosOuter = lanes([](const GpuLight& g) { return g.cosOuter; });
  const __m128 noCone = _mm_cmplt_ps(cosOuter, _mm_set1_ps(-1.0f));
  __m128 spot = one;
  if (_mm_movemask_ps(noCone) != 0xf) {
    const __m128 cosInner = lanes([](const GpuLight& g) { return g.cosInner; });
    const __m128 cosAxis =
        _mm_sub_ps(zero,
                   dot(lanes([](const GpuLight& g) { return g.direction.x; }), lanes([](const GpuLight& g) { return g.direction.y; }),
                       lanes([](const GpuLight& g) { return g.direction.z; })));
    const __m128 fade = _mm_div_ps(_mm_sub_ps(cosAxis, cosOuter), _mm_sub_ps(cosInner, cosOuter));
    const __m128 inCone = _mm_or_ps(_mm_and_ps(_mm_cmpge_ps(cosAxis, cosInner), one), _mm_andnot_ps(_mm_cmpge_ps(cosAxis, cosInner), fade));
    const __m128 cone = _mm_andnot_ps(_mm_cmplt_ps(cosAxis, cosOuter), inCone);
    spot = _mm_or_ps(_mm_and_ps(noCone, one), _mm_andnot_ps(noCone, cone));
  }
  const __m128 weight =
      _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(lanes([](const GpuLight& g) { return physical::selectionColour(g); }), falloff), spot), cosSurface);
  // selectionWeight's early zeros: no distance, or the light behind the surface's plane.
  const __m128 lit = _mm_and_ps(_mm_cmpgt_ps(dist2, zero), _mm_cmpnle_ps(cosSurface, zero));
  return _mm_and_ps(lit, weight);
}
#endif

glm::vec3 sunContribution(const RenderScene& rs, const Bsdf& bsdf, const GpuLight& light, const glm::vec3& origin, const glm::vec3& ng,
                          const glm::vec3& wo, Rng& rng) {
  glm::vec3 wi = -light.direction;
  if (light.deviance > 0.0f) wi = sampleCone(wi, light.deviance, rng.next2());
  float pdf;
  const glm::vec3 f = bsdfEval(bsdf, ng, wo, wi, pdf);
  if (pdf == 0.0f) return glm::vec3(0.0f);
  // A sun with `_suntexture` shines only through sky faces of that texture, as in faithful mode.
  if (!reachesSky(rs, Ray{origin, 0.0f, wi, std::numeric_limits<float>::infinity()}, LightingMode::Physical, light.skyMaterial))
    return glm::vec3(0.0f);
  return f * physical::colour(light.color) * light.value * rs.world.range * kPhysicalSunScale * glm::dot(bsdf.n, wi);
}

// One point light or sun with its own shadow ray (a jittered copy where it has _deviance); zero
// for the lights physical mode draws otherwise or not at all.
glm::vec3 oneLightShadowed(const RenderScene& rs, const Bsdf& bsdf, const GpuLight& light, const glm::vec3& origin, const glm::vec3& ng,
                           const glm::vec3& wo, float minDist2, Rng& rng) {
  if (light.value <= 0.0f) return glm::vec3(0.0f); // negative lights have no physical meaning
  if (light.type == uint32_t(LightType::Sun)) return sunContribution(rs, bsdf, light, origin, ng, wo, rng);
  if (light.type != uint32_t(LightType::Point) || light.formula == uint32_t(LightFormula::LocalMin)) return glm::vec3(0.0f);
  if (light.flags & kLightFlagFromSurface) return glm::vec3(0.0f); // its faces are area emitters here
  const glm::vec3 pos = jitteredOrigin(light, rng);
  glm::vec3 wi;
  float dist;
  const glm::vec3 c = pointLightUnshadowed(rs, bsdf, light, pos, origin, ng, wo, minDist2, wi, dist);
  if (c == glm::vec3(0.0f) || occluded(rs, Ray{origin, 0.0f, wi, dist}, LightingMode::Physical)) return glm::vec3(0.0f);
  return c;
}

// Every point light and sun, each with its own shadow ray: the reference for selection.
glm::vec3 allLightsExhaustive(const RenderScene& rs, const Bsdf& bsdf, const glm::vec3& origin, const glm::vec3& ng, const glm::vec3& wo,
                              float minDist2, Rng& rng) {
  glm::vec3 l(0.0f);
  for (const GpuLight& light : rs.lights) l += oneLightShadowed(rs, bsdf, light, origin, ng, wo, minDist2, rng);
  return l;
}

// origin's near list, at most kPhysicalNearLights long (all of it: the grid lists no more), so
// that its weights fit the pick's array.
std::span<const uint32_t> nearLights(const RenderScene& rs, const glm::vec3& origin) {
  const std::span<const uint32_t> listed = rs.lightGrid.physicalNearLights(origin);
  return listed.first(std::min<size_t>(listed.size(), kPhysicalNearLights));
}

// selectionWeight of each near light, into weights[0, near.size()); past that the SSE stores
// leave copies of the last weight, which are never read. Inlined into the pick, as the loop was
// before tests needed it on its own.
[[gnu::always_inline]] inline void nearWeights(const RenderScene& rs, std::span<const uint32_t> near, const glm::vec3& origin,
                                               const glm::vec3& n, std::array<float, kPhysicalNearLights>& weights) {
#if defined(__SSE2__)
  static_assert(kPhysicalNearLights % 4 == 0, "the weights are stored four at a time");
  for (size_t k = 0; k < near.size(); k += 4) {
    std::array<const GpuLight*, 4> four;
    for (size_t j = 0; j < 4; ++j) four[j] = &rs.lights[near[std::min(k + j, near.size() - 1)]];
    _mm_storeu_ps(weights.data() + k, selectionWeights(four, origin, n));
  }
#else
  for (size_t k = 0; k < near.size(); ++k) weights[k] = physical::selectionWeight(rs.lights[near[k]], origin, n);
#endif
}

// Light selection's probability of the near list (the rest goes to a uniform pick among the
// cell's other lights in reach, so that a light missing from the near list can still be picked:
// unbiased).
constexpr float kNearListProbability = BT_NEAR_LIST_PROBABILITY;

// Physical mode's pick (IntegratorSettings::PhysicalPick::NearList), a one-sample mixture of two
// strategies (Veach's "balance" pdf):
//   near:    the cell's near list (light_grid.h), by selectionWeight at the hit's origin;
//   uniform: one of the cell's other lights in reach (physicalRestLights), 1 / count.
// The two lists are disjoint: pdf(light) = P(near) * weight / nearTotal for a near light,
// (1 - P(near)) / count for another; P(near) is 1 where no other light is in reach, 0 where no
// near light lights the point.
// Random numbers: the strategy, then the pick.
LightPick pickFromNearList(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& n, Rng& rng) {
  const std::span<const uint32_t> rest = rs.lightGrid.physicalRestLights(origin);
  const std::span<const uint32_t> near = nearLights(rs, origin);
  // Each weight once: the pick's walk below reads them again (a fifth of a path's time went to
  // computing them twice, bench/README.md issue 18 session 26).
  std::array<float, kPhysicalNearLights> weights;
  nearWeights(rs, near, origin, n, weights);
  float nearTotal = 0.0f;
  for (size_t k = 0; k < near.size(); ++k) nearTotal += weights[k];
  const float uStrategy = rng.next(), uPick = rng.next();
  const float nearProbability = nearTotal > 0.0f ? (rest.empty() ? 1.0f : kNearListProbability) : 0.0f;
  if (nearProbability == 0.0f && rest.empty()) return {};

  uint32_t chosen = 0;
  float chosenWeight = 0.0f; // its near-list weight, 0 when not listed
  if (uStrategy < nearProbability) {
    // The entry whose cumulative interval holds the target (the last one with weight when
    // rounding leaves the target past the end).
    const float target = uPick * nearTotal;
    float cumulative = 0.0f;
    for (size_t k = 0; k < near.size(); ++k) {
      const float w = weights[k];
      if (w <= 0.0f) continue;
      chosen = near[k], chosenWeight = w;
      cumulative += w;
      if (cumulative > target) break;
    }
  } else {
    chosen = rest[std::min(uint32_t(uPick * float(rest.size())), uint32_t(rest.size()) - 1)];
  }
  const float pdf =
      uStrategy < nearProbability ? nearProbability * chosenWeight / nearTotal : (1.0f - nearProbability) / float(rest.size());
  return {pdf > 0.0f, chosen, pdf};
}

// Suns one by one (there are at most a few), then ONE point light, divided by the probability
// of picking it: an unbiased estimate of the sum over all of them with one shadow ray instead
// of hundreds. The pick (the near lists, or the light tree: light_tree.h) weighs lights at
// their own origin and the shading normal, so it does not depend on the light's _deviance
// jitter, which is drawn for the chosen light only. Random numbers per hit, in order: the
// suns', the pick's (two for the near lists, one for the tree), the chosen light's jitter (3,
// when soft); light_select.glsl draws the same as the near lists.
glm::vec3 allLightsSelected(const RenderScene& rs, const IntegratorSettings& settings, const Bsdf& bsdf, const glm::vec3& origin,
                            const glm::vec3& ng, const glm::vec3& wo, float minDist2, int depth, Rng& rng) {
  glm::vec3 l(0.0f);
  for (uint32_t i : rs.lightGrid.fixedLights()) {
    const GpuLight& light = rs.lights[i];
    if (light.type == uint32_t(LightType::Sun) && light.value > 0.0f) l += sunContribution(rs, bsdf, light, origin, ng, wo, rng);
  }
  rng.at(depth, BT_DIM_LIGHT_PICK);
  const LightPick pick = settings.physicalPick == IntegratorSettings::PhysicalPick::Tree
      ? pickLightFromTree(rs.lightGrid.physicalTree, origin, bsdf.n, rng.next())
      : pickFromNearList(rs, origin, bsdf.n, rng);
  rng.atPcg();
  if (!pick.found) return l;

  const GpuLight& light = rs.lights[pick.light];
  rng.at(depth, BT_DIM_LIGHT_POINT);
  const glm::vec3 pos = jitteredOrigin(light, rng);
  rng.atPcg();
  glm::vec3 wi;
  float dist;
  const glm::vec3 c = pointLightUnshadowed(rs, bsdf, light, pos, origin, ng, wo, minDist2, wi, dist);
  if (c != glm::vec3(0.0f) && !occluded(rs, Ray{origin, 0.0f, wi, dist}, LightingMode::Physical)) l += c / pick.pdf;
  return l;
}

// Direct light at a surface by next-event estimation: point lights and suns, then one emitter
// triangle (MIS-weighted against BSDF sampling). Rays leave from the face (ng), not from where
// a normal map pretends it is. `depth`: the path's surface, 0 the camera's (the firefly clamp spares
// it; Rng::at places its draws by it).
glm::vec3 directLight(const RenderScene& rs, const IntegratorSettings& settings, const Bsdf& bsdf, const glm::vec3& p, const glm::vec3& ng,
                      const glm::vec3& wo, int depth, Rng& rng) {
  const glm::vec3 origin = offsetRayOrigin(p, ng);
  const float minDist2 = depth > 0 ? settings.clampIndirect * settings.clampIndirect : 0.0f;
  glm::vec3 l = settings.lightSelection ? allLightsSelected(rs, settings, bsdf, origin, ng, wo, minDist2, depth, rng)
                                        : allLightsExhaustive(rs, bsdf, origin, ng, wo, minDist2, rng);

  if (!rs.emitters.empty()) {
    rng.at(depth, BT_DIM_EMITTER);
    const GpuEmitter& e = rs.emitters[pickEmitter(rs, rng.next())];
    const glm::vec3 q = sampleTriangle(e.v0, e.v1, e.v2, rng.next2());
    rng.atPcg();
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

// Worldspawn minlight (`light`, `_minlight`): the game's floor under every luxel, the same value
// on every face, so what the game's display shows of it is known exactly: `texture` (the sRGB
// texel) times the stored floor over the display's one, in the texture's gamma space, as faithful
// mode shows a face lit by it alone. No one display match fits a floor: at `_minlight 100` (0.39
// of the one) the game shows 0.15 of a mid-grey texture's linear colour, k x 0.39 gave 0.23.
// On what the camera sees only: the compiler's bounce does not bounce minlight either
// (lighting/README.md, "Physical mode").
glm::vec3 minlightRadiance(const RenderScene& rs, const glm::vec3& texture) {
  return srgbToLinear(texture * storedLuxel(rs, rs.world.minlight) / rs.world.overbrightOne);
}

Bsdf surfaceBsdf(const RenderScene& rs, const SurfaceHit& hit, const glm::vec3& wo) {
  const GpuMaterial& m = rs.materials[gpuFace(rs, hit.face).material];
  return Bsdf{srgbToLinear(glm::vec3(baseColorAt(rs, hit.face, hit.position))), m.roughness, m.metallic, (m.flags & kMaterialSpecular) != 0,
              shadingNormal(rs, hit, wo)};
}

glm::vec3 radiancePhysical(const RenderScene& rs, const IntegratorSettings& settings, Ray ray, Rng& rng) {
  glm::vec3 l(0.0f), throughput(1.0f);
  float prevBsdfPdf = 0.0f; // 0: camera ray (no MIS weight on what it sees)
  for (int depth = 0;; ++depth) {
    SurfaceHit hit = traceVisible(rs, ray);
    // A translucent liquid is drawn with probability self / (self + behind), else the ray goes
    // on behind it; weighted by self + behind, the mean is the engine's blend (physical opacity).
    // Light that crosses it takes the liquid's tint (lighting/liquids.h liquidTint).
    for (LiquidBlend blend = physicalSurfaceBlend(rs, hit); blend.behind > 0.0f; blend = physicalSurfaceBlend(rs, hit)) {
      const float total = blend.self + blend.behind;
      throughput *= total;
      if (rng.next() * total < blend.self) break;
      const GpuMaterial& liquid = rs.materials[gpuFace(rs, hit.face).material];
      l += throughput * liquidAddedRadiance(liquid); // an additive surface's light, seen through
      throughput *= liquidTint(liquid);
      ray.tMin = continueRayAfter(hit.t);
      hit = traceVisible(rs, ray);
    }
    if (!hit.found) break; // the void outside a level is black
    const uint32_t flags = rs.faceFlags[hit.face];
    if (flags & kFaceSky) {
      // The camera sees the sky as the game draws it: the level's sky images by the ray's
      // direction, else the face's texture. After a bounce the sky is the light the compiler
      // gives it, the dome (`_sunlight2`, `_sunlight3`) and nothing else: its picture lights
      // nothing in the game, and a sky window of a level without a dome stays dark
      // (lighting/README.md, "Physical mode").
      if (depth > 0) {
        l += throughput * skyDomeRadiance(rs, ray.direction);
      } else {
        l += throughput *
            (rs.sky.size > 0 ? skyRadiance(rs.sky, ray.direction) : srgbToLinear(glm::vec3(baseColorAt(rs, hit.face, hit.position))));
      }
      break;
    }
    // Without `_litwater` the game draws liquids unlit, at their texture: the camera sees them
    // so, neither lit nor lighting (the light they give is in the level's lights and emitters,
    // lava's glow included); rays after a bounce see them as any surface (lighting/README.md).
    if (depth == 0 && (flags & kFaceLiquid) && !rs.world.litwater) {
      l += throughput * srgbToLinear(glm::vec3(baseColorAt(rs, hit.face, hit.position)));
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

    const Bsdf bsdf = surfaceBsdf(rs, hit, wo);
    if (depth == 0 && rs.world.minlight != glm::vec3(0.0f))
      l += throughput * minlightRadiance(rs, glm::vec3(baseColorAt(rs, hit.face, hit.position)));
    l += throughput * directLight(rs, settings, bsdf, hit.position, n, wo, depth, rng);

    rng.at(depth, BT_DIM_BSDF);
    const glm::vec3 wi = bsdfSample(bsdf, wo, rng);
    rng.atPcg();
    float pdf;
    const glm::vec3 f = bsdfEval(bsdf, n, wo, wi, pdf);
    if (pdf <= 0.0f) break;
    throughput *= f * glm::dot(bsdf.n, wi) / pdf;
    prevBsdfPdf = pdf;

    // Russian roulette after three bounces, survival by throughput.
    if (depth >= 3) {
      const float survive = std::min(0.95f, std::max({throughput.x, throughput.y, throughput.z}));
      rng.at(depth, BT_DIM_ROULETTE);
      const float u = rng.next();
      rng.atPcg();
      if (u >= survive) break;
      throughput /= survive;
    }
    ray = Ray{offsetRayOrigin(hit.position, n), 0.0f, wi, std::numeric_limits<float>::infinity()};
  }
  return l;
}

} // namespace

glm::vec3 radiance(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, Rng& rng) {
  if (settings.mode == LightingMode::Faithful) return radianceFaithful(rs, settings, ray, rng);
  return radiancePhysical(rs, settings, ray, rng);
}

std::vector<float> nearListWeights(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& n) {
  const std::span<const uint32_t> near = nearLights(rs, origin);
  std::array<float, kPhysicalNearLights> weights;
  nearWeights(rs, near, origin, n, weights);
  return {weights.begin(), weights.begin() + std::ptrdiff_t(near.size())};
}

PhysicalShares physicalLightShares(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, int samples, Rng& rng) {
  PhysicalShares out;
  out.perLight.assign(rs.lights.size(), glm::vec3(0.0f));
  out.samples = std::max(samples, 1);
  for (int i = 0; i < out.samples; ++i) out.shown += radiancePhysical(rs, settings, ray, rng);
  out.shown /= float(out.samples);
  glm::vec3 direct(0.0f);
  const SurfaceHit hit = traceVisible(rs, ray);
  if (hit.found && !(rs.faceFlags[hit.face] & (kFaceSky | kFaceLiquid))) {
    const glm::vec3 wo = -ray.direction;
    const Bsdf bsdf = surfaceBsdf(rs, hit, wo);
    const glm::vec3 origin = offsetRayOrigin(hit.position, hit.normal);
    out.minlight = minlightRadiance(rs, glm::vec3(baseColorAt(rs, hit.face, hit.position)));
    for (size_t i = 0; i < rs.lights.size(); ++i) {
      const GpuLight& light = rs.lights[i];
      // A soft light (a sun's penumbra, _deviance) averaged over as many draws as the paths.
      const int draws = light.deviance > 0.0f ? out.samples : 1;
      for (int k = 0; k < draws; ++k) out.perLight[i] += oneLightShadowed(rs, bsdf, light, origin, hit.normal, wo, 0.0f, rng);
      out.perLight[i] /= float(draws);
      direct += out.perLight[i];
    }
  }
  out.rest = out.shown - direct - out.minlight;
  return out;
}

} // namespace bt

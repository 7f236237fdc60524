#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef BT_TEXTURES_BINDLESS
#extension GL_ARB_bindless_texture : require
#endif
// One sample per pixel of the integrator in renderer/cpu/integrator.cpp (faithful and
// physical modes), added to a running sum: progressive accumulation, the mean read back as
// sum / samples. Sample n of pixel (x, y) draws from pixelRng(x, y, n, seed) like the CPU's.
#include "scene_buffers.glsl"
#include "textures.glsl"
#include "trace.glsl"
#include "visible.glsl"
#include "camera.glsl"
#include "sampling.glsl"
#include "faithful.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform image2D accumulation; // rgb: sum of samples

// Physical-mode scale from Quake light units (renderer/cpu/integrator.h).
const float PHYSICAL_POINT_SCALE = PI * 128.0;
const float PHYSICAL_SUN_SCALE = PI / 128.0;

vec2 textureUv(uint face, vec3 p) { return faceUv(faces[face], materials[faces[face].material], p); }
vec4 baseColorAt(uint face, vec3 p) { return materialBaseColor(materials[faces[face].material], textureUv(face, p)); }
vec3 emissiveAt(uint face, vec3 p) {
  GpuMaterial m = materials[faces[face].material];
  if ((m.flags & MATERIAL_HAS_EMISSIVE) == 0u) return vec3(0.0);
  return sampleEmissive(m, textureUv(face, p)).rgb;
}

uint pickEmitter(float u) {
  uint lo = 0u, hi = world.emitterCount - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (emitters[mid].cdf < u) lo = mid + 1u;
    else hi = mid;
  }
  return lo;
}

// One of ericw-tools' `_samples` jittered copies of a point light: uniform in the cube of
// half-size `_deviance` (renderer/cpu/integrator.cpp jitteredOrigin).
vec3 jitteredOrigin(GpuLight light, inout Rng rng) {
  if (light.deviance <= 0.0) return light.origin;
  vec3 u = vec3(rngNext(rng), rngNext(rng), rngNext(rng));
  return light.origin + light.deviance * (2.0 * u - 1.0);
}

// ---- faithful mode ---------------------------------------------------------------------

vec3 faithfulLightAt(vec3 p, vec3 n, inout Rng rng) {
  vec3 origin = offsetPoint(p, n);
  vec3 sum = vec3(0.0);
  vec3 localMin = vec3(0.0);
  for (uint i = 0u; i < world.lightCount; ++i) {
    GpuLight light = lights[i];
    if (light.type == LIGHT_POINT) {
      vec3 pos = jitteredOrigin(light, rng);
      vec3 d = pos - p;
      float dist = length(d);
      if (dist <= 0.0) continue;
      float value = pointLightValue(light, n, d / dist, dist, world.scaledist);
      if (value == 0.0) continue;
      vec3 toLight = pos - origin;
      float len = length(toLight);
      if (occluded(origin, toLight / len, len, false)) continue;
      if (light.formula == FORMULA_LOCAL_MIN) localMin = max(localMin, value * light.color);
      else sum += value * light.color;
    } else if (light.type == LIGHT_SUN) {
      vec3 toSun = -light.direction;
      if (light.deviance > 0.0) toSun = sampleCone(toSun, light.deviance, rngNext2(rng));
      float value = sunValue(light, -toSun, n);
      if (value == 0.0) continue;
      if (!reachesSky(origin, toSun, false)) continue;
      sum += value * light.color;
    } else if (light.type == LIGHT_DOME) {
      vec3 dir = sampleUniformHemisphere(light.direction, rngNext2(rng));
      float cosIncidence = dot(dir, n);
      if (cosIncidence <= 0.0) continue;
      if (!reachesSky(origin, dir, false)) continue;
      sum += light.value * angleTerm(cosIncidence, light.anglescale) * light.color;
    }
  }

  sum = max(sum, localMin);
  return max(sum, world.minlight);
}

// _bounce N: light reflected off other surfaces (light units), iterative form of the CPU's
// recursion: each level multiplies the colour seen so far.
vec3 faithfulBounce(vec3 p, vec3 n, inout Rng rng) {
  vec3 total = vec3(0.0);
  vec3 weight = vec3(world.bouncescale);
  for (int depth = world.faithfulBounces; depth > 0; --depth) {
    vec3 dir = sampleCosineHemisphere(n, rngNext2(rng));
    SurfaceHit hit = traceVisible(offsetPoint(p, n), dir);
    if (!hit.found || (faces[hit.face].flags & FACE_SKY) != 0u) break;
    vec3 color = baseColorAt(hit.face, hit.position).rgb;
    weight *= color;
    total += weight * faithfulLightAt(hit.position, hit.normal, rng);
    weight *= world.bouncescale;
    p = hit.position;
    n = hit.normal;
  }
  return total;
}

vec3 radianceFaithful(vec3 origin, vec3 dir, inout Rng rng) {
  SurfaceHit hit = traceVisible(origin, dir);
  if (!hit.found) return vec3(0.0);
  uint flags = faces[hit.face].flags;
  vec3 texture = baseColorAt(hit.face, hit.position).rgb;
  // Quake draws sky and (without _litwater) liquids at the texture's own colour, unlit.
  if ((flags & FACE_SKY) != 0u || ((flags & FACE_LIQUID) != 0u && world.litwater == 0u)) return srgbToLinear(texture);

  vec3 light = max(faithfulLightAt(hit.position, hit.normal, rng), surfaceFaceMinlight(surfaceLights[faces[hit.face].material]));
  if (world.faithfulBounces > 0) light += faithfulBounce(hit.position, hit.normal, rng);
  // The compiler scales a coloured sum so its brightest channel fits in 255, keeping the hue.
  vec3 stored = light * world.range;
  float peak = max(stored.x, max(stored.y, stored.z));
  if (peak > 255.0) stored *= 255.0 / peak;
  stored = max(stored, vec3(0.0));
  // Engine: texture x lightmap / 128 in the texture's (gamma) space; fullbright texels unlit.
  vec3 display = max(texture * stored / OVERBRIGHT_ONE, emissiveAt(hit.face, hit.position));
  return srgbToLinear(display);
}

// ---- physical mode ---------------------------------------------------------------------

struct Bsdf {
  vec3 albedo;
  float roughness;
  float metallic;
  bool specular;
};

const float SPECULAR_LOBE_PROBABILITY = 0.5;

float ggxD(float noh, float alpha) {
  float a2 = alpha * alpha;
  float d = noh * noh * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}

float smithG1(float nov, float alpha) {
  float a2 = alpha * alpha;
  return 2.0 * nov / (nov + sqrt(a2 + (1.0 - a2) * nov * nov));
}

vec3 bsdfEval(Bsdf b, vec3 n, vec3 wo, vec3 wi, out float pdf) {
  float nol = dot(n, wi);
  float nov = dot(n, wo);
  pdf = 0.0;
  if (nol <= 0.0 || nov <= 0.0) return vec3(0.0);
  if (!b.specular) {
    pdf = nol / PI;
    return b.albedo / PI;
  }
  float alpha = max(b.roughness * b.roughness, 1e-3);
  vec3 h = normalize(wo + wi);
  float noh = max(dot(n, h), 0.0), voh = max(dot(wo, h), 1e-6);
  vec3 f0 = mix(vec3(0.04), b.albedo, b.metallic);
  vec3 fresnel = f0 + (1.0 - f0) * pow(1.0 - voh, 5.0);
  float d = ggxD(noh, alpha);
  vec3 spec = fresnel * d * smithG1(nol, alpha) * smithG1(nov, alpha) / (4.0 * nol * nov);
  vec3 diffuse = (1.0 - b.metallic) * b.albedo / PI;
  pdf = (1.0 - SPECULAR_LOBE_PROBABILITY) * nol / PI + SPECULAR_LOBE_PROBABILITY * d * noh / (4.0 * voh);
  return diffuse + spec;
}

vec3 bsdfSample(Bsdf b, vec3 n, vec3 wo, inout Rng rng) {
  if (!b.specular || rngNext(rng) >= SPECULAR_LOBE_PROBABILITY) return sampleCosineHemisphere(n, rngNext2(rng));
  float alpha = max(b.roughness * b.roughness, 1e-3);
  vec2 u = rngNext2(rng);
  float cosTheta = sqrt((1.0 - u.x) / (1.0 + (alpha * alpha - 1.0) * u.x));
  float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
  float phi = 2.0 * PI * u.y;
  vec3 h = toWorld(vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta), n);
  return reflect(-wo, h);
}

vec3 emittedRadiance(uint face, vec3 p) {
  vec3 le = srgbToLinear(emissiveAt(face, p));
  GpuLight tmpl = surfaceLights[faces[face].material];
  if (tmpl.value > 0.0) le += tmpl.color * tmpl.value * world.range * PHYSICAL_SUN_SCALE;
  return le;
}

vec3 skyDomeRadiance(vec3 dir) {
  vec3 l = vec3(0.0);
  for (uint i = 0u; i < world.lightCount; ++i)
    if (lights[i].type == LIGHT_DOME && dir.z * lights[i].direction.z > 0.0)
      l += lights[i].color * lights[i].value * world.range * PHYSICAL_SUN_SCALE / PI;
  return l;
}

vec3 directLight(Bsdf bsdf, vec3 p, vec3 n, vec3 wo, inout Rng rng) {
  vec3 origin = offsetPoint(p, n);
  vec3 l = vec3(0.0);
  for (uint i = 0u; i < world.lightCount; ++i) {
    GpuLight light = lights[i];
    if (light.value <= 0.0) continue; // negative lights have no physical meaning
    if (light.type == LIGHT_POINT) {
      if (light.formula == FORMULA_LOCAL_MIN) continue;
      if ((light.flags & LIGHT_FLAG_FROM_SURFACE) != 0u) continue; // its faces are area emitters here
      vec3 pos = jitteredOrigin(light, rng);
      vec3 d = pos - origin;
      float dist2 = dot(d, d);
      float dist = sqrt(dist2);
      vec3 wi = d / dist;
      float pdf;
      vec3 f = bsdfEval(bsdf, n, wo, wi, pdf);
      float cone = spotTerm(light, wi);
      if (pdf == 0.0 || cone == 0.0) continue;
      if (occluded(origin, wi, dist, true)) continue;
      vec3 intensity = light.color * light.value * world.range * PHYSICAL_POINT_SCALE * cone;
      l += f * intensity * dot(n, wi) / dist2;
    } else if (light.type == LIGHT_SUN) {
      vec3 wi = -light.direction;
      if (light.deviance > 0.0) wi = sampleCone(wi, light.deviance, rngNext2(rng));
      float pdf;
      vec3 f = bsdfEval(bsdf, n, wo, wi, pdf);
      if (pdf == 0.0) continue;
      if (!reachesSky(origin, wi, true)) continue;
      l += f * light.color * light.value * world.range * PHYSICAL_SUN_SCALE * dot(n, wi);
    }
  }

  if (world.emitterCount > 0u) {
    GpuEmitter e = emitters[pickEmitter(rngNext(rng))];
    vec3 q = sampleTriangle(e.v0, e.v1, e.v2, rngNext2(rng));
    vec3 d = q - origin;
    float dist2 = dot(d, d);
    float dist = sqrt(dist2);
    vec3 wi = d / dist;
    float cosLight = -dot(faces[e.face].normal, wi);
    float bsdfPdf;
    vec3 f = bsdfEval(bsdf, n, wo, wi, bsdfPdf);
    if (cosLight > 0.0 && bsdfPdf > 0.0) {
      float lightPdf = dist2 / (cosLight * world.emitterArea);
      // Stop just short of the emitter so that its own face does not count as a blocker.
      if (!occluded(origin, wi, dist - 2.0 * SURFACE_OFFSET, true)) {
        vec3 le = emittedRadiance(e.face, q);
        l += f * le * dot(n, wi) * powerHeuristic(lightPdf, bsdfPdf) / lightPdf;
      }
    }
  }
  return l;
}

vec3 radiancePhysical(vec3 origin, vec3 dir, inout Rng rng) {
  vec3 l = vec3(0.0), throughput = vec3(1.0);
  float prevBsdfPdf = 0.0; // 0: camera ray (no MIS weight on what it sees)
  for (int depth = 0;; ++depth) {
    SurfaceHit hit = traceVisible(origin, dir);
    if (!hit.found) break; // the void outside a level is black
    GpuFace face = faces[hit.face];
    if ((face.flags & FACE_SKY) != 0u) {
      l += throughput * (srgbToLinear(baseColorAt(hit.face, hit.position).rgb) + skyDomeRadiance(dir));
      break;
    }
    vec3 n = hit.normal;
    vec3 wo = -dir;
    if ((face.flags & FACE_EMISSIVE) != 0u) {
      vec3 le = emittedRadiance(hit.face, hit.position);
      float weight = 1.0;
      if (prevBsdfPdf > 0.0) {
        float cosLight = max(dot(n, wo), 1e-6);
        float lightPdf = hit.t * hit.t / (cosLight * world.emitterArea);
        weight = powerHeuristic(prevBsdfPdf, lightPdf);
      }
      l += throughput * le * weight;
    }
    if (depth >= world.bounces + 1) break;

    GpuMaterial m = materials[face.material];
    Bsdf bsdf = Bsdf(srgbToLinear(baseColorAt(hit.face, hit.position).rgb), m.roughness, m.metallic,
                     (m.flags & MATERIAL_SPECULAR) != 0u);
    l += throughput * directLight(bsdf, hit.position, n, wo, rng);

    vec3 wi = bsdfSample(bsdf, n, wo, rng);
    float pdf;
    vec3 f = bsdfEval(bsdf, n, wo, wi, pdf);
    if (pdf <= 0.0) break;
    throughput *= f * dot(n, wi) / pdf;
    prevBsdfPdf = pdf;

    // Russian roulette after three bounces, survival by throughput.
    if (depth >= 3) {
      float survive = min(0.95, max(throughput.x, max(throughput.y, throughput.z)));
      if (rngNext(rng) >= survive) break;
      throughput /= survive;
    }
    origin = offsetPoint(hit.position, n);
    dir = wi;
  }
  return l;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, camera.imageSize))) return;
  Rng rng = pixelRng(uint(pixel.x), uint(pixel.y), camera.frameIndex, camera.seed);
  vec2 jitter = rngNext2(rng);
  vec3 dir = cameraRayDirection(vec2(pixel) + jitter);
  vec3 l = world.physical != 0u ? radiancePhysical(camera.origin, dir, rng) : radianceFaithful(camera.origin, dir, rng);
  vec4 sum = camera.frameIndex == camera.firstFrame ? vec4(0.0) : imageLoad(accumulation, pixel);
  // A NaN or infinite sample would poison the pixel for good; drop it, as the CPU does.
  if (!any(isnan(l)) && !any(isinf(l))) sum.rgb += l;
  imageStore(accumulation, pixel, sum);
}

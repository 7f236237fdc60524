#version 450
#extension GL_GOOGLE_include_directive : require
#include "gl_bindings.glsl"
#include "denoise_constants.glsl" // BT_LUMINANCE_*: accumulate()'s second moment
#ifdef BT_TEXTURES_BINDLESS
#extension GL_ARB_bindless_texture : require
#endif
#ifdef BT_WAVEFRONT_SHADE
// The wavefront form exists to compile fast: without NVIDIA's loop unrolling its first image
// comes sooner for a few per cent of its physical samples/s (bench/README.md). The traversal,
// where unrolling pays most, is the trace kernel's and keeps it.
#pragma optionNV(unroll none)
#endif
// One sample per pixel of the integrator in renderer/cpu/integrator.cpp (faithful and
// physical modes), added to a running sum: progressive accumulation, the mean read back as
// sum / samples. Sample n of pixel (x, y) draws from pixelRng(x, y, n, seed) like the CPU's,
// in the same order (physical mode: pixelSampler, its draws placed at the same dimensions).
//
// Shape: one ray per loop iteration. GPU compilers (NVIDIA's above all) inline every call, so
// each place that calls the BVH traversal gets its own full copy of it; written as nested
// functions (camera ray -> surface -> each light's shadow ray -> bounce ray -> ...) the
// integrator held a dozen copies and took tens of seconds to compile. Here a Path carries what
// the CPU's recursion keeps on its stack, main() traces whatever ray the path waits for, at one
// call site, and advance() takes the result and sets up the next ray:
//   RAY_SURFACE (camera or bounce ray) -> the surface's lights, one RAY_SHADOW or RAY_SKY ray
//   each -> the next RAY_SURFACE, until the path ends.
#include "scene_buffers.glsl"
#include "textures.glsl"
#include "sky.glsl"
#include "trace.glsl"
#include "visible.glsl"
#include "camera.glsl"
#ifdef BT_LIGHTING_PHYSICAL
#define BT_LOW_DISCREPANCY // sampling.glsl: the Sobol dimensions of renderer/cpu's physical paths
#define BT_SAMPLE_INDEX camera.frameIndex
#endif
#include "sampling.glsl"
#include "faithful.glsl"
#include "light_select.glsl"
#include "lightmaps.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = BT_IMAGE_ACCUMULATION) uniform image2D accumulation; // rgb: sum of samples, a: of their luminance squared

// The lighting mode is fixed when the program is built (renderer/gl/gl_tracer.cpp builds one
// program per mode): each program then compiles only its own integrator, and the driver's
// compile time, seconds on llvmpipe, is not spent on code the render never runs.
#ifdef BT_LIGHTING_PHYSICAL
const bool PHYSICAL = true;
#else
const bool PHYSICAL = false;
#endif
// The same for the faithful program's optional parts (renderer/gl FaithfulFeatures): a level
// without suns and sky domes, or without _deviance, compiles without their code.
#if defined(BT_LIGHTING_PHYSICAL) || defined(BT_FAITHFUL_SKY)
const bool SKY_RAYS = true; // physical suns, faithful suns and domes
#else
const bool SKY_RAYS = false;
#endif

// Physical-mode scale from Quake light units (renderer/cpu/integrator.h).
const float PHYSICAL_POINT_SCALE = PI * BT_PHYSICAL_DISPLAY_MATCH / BT_PHYSICAL_LIGHT_UNIT; // integrator.h kPhysicalPointScale
const float PHYSICAL_SUN_SCALE = PI * BT_PHYSICAL_DISPLAY_MATCH / BT_PHYSICAL_LIGHT_UNIT;

vec2 textureUv(uint face, vec3 p) { return faceUv(faces[face], materials[faces[face].material], p); }
vec3 emissiveAt(uint face, vec3 p) {
  GlMaterial m = materials[faces[face].material];
  if ((m.flags & MATERIAL_HAS_EMISSIVE) == 0u) return vec3(0.0);
  return sampleEmissive(m, textureUv(face, p)).rgb;
}

#include "bsdf.glsl"

// lighting/physical_light.h colour: the compiler's colour as the game shows it, made linear
// (each channel's share of the brightest one through the sRGB curve, the brightest one kept).
// Only for the light a sample shades; selection reads the prepared GpuLight::physicalHueSum.
vec3 physicalColour(vec3 c) {
  float m = max(c.x, max(c.y, c.z));
  return m > 0.0 ? m * srgbToLinear(c / m) : vec3(0.0);
}

vec3 emittedRadiance(uint face, vec3 p) {
  vec3 le = srgbToLinear(emissiveAt(face, p));
  GpuLight tmpl = surfaceLights[faces[face].material];
  if (tmpl.value > 0.0) le += physicalColour(tmpl.color) * tmpl.value * world.range * PHYSICAL_SUN_SCALE;
  return le;
}

// Domes sit in the light grid's fixed list (renderer/cpu skyDomeRadiance): a ray that reaches
// the sky looks at a handful of lights, not at every light of the level.
vec3 skyDomeRadiance(vec3 dir) {
  vec3 l = vec3(0.0);
  for (uint k = 0u; k < lightGrid.fixedCount; ++k) {
    GpuLight light = lights[lightIndices[k]];
    if (light.type == LIGHT_DOME && dir.z * light.direction.z > 0.0)
      l += physicalColour(light.color) * light.value * world.range * PHYSICAL_SUN_SCALE / PI;
  }
  return l;
}

// ---- the path ----------------------------------------------------------------------------

const uint RAY_SURFACE = 0u; // camera or bounce ray: the next surface drawn (lighting traceVisible)
const uint RAY_SHADOW = 1u;  // to a light: is the segment blocked (occluded), any hit
const uint RAY_SKY = 2u;     // to the sun or the sky dome: does it reach a sky face (reachesSky)
const uint RAY_DIRT = 3u;    // faithful dirt: how far it gets before a face that blocks light (blockedDistance)

// What the CPU's recursion keeps on its stack; path_fields.glsl lists the fields.
#include "path_fields.glsl"
#define DECLARE_PATH_FIELD(type, name, kept, onLoad) type name;
struct Path {
  PATH_FIELDS(DECLARE_PATH_FIELD)
};

void setRay(inout Path path, uint kind, vec3 origin, vec3 dir, float tMax) {
  path.kind = kind;
  path.origin = origin;
  path.dir = dir;
  path.tMin = 0.0;
  path.tMax = tMax;
  path.passFlags = lightPassFlags(PHYSICAL);
  path.emitterFace = NO_FACE;
  path.skips = 0;
}

// ---- faithful mode ---------------------------------------------------------------------

// What dirt leaves of a light `dist` away at the current surface (1 without dirt).
float dirtFactor(Path path, GpuLight light, float dist) {
#ifdef BT_FAITHFUL_DIRT
  return lightDirtFactor(light, path.occlusion, dist);
#else
  return 1.0;
#endif
}

// ... and of the worldspawn minlight (_minlight_dirt).
float minlightDirtFactor(Path path) {
#ifdef BT_FAITHFUL_DIRT
  if (world.minlightDirt != 0u) return 1.0 - dirtAmount(path.occlusion, world.dirtGain, world.dirtScale);
#endif
  return 1.0;
}

#ifdef BT_FAITHFUL_DIRT
// The surface's next occlusion ray (lighting faithfulOcclusion): the fixed pattern, or for
// _dirtmode 1 a random direction of the cone, from 1 unit off the face.
void faithfulDirtRay(inout Path path, inout Rng rng) {
  vec3 v;
  if (world.dirtMode == 1u) {
    float u0 = rngNext(rng);
    float u1 = rngNext(rng);
    v = dirtRandomVector(u0, u1, world.dirtAngle);
  } else {
    v = dirtPatternVector(path.dirtRay, world.dirtAngle);
  }
  setRay(path, RAY_DIRT, path.position + path.normal * DIRT_SAMPLE_LIFT, dirtRayDirection(path.normal, v), world.dirtDepth);
  path.dirtRay++;
}
#endif

// One light of lighting/faithful_light.h LightSet::Grid at the current surface: false if it adds nothing
// here, else the ray that decides whether it does.
bool faithfulLightRay(inout Path path, GpuLight light, inout Rng rng) {
  vec3 p = path.position;
  bool twoSided = (faceFlags[path.face] & FACE_LIQUID) != 0u;
  path.pendingIsFloor = false;
  NEGATIVE_ONLY(path.pendingIsNegative = subtractedLight(light);)
  // The compiler's lighting channels: a point light lights only faces on one of its channels,
  // the sky the default channel's (lighting addFaithfulLight).
  if (((light.type == LIGHT_POINT ? light.lightChannels : DEFAULT_CHANNELS) & faceChannels(path.face)) == 0u) return false;
  if (light.type == LIGHT_POINT) {
    vec3 pos = jitteredOrigin(light, rng);
    vec3 d = pos - p;
    float dist = length(d);
    vec3 toLightDir = d / dist;
    if (!(dist >= NEAREST_LIGHT)) {
      dist = NEAREST_LIGHT, toLightDir = vec3(0.0, 0.0, 1.0);
      pos = p + toLightDir * dist;
    }
    vec3 n = facingNormal(path.normal, toLightDir, twoSided);
    float value = pointLightValue(light, n, toLightDir, dist, world.scaledist) * dirtFactor(path, light, dist);
    if (value == 0.0) return false;
    vec3 origin = offsetPoint(p, n);
    vec3 toLight = pos - origin;
    float len = length(toLight);
    setRay(path, RAY_SHADOW, origin, toLight / len, len);
    path.passFlags = shadowPassFlags(false, light.shadowChannels);
    path.pending = value * light.color;
    path.pendingIsFloor = light.formula == FORMULA_LOCAL_MIN;
    return true;
  }
#ifdef BT_FAITHFUL_SKY
  if (light.type == LIGHT_SUN) {
    vec3 toSun = -light.direction;
    if (light.deviance > 0.0) toSun = sampleCone(toSun, light.deviance, rngNext2(rng));
    vec3 n = facingNormal(path.normal, toSun, twoSided);
    float value = sunValue(light, -toSun, n) * dirtFactor(path, light, 0.0);
    if (value == 0.0) return false;
    setRay(path, RAY_SKY, offsetPoint(p, n), toSun, INFINITY);
    path.pending = value * light.color;
    return true;
  }
  if (light.type == LIGHT_DOME) {
    vec3 dir = sampleUniformHemisphere(light.direction, rngNext2(rng));
    vec3 n = facingNormal(path.normal, dir, twoSided);
    float cosIncidence = dot(dir, n);
    if (cosIncidence <= 0.0) return false;
    setRay(path, RAY_SKY, offsetPoint(p, n), dir, INFINITY);
    path.pending = light.value * angleTerm(cosIncidence, light.anglescale) * dirtFactor(path, light, 0.0) * light.color;
    return true;
  }
#endif
  return false;
}

#ifdef BT_FAITHFUL_BOUNCE_DRAW
// The draw among a cell's bounce lights, in programs built for a level with more bounce lights
// than the draw's rays (renderer/gl FaithfulFeatures): where no cell lists that many, every
// light has its own ray below, as the CPU gives each then too.
const uint NO_BOUNCE_DRAW = 0xffffffffu;

// A bounce light's unshadowed share at the current surface (lighting bounceShare): the gate
// applied, dirt not (it comes after the draw); weight, its brightest channel, 0 where it adds
// nothing; n, the side of the surface it lights.
struct BounceShare {
  vec3 rgb;
  float weight;
  float dist;
  vec3 n;
};

// lighting clearlyUnlit: behind the light's face, or the light behind a one-sided surface, at
// a cosine above 1e-4 (pointLightValue gives 0 there too), without a square root.
bool clearlyUnlit(GpuLight light, vec3 n, bool twoSided, vec3 d) {
  const float COS2 = 1e-8;
  float d2 = dot(d, d);
  float away = dot(light.direction, d);
  if (away > 0.0 && away * away > COS2 * d2) return true;
  float facing = dot(n, d);
  return !twoSided && facing < 0.0 && facing * facing > COS2 * d2;
}

BounceShare bounceShare(Path path, GpuLight light) {
  BounceShare s = BounceShare(vec3(0.0), 0.0, 0.0, vec3(0.0));
  vec3 d = light.origin - path.position;
  bool twoSided = (faceFlags[path.face] & FACE_LIQUID) != 0u;
  if (clearlyUnlit(light, path.normal, twoSided, d)) return s;
  s.dist = length(d);
  if (!(s.dist > 0.0)) return s;
  vec3 toLight = d / s.dist;
  s.n = facingNormal(path.normal, toLight, twoSided);
  float value = pointLightValue(light, s.n, toLight, s.dist, world.scaledist);
  if (!(value > 0.0)) return s;
  s.rgb = value * light.color;
  s.weight = max(max(max(s.rgb.x, s.rgb.y), s.rgb.z), 0.0);
  return s;
}

// The draw begins at list position `first`, the first of the cell's bounce lights: the first
// sweep (their total share and the last with one) and the first target.
void startBounceDraw(inout Path path, uint cell, uint first, uint count, inout Rng rng) {
  path.bounceFirst = first;
  path.bounceLast = NO_BOUNCE_DRAW;
  path.bounceDrawn = 0u;
  path.bounceTotal = 0.0;
  path.bounceCumulative = 0.0;
  for (uint k = first; k < count; ++k) {
    float w = bounceShare(path, lights[faithfulLight(cell, k)]).weight;
    if (w > 0.0) {
      path.bounceTotal += w;
      path.bounceLast = k;
    }
  }
  if (path.bounceLast != NO_BOUNCE_DRAW) path.bounceTarget = rngNext(rng) / float(BOUNCE_SHADOW_RAYS) * path.bounceTotal;
}

// The second sweep (lighting sampledBounceSum), from list position i on, to the next bounce
// light a target falls on: the targets on its share, one drawn per stratum, and one shadow ray
// for them all; false (the list done) when every target is placed.
bool faithfulBounceRay(inout Path path, uint cell, uint i, uint count, inout Rng rng) {
  uint end = path.bounceLast == NO_BOUNCE_DRAW ? i : path.bounceLast + 1u; // none with a share: nothing to draw
  for (; i < end && path.bounceDrawn < BOUNCE_SHADOW_RAYS; ++i) {
    GpuLight light = lights[faithfulLight(cell, i)];
    BounceShare s = bounceShare(path, light);
    if (!(s.weight > 0.0)) continue;
    path.bounceCumulative += s.weight;
    uint picks = 0u;
    while (path.bounceDrawn < BOUNCE_SHADOW_RAYS && (path.bounceTarget < path.bounceCumulative || i == path.bounceLast)) {
      picks++;
      path.bounceDrawn++;
      if (path.bounceDrawn < BOUNCE_SHADOW_RAYS)
        path.bounceTarget = (float(path.bounceDrawn) + rngNext(rng)) / float(BOUNCE_SHADOW_RAYS) * path.bounceTotal;
    }
    if (picks == 0u) continue;
    vec3 origin = offsetPoint(path.position, s.n);
    vec3 toLight = light.origin - origin;
    float len = length(toLight);
    setRay(path, RAY_SHADOW, origin, toLight / len, len);
    path.pending = s.rgb * dirtFactor(path, light, s.dist) *
                   (float(picks) * path.bounceTotal / (s.weight * float(BOUNCE_SHADOW_RAYS)));
    path.pendingIsFloor = false;
    NEGATIVE_ONLY(path.pendingIsNegative = false;)
    path.lightIndex = i + 1u;
    return true;
  }
  path.lightIndex = count; // every target placed: the rest of the list adds nothing
  return false;
}

// Light i of the faithful lists (light_select.glsl faithfulLight) at the current surface, in
// lighting/faithful_light.h LightSet::GridSampledBounce's way: its own ray, except the cell's bounce lights (last in
// its list) where there are more than BOUNCE_SHADOW_RAYS: those are drawn among.
bool faithfulListedLightRay(inout Path path, uint cell, uint i, uint count, inout Rng rng) {
  if (i < path.bounceFirst) {
    GpuLight light = lights[faithfulLight(cell, i)];
    bool inCell = i >= lightGrid.fixedCount + lightGrid.globalCount;
    if (!(inCell && light.formula == FORMULA_BOUNCE && count - i > BOUNCE_SHADOW_RAYS)) return faithfulLightRay(path, light, rng);
    startBounceDraw(path, cell, i, count, rng);
  }
  return faithfulBounceRay(path, cell, i, count, rng);
}
#endif

// What the compiler stores for `light` light units: light x _range, scaled so that its brightest
// channel fits in 255, keeping the hue (renderer/cpu storedLuxel).
vec3 storedLuxel(vec3 light) {
  vec3 stored = light * world.range;
  float peak = max(stored.x, max(stored.y, stored.z));
  if (peak > 255.0) stored *= 255.0 / peak;
  return max(stored, vec3(0.0));
}

// The pixel's value once a faithful path has ended: what the game would draw.
vec3 faithfulDisplay(Path path) {
  vec3 stored = storedLuxel(path.lit);
  // Engine: texture x lightmap / its overbright one (Quake 128, Quake 2 and Half-Life 255) in the
  // texture's (gamma) space; fullbright texels unlit.
  vec3 display = max(path.texture * shownLuxel(world.luxelDisplay, stored) / world.overbrightOne, path.fullbright);
  return srgbToLinear(display);
}

// A surface ray's result. False when the path ends here. A faithful path is the camera ray's
// surface only: the level's _bounce arrives there through its bounce lights (lighting/bounce.h).
bool faithfulSurface(inout Path path, SurfaceHit hit) {
  path.face = hit.found ? hit.face : NO_FACE, path.position = hit.position; // faithfulBehindLiquid's too
  if (!hit.found) return false;
  uint flags = faceFlags[hit.face];
  // The base colour and the emissive texels, read in one loop as in physicalSurface: each place
  // that reads a texture is a copy of the sampling code for the driver to compile.
  GlMaterial m = materials[faces[hit.face].material];
  vec2 uv = textureUv(hit.face, hit.position);
  vec3 base = vec3(0.5), emissive = vec3(0.0); // a material without a texture is mid grey (materialBaseColor)
  bool hasBase = (m.flags & MATERIAL_HAS_BASE) != 0u, hasEmissive = (m.flags & MATERIAL_HAS_EMISSIVE) != 0u;
  for (int k = hasBase ? 0 : 1; k <= (hasEmissive ? 1 : 0); ++k) {
    vec3 texel = sampleBaseOrEmissive(m, k == 1, uv).rgb;
    if (k == 0) base = texel;
    else emissive = texel;
  }
  path.texture = base;
  // Quake draws sky and (without _litwater) liquids at the texture's own colour, unlit; Quake 2
  // its glass too (render_scene.h engineDrawsUnlit).
  bool unlit = (flags & FACE_SKY) != 0u || ((flags & FACE_LIQUID) != 0u && world.litwater == 0u);
#ifdef BT_QUAKE2_GLASS
  unlit = unlit || glassAlpha(hit.face) > 0.0;
#endif
  if (unlit) {
    path.radiance = srgbToLinear(path.texture);
    return false;
  }
  path.fullbright = emissive;
#ifndef BT_NO_LUXELS
  // A baked face shows its luxels as the game shows its lightmap; the path ends here. The shade
  // kernel of a level with no baked face (renderer/gl FaithfulFeatures::luxels; a .map before its
  // bake) is built without this read: a tenth of its code, which the first image waits to compile.
  uvec2 baked = lightmapRange(hit.face);
  if (baked.y > 0u) {
    GpuFace f = faces[hit.face];
    vec3 d = hit.position - f.origin;
    vec3 stored = lightmapValue(baked, vec2(dot(d, f.tangent), dot(d, f.bitangent)));
    path.radiance = srgbToLinear(max(path.texture * stored * lightmapDisplayScale(), path.fullbright));
    return false;
  }
#endif
  path.normal = hit.normal;
  path.lightSum = vec3(0.0);
  path.lightFloor = vec3(0.0);
  NEGATIVE_ONLY(path.lightNegative = vec3(0.0);)
#ifdef BT_FAITHFUL_BOUNCE_DRAW
  path.bounceFirst = NO_BOUNCE_DRAW;
#endif
#ifdef BT_FAITHFUL_DIRT
  path.dirtRay = 0;
  path.dirtSum = 0.0;
  path.occlusion = 0.0;
#endif
  return true;
}

// The surface's lights are all done: the floors, then what the game would draw. The path ends
// (advance() calls this where physical mode samples its next bounce).
void faithfulPathEnd(inout Path path) {
  vec3 light = max(max(path.lightSum + world.ambient, path.lightFloor), world.minlight * minlightDirtFactor(path));
  // The _surface template's own faces: ericw-tools' face minlight (lighting faithfulFaceMinlight).
  path.lit = max(light, surfaceFaceMinlight(surfaceLights[faces[path.face].material]) * minlightDirtFactor(path));
  NEGATIVE_ONLY(path.lit = max(path.lit + path.lightNegative, vec3(0.0));) // after the floors (lighting applyFloors)
  path.radiance = faithfulDisplay(path);
}

// Whether a sun's ray that reached the sky reached one the sun shines through: with
// `_suntexture` (skyMaterial 1 + its material) only sky faces of that texture, not the level's
// outside (lighting reachesSky); 0 is any sky.
bool sunSeesItsSky(uint skyMaterial, uint face) {
  return skyMaterial == 0u || (face != NO_FACE && faces[face].material + 1u == skyMaterial);
}

#include "liquids.glsl" // faithfulBehindLiquid, physicalPassesLiquid
// ---- physical mode ---------------------------------------------------------------------

// A light of the fixed list (light_select.glsl) at the current surface: suns get a ray, the
// rest (domes, local minlights) light nothing here (renderer/cpu allLightsSelected).
bool physicalSunRay(inout Path path, GpuLight light, inout Rng rng) {
  if (light.type != LIGHT_SUN || light.value <= 0.0) return false;
  vec3 n = path.normal;
  vec3 origin = offsetPoint(path.position, n);
  vec3 wi = -light.direction;
  if (light.deviance > 0.0) wi = sampleCone(wi, light.deviance, rngNext2(rng));
  float pdf;
  vec3 f = bsdfEval(path.bsdf, n, path.wo, wi, pdf);
  if (pdf == 0.0) return false;
  setRay(path, RAY_SKY, origin, wi, INFINITY);
  path.pending = f * physicalColour(light.color) * light.value * world.range * PHYSICAL_SUN_SCALE * dot(path.bsdf.n, wi);
  return true;
}

// Whether the sky a physical sun's ray reached is one the sun shines through: with `_suntexture`
// only sky faces of that texture, not the level's outside (renderer/cpu sunContribution,
// lighting reachesSky). The ray's sun is the fixed list's entry before `lightIndex` (nextLightRay); read
// here, once the ray is back, so that the path carries nothing more across the trace.
bool physicalSunSeesItsSky(uint lightIndex, uint face) {
  return sunSeesItsSky(lights[lightIndices[lightIndex - 1u]].skyMaterial, face);
}

// One point light picked by light selection (light_select.glsl), divided by the probability
// of the pick; its _deviance jitter is drawn after the pick, as on the CPU.
bool physicalSelectedLightRay(inout Path path, inout Rng rng) {
  vec3 n = path.normal;
  vec3 origin = offsetPoint(path.position, n);
  rngAt(rng, path.depth, BT_DIM_LIGHT_PICK);
  SelectedLight chosen = selectPhysicalLight(origin, path.bsdf.n, rng);
  rngAtPcg(rng);
  if (!chosen.found) return false;
  GpuLight light = lights[chosen.light];
  rngAt(rng, path.depth, BT_DIM_LIGHT_POINT);
  vec3 d = jitteredOrigin(light, rng) - origin;
  rngAtPcg(rng);
  float dist2 = dot(d, d);
  float dist = sqrt(dist2);
  vec3 wi = d / dist;
  float pdf;
  vec3 f = bsdfEval(path.bsdf, n, path.wo, wi, pdf);
  float cone = spotTerm(light, wi);
  if (pdf == 0.0 || cone == 0.0) return false;
  float minDist2 = path.depth > 0 ? world.clampIndirect * world.clampIndirect : 0.0; // the firefly clamp (cpu clampedShare)
  float share = dist2 < minDist2 ? dist2 / minDist2 : 1.0;
  vec3 irradiance = physicalColour(light.color) * physicalFalloff(light, dist2) * share * world.range * PHYSICAL_POINT_SCALE * cone;
  setRay(path, RAY_SHADOW, origin, wi, dist);
  path.pending = f * irradiance * dot(path.bsdf.n, wi) / chosen.pdf;
  return true;
}

// One point on a random emitter triangle, MIS-weighted against BSDF sampling.
bool physicalEmitterRay(inout Path path, inout Rng rng) {
  vec3 n = path.normal;
  vec3 origin = offsetPoint(path.position, n);
  rngAt(rng, path.depth, BT_DIM_EMITTER);
  GpuEmitter e = emitters[pickEmitter(rngNext(rng))];
  vec3 q = sampleTriangle(e.v0, e.v1, e.v2, rngNext2(rng));
  rngAtPcg(rng);
  vec3 d = q - origin;
  float dist2 = dot(d, d);
  float dist = sqrt(dist2);
  vec3 wi = d / dist;
  float cosLight = -dot(faces[e.face].plane.xyz, wi);
  float bsdfPdf;
  vec3 f = bsdfEval(path.bsdf, n, path.wo, wi, bsdfPdf);
  if (!(cosLight > 0.0 && bsdfPdf > 0.0)) return false;
  float lightPdf = dist2 / (cosLight * world.emitterArea);
  // Stop just short of the emitter so that its own face does not count as a blocker.
  setRay(path, RAY_SHADOW, origin, wi, dist - 2.0 * SURFACE_OFFSET);
  path.emitterFace = e.face;
  path.emitterPoint = q;
  path.pending = f * dot(path.bsdf.n, wi) * powerHeuristic(lightPdf, bsdfPdf) / lightPdf; // times the emission
  return true;
}

// `le`: the surface's emission (emittedRadiance) where it is an emitter.
bool physicalSurface(inout Path path, SurfaceHit hit, vec3 le) {
  if (!hit.found) return false; // the void outside a level is black
  uint flags = faceFlags[hit.face];
  GpuFace f = faces[hit.face];
  GlMaterial m = materials[f.material];
  bool shaded = (flags & FACE_SKY) == 0u && path.depth < world.bounces + 1;
  // The base colour, for the sky and the BSDF, and the normal map where a shaded surface's
  // material has one, read in one loop: each place that reads a texture is a copy of the
  // sampling code for the driver to compile (textures.glsl), and one loop costs llvmpipe's
  // compile less than a second place (bench/README.md).
  vec4 base = vec4(0.5, 0.5, 0.5, 1.0); // a material without a texture is mid grey (materialBaseColor)
  vec3 normalTexel = vec3(0.0);
  uint firstMap = (m.flags & MATERIAL_HAS_BASE) != 0u ? MAP_BASE : MAP_NORMAL;
  uint lastMap = shaded && (m.flags & MATERIAL_HAS_NORMAL) != 0u ? MAP_NORMAL : MAP_BASE;
  vec2 uv = faceUv(f, m, hit.position);
  for (uint map = firstMap; map <= lastMap; ++map) {
    vec4 texel = sampleBaseOrNormal(m, map, uv);
    if (map == MAP_BASE) base = texel;
    else normalTexel = texel.rgb;
  }
  vec3 baseColor = srgbToLinear(base.rgb);
  // The camera sees an unlit liquid as the game draws it, its texture (cpu radiancePhysical).
  if (path.depth == 0 && (flags & FACE_LIQUID) != 0u && world.litwater == 0u) {
    path.radiance += path.throughput * baseColor;
    return false;
  }
  if ((flags & FACE_SKY) != 0u) {
    // The camera sees the sky as the game draws it; after a bounce it is the dome's light alone
    // (cpu radiancePhysical).
    path.radiance += path.throughput * (path.depth > 0 ? skyDomeRadiance(path.dir) : baseColor);
    return false;
  }
  vec3 n = hit.normal;
  vec3 wo = -path.dir;
  if ((flags & FACE_EMISSIVE) != 0u) {
    float weight = 1.0;
    if (path.prevBsdfPdf > 0.0) {
      float cosLight = max(dot(n, wo), 1e-6);
      float lightPdf = hit.t * hit.t / (cosLight * world.emitterArea);
      weight = powerHeuristic(path.prevBsdfPdf, lightPdf);
    }
    path.radiance += path.throughput * le * weight;
  }
  if (!shaded) return false;
  // Minlight, on what the camera sees only, as the game's display shows it (renderer/cpu
  // minlightRadiance).
  if (path.depth == 0 && world.minlight != vec3(0.0))
    path.radiance += path.throughput * srgbToLinear(base.rgb * storedLuxel(world.minlight) / world.overbrightOne);

  // The shading normal (renderer/cpu shadingNormal); rays still leave from the face (n).
  vec3 ns = n;
  vec3 local = decodeNormalTexel(normalTexel);
  if (lastMap == MAP_NORMAL && local != vec3(0.0))
    ns = keepAboveHorizon(normalMapToWorld(local, f.tangent, f.bitangent, n), n, wo);
  path.bsdf = Bsdf(baseColor, m.roughness, m.metallic, (m.flags & MATERIAL_SPECULAR) != 0u, ns);
  path.position = hit.position;
  path.normal = n;
  path.wo = wo;
  return true;
}

// Direct light is done: sample the BSDF for the next bounce, or false at the path's end.
bool physicalBounce(inout Path path, inout Rng rng) {
  vec3 n = path.normal;
  rngAt(rng, path.depth, BT_DIM_BSDF);
  vec3 wi = bsdfSample(path.bsdf, path.wo, rng);
  rngAtPcg(rng);
  float pdf;
  vec3 f = bsdfEval(path.bsdf, n, path.wo, wi, pdf);
  if (pdf <= 0.0) return false;
  path.throughput *= f * dot(path.bsdf.n, wi) / pdf;
  path.prevBsdfPdf = pdf;
  // Russian roulette after three bounces, survival by throughput.
  if (path.depth >= 3) {
    float survive = min(0.95, max(path.throughput.x, max(path.throughput.y, path.throughput.z)));
    rngAt(rng, path.depth, BT_DIM_ROULETTE);
    float u = rngNext(rng);
    rngAtPcg(rng);
    if (u >= survive) return false;
    path.throughput /= survive;
  }
  setRay(path, RAY_SURFACE, offsetPoint(path.position, n), wi, INFINITY);
  path.depth++;
  return true;
}

// ---- the loop ----------------------------------------------------------------------------

// The next light of the current surface that needs a ray, set up in `path`; false when none is
// left. The lights come from the light grid (light_select.glsl), in renderer/cpu's order:
//   faithful: the fixed, global and cell lists (LightSet::GridSampledBounce; _surface lights are
//             point lights in them), a cell's many bounce lights drawn among (faithfulListedLightRay);
//   physical: the fixed list's suns, one selected point light (allLightsSelected), then one
//             emitter sample.
bool nextLightRay(inout Path path, inout Rng rng) {
#ifdef BT_FAITHFUL_DIRT
  // Faithful dirt: the occlusion rays come first, as every light needs the occlusion.
  if (!PHYSICAL && path.dirtRay < DIRT_RAYS) {
    faithfulDirtRay(path, rng);
    return true;
  }
#endif
  uint cell = lightGridCell(path.position);
  uint count = PHYSICAL ? lightGrid.fixedCount + 1u : faithfulLightCount(cell);
  while (path.lightIndex <= count) {
    uint i = path.lightIndex++;
    bool needsRay;
    if (i == count)
      needsRay = PHYSICAL && world.emitterCount > 0u && physicalEmitterRay(path, rng);
    else if (!PHYSICAL)
#ifdef BT_FAITHFUL_BOUNCE_DRAW
      needsRay = faithfulListedLightRay(path, cell, i, count, rng);
#else
      needsRay = faithfulLightRay(path, lights[faithfulLight(cell, i)], rng);
#endif
    else if (i < lightGrid.fixedCount)
      needsRay = physicalSunRay(path, lights[lightIndices[i]], rng);
    else
      needsRay = physicalSelectedLightRay(path, rng);
    if (needsRay) return true;
  }
  return false;
}

// Whether the hit of a ray that is not a shadow ray fails its alpha test: the wavefront form's
// trace kernel tested it (`traced`, trace.glsl closestHitMasked), so that the shade kernel holds no
// copy of the texture sampling for it; the megakernel tests it here, only where it is needed, so
// that it compiles to the code it had before.
bool hitMasked(Path path, Hit hit, bool traced) {
#ifdef BT_WAVEFRONT_SHADE
  return traced;
#else
  return maskedOut(hit.face, path.origin + path.dir * hit.t);
#endif
}

// Takes the hit of the ray the path waited for and sets up the next one; false when the path
// has ended (path.radiance is then the sample). `tracedMask`: the wavefront trace kernel's alpha
// test of the hit (hitMasked).
bool advance(inout Path path, Hit hit, bool tracedMask, inout Rng rng) {
  bool ended = false;
  // Physical mode reads emission (an emissive texture) at one place below, for an emitter
  // sample's shadow ray that got through and for a surface ray that hit an emitter: each place
  // that reads a texture is a copy of the sampling code for the driver to compile.
  uint emissionFace = NO_FACE;
  vec3 emissionPoint = vec3(0.0);
  bool surfaceReached = false, skyShown = false;
  SurfaceHit surface;
  bool shadowPassed = path.kind == RAY_SHADOW && hit.face == NO_FACE;
  if (path.kind == RAY_SHADOW) {
    // The any-hit traversal passed everything that does not block light already.
    if (shadowPassed && !PHYSICAL) {
      if (path.pendingIsFloor) path.lightFloor = max(path.lightFloor, path.pending);
      NEGATIVE_ONLY(else if (path.pendingIsNegative) path.lightNegative += path.pending;)
      else path.lightSum += path.pending;
    }
    if (shadowPassed && PHYSICAL) {
      emissionFace = path.emitterFace;
      emissionPoint = path.emitterPoint;
    }
  } else {
    // Surface and sky rays pass hidden faces (and, for the sky, what does not block light) and
    // the far side of a brush they start in, stepping on past each like the CPU's loops.
    uint flags = 0u;
    if (hit.face != NO_FACE) flags = faceFlags[hit.face]; // a branch: never a read at NO_FACE
    bool passThrough = hit.face != NO_FACE &&
                       (hit.inside || hitMasked(path, hit, tracedMask) ||
                        (path.kind == RAY_SURFACE ? (flags & FACE_HIDDEN) != 0u
                                                                : (flags & FACE_SKY) == 0u && !blocksLight(flags, PHYSICAL)));
#ifdef BT_LIQUID_CSG
    // What qbsp's CSG leaves of overlapping liquids (visible.glsl): the hit may be another face.
    if (path.kind == RAY_SURFACE && hit.face != NO_FACE && (flags & FACE_HIDDEN) == 0u) {
      bool shown = !passThrough;
      liquidCsgHit(hit.face, shown, hit.inside, path.origin + path.dir * hit.t, path.dir);
      passThrough = !shown;
      flags = faceFlags[hit.face];
    }
#endif
    if (passThrough && ++path.skips < MAX_SKIPS) {
      path.tMin = hit.t + SKIP_STEP;
      return true;
    }
    bool gaveUp = passThrough; // too many skips: a miss for surface rays, blocked for sky and dirt rays
#ifdef BT_FAITHFUL_DIRT
    if (path.kind == RAY_DIRT) {
      // A face that blocks light ends the ray where it is; the sky or nothing counts as _dirtdepth.
      bool solid = hit.face != NO_FACE && (gaveUp || (flags & FACE_SKY) == 0u);
      path.dirtSum += solid ? min(hit.t, world.dirtDepth) : world.dirtDepth;
      if (path.dirtRay == DIRT_RAYS) path.occlusion = 1.0 - path.dirtSum / (float(DIRT_RAYS) * world.dirtDepth);
    } else
#endif
    if (SKY_RAYS && path.kind == RAY_SKY) {
      bool reached = !gaveUp && (hit.face == NO_FACE || (flags & FACE_SKY) != 0u);
      if (PHYSICAL && reached) reached = physicalSunSeesItsSky(path.lightIndex, hit.face);
#ifdef BT_FAITHFUL_SKY
      // The ray's light is the list entry before lightIndex (nextLightRay), in the cell of the
      // point it left, read once the ray is back so that the path carries nothing more.
      if (!PHYSICAL && reached)
        reached = sunSeesItsSky(lights[faithfulLight(lightGridCell(path.position), path.lightIndex - 1u)].skyMaterial, hit.face);
#endif
      if (reached) {
        if (PHYSICAL) path.radiance += path.throughput * path.pending;
        NEGATIVE_ONLY(else if (path.pendingIsNegative) path.lightNegative += path.pending;)
        else path.lightSum += path.pending;
      }
    } else {
      bool found = !gaveUp && hit.face != NO_FACE;
      if (PHYSICAL && found && (flags & FACE_LIQUID) != 0u && physicalPassesLiquid(path, hit.face, rng)) return passOn(path, hit.t);
      vec3 position = path.origin + path.dir * hit.t;
      surface = SurfaceHit(found, hit.t, hit.face, position, vec3(0.0));
      if (found) surface.normal = faceNormal(hit.face);
#ifdef BT_LIQUID_CSG
      if (found && hit.inside) surface.normal = -surface.normal; // a liquid face seen from inside: its mirror, facing the ray
#endif
      surfaceReached = true;
      skyShown = found && (flags & FACE_SKY) != 0u && world.skySize != 0u;
      if (PHYSICAL && found && (flags & FACE_EMISSIVE) != 0u) {
        emissionFace = hit.face;
        emissionPoint = position;
      }
    }
  }
  vec3 le = vec3(0.0);
  if (PHYSICAL && emissionFace != NO_FACE) le = emittedRadiance(emissionFace, emissionPoint);
  if (PHYSICAL && shadowPassed)
    path.radiance += path.throughput * path.pending * (path.emitterFace != NO_FACE ? le : vec3(1.0));
  if (surfaceReached) {
    // The level's sky images by the ray's direction, as a miss: not the surface shading (sky.glsl).
    // After a bounce, physical mode's sky is the dome's light alone (cpu radiancePhysical).
    // A faithful path is its camera ray alone and keeps no throughput between wavefront dispatches.
    if (skyShown) {
      vec3 sky = skyRadiance(path.dir);
      path.radiance = PHYSICAL ? path.radiance + path.throughput * (path.depth > 0 ? skyDomeRadiance(path.dir) : sky) : sky;
    }
    ended = skyShown || !(PHYSICAL ? physicalSurface(path, surface, le) : faithfulSurface(path, surface));
    path.lightIndex = 0u;
  }
  if (!ended) {
    if (nextLightRay(path, rng)) return true;
    if (PHYSICAL) return physicalBounce(path, rng);
    faithfulPathEnd(path);
  }
  // One call for both ends of a faithful surface (shown, or its lights done): each call is a copy
  // of the liquid blend for the driver to compile.
  return !PHYSICAL && faithfulBehindLiquid(path, !ended || !skyShown);
}

// ---- the two forms of the loop ------------------------------------------------------------

// Sample camera.frameIndex of `pixel`: its random stream, and the path waiting for its camera ray.
Path cameraPath(ivec2 pixel, out Rng rng) {
#ifdef BT_LOW_DISCREPANCY
  rng = pixelSampler(uint(pixel.x), uint(pixel.y), camera.frameIndex, camera.seed);
#else
  rng = pixelRng(uint(pixel.x), uint(pixel.y), camera.frameIndex, camera.seed);
#endif
  vec2 jitter = rngNext2(rng);
  rngAtPcg(rng);
  Path path;
  setRay(path, RAY_SURFACE, camera.origin, cameraRayDirection(vec2(pixel) + jitter), INFINITY);
  path.depth = 0;
  path.lit = vec3(0.0);
  path.texture = vec3(0.0);
  path.fullbright = vec3(0.0);
  path.throughput = vec3(1.0);
  path.prevBsdfPdf = 0.0;
  path.radiance = vec3(0.0);
  path.veil = vec3(0.0), path.veilKeep = VeilKeep(1.0);
  return path;
}

// Adds an ended path's sample to the pixel's running sum, and its luminance squared to the sum's
// alpha (the second moment the denoiser takes each pixel's noise from: RenderImage::luminanceMoment2).
void accumulate(ivec2 pixel, vec3 l) {
  vec4 sum = camera.frameIndex == camera.firstFrame ? vec4(0.0) : imageLoad(accumulation, pixel);
  // A NaN or infinite sample would poison the pixel for good; drop it, as the CPU does.
  if (!any(isnan(l)) && !any(isinf(l))) {
    float luminance = dot(l, vec3(BT_LUMINANCE_R, BT_LUMINANCE_G, BT_LUMINANCE_B));
    sum += vec4(l, luminance * luminance);
  }
  imageStore(accumulation, pixel, sum);
}

#ifdef BT_WAVEFRONT_SHADE
// The wavefront form's shade kernel (wavefront.glsl): the loop below with the traversal taken
// out. Each dispatch moves every live path one ray on: advance() with the hit the trace kernel
// found, then the next ray out to WavefrontRays, or the sample into the image at the path's end.
#include "wavefront.glsl"

#include "wavefront_path.glsl"

layout(location = 0) uniform uint wavefrontStart; // 1: start the paths at the camera

void main() {
  ivec2 pixel = dispatchPixel();
  int slot = wavefrontSlot(pixel);
  if (slot < 0) return;
  Rng rng;
  Path path;
  if (wavefrontStart != 0u) {
    path = cameraPath(pixel, rng);
  } else {
    if (wavefrontRays[slot].live == 0u) return;
    path = loadPath(slot, rng);
    WavefrontHit hit = wavefrontHits[slot];
    if (!advance(path, Hit(hit.t, hit.face, hit.inside), hit.masked, rng)) {
      wavefrontRays[slot].live = 0u;
      accumulate(pixel, path.radiance);
      atomicAdd(wavefrontEnded, 1u);
      return;
    }
  }
  storePath(slot, rng, path);
  wavefrontRays[slot] = WavefrontRay(path.origin, path.tMin, path.dir, path.tMax, path.kind == RAY_SHADOW ? 1u : 0u,
                                     path.passFlags, 1u);
}
#else
void main() {
  ivec2 pixel = dispatchPixel();
  if (any(greaterThanEqual(pixel, camera.imageSize))) return;
  Rng rng;
  Path path = cameraPath(pixel, rng);
  while (true) {
    // The one call of the traversal in this program.
    Hit hit = traceRay(makeTraceRay(path.origin, path.dir, path.tMin, path.tMax), path.kind == RAY_SHADOW, path.passFlags);
    if (!advance(path, hit, false, rng)) break; // the megakernel does its alpha tests in advance()
  }
  accumulate(pixel, path.radiance);
}
#endif

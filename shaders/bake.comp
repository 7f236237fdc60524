#version 450
#extension GL_GOOGLE_include_directive : require
#include "gl_bindings.glsl"
#ifdef BT_TEXTURES_BINDLESS
#extension GL_ARB_bindless_texture : require
#endif
// Faithful mode's light compiler on the GPU: lighting/lightmap_bake.cpp bakeLightmaps with
// integrator.cpp faithfulLuxelPass and faithfulLuxelLight, the CPU reference, drawing the same
// random numbers in the same order. The CPU finds the sample points (lightmap_bake.h
// luxelSamples); each dispatch runs some passes over a range of them, adding to their sums, and a
// resolve dispatch turns the sums so far into the stored luxels that lightmaps.glsl shows, so
// the luxels sharpen pass by pass.
#include "scene_buffers.glsl"
#include "textures.glsl"
#include "trace.glsl"
#include "visible.glsl"
#include "sampling.glsl"
#include "faithful.glsl"
#include "light_select.glsl"

// Workgroups of trace.glsl's 8 x 8 invocations, one item each, in a row of groups (gl_bake.cpp).
// scene/gpu_structs.h GpuLuxelSample, byte for byte.
struct GpuLuxelSample {
  vec3 position;     // offset 0
  uint face;         // offset 12
  vec3 faceMinlight; // offset 16
  uint flags;        // offset 28
};                   // 32 bytes
const uint LUXEL_SAMPLE_OCCLUDED = BT_LUXEL_SAMPLE_OCCLUDED;
const uint LUXEL_SAMPLE_TWO_SIDED = BT_LUXEL_SAMPLE_TWO_SIDED;

// Binding numbers: renderer/gl/gl_structs.h kBindingBake*.
layout(std430, binding = BT_BINDING_BAKE_SAMPLES) readonly buffer LuxelSamples { GpuLuxelSample luxelSamples[]; };
// Per sample, lighting LuxelSums as 4 vec4: (fixed, occlusion), (localMin, negative.r), (dome, negative.g),
// (soft, negative.b): the negative lights' sum in the spare fourth components, no fifth vec4 for
// the few levels that have them.
layout(std430, binding = BT_BINDING_BAKE_SUMS) buffer LuxelSumBuffer { vec4 luxelSums[]; };
// faithful.h skyDomeDirections (domeSuns of them), then RenderScene::sunTable, then the visapprox
// boxes as (mins, maxs) rows: the lights' from lightBoxes, the compiled faces' from receiverBoxes;
// where the GPU computes the lights' (visBoxPass, which writes them), their rows hold the light's
// origin twice until then, and vis_approx.h's ray directions follow from visRays.
layout(std430, binding = BT_BINDING_BAKE_SKY_DOME) buffer SkyDome { vec4 skyDome[]; };
layout(std430, binding = BT_BINDING_LIGHTMAPS) buffer Lightmaps { uint lightmapData[]; };   // scene/gpu_structs.h layout

layout(location = 0) uniform uint firstItem;   // first sample (a pass) or luxel (the resolve)
layout(location = 1) uniform uint itemCount;
layout(location = 2) uniform int firstPass;    // the first pass to run; -1: resolve
layout(location = 7) uniform int passCount;    // passes to run, one after the other in each invocation
int pass;                                      // the pass runPasses is in
layout(location = 3) uniform int passesDone;   // for the resolve
layout(location = 4) uniform int softSamples;
layout(location = 5) uniform uint samplesPerLuxel;
layout(location = 6) uniform uint bakeSeed;    // lightmap_bake.cpp kBakeSeed
layout(location = 8) uniform int domeSuns;     // the dome's directions at the start of skyDome
layout(location = 9) uniform int lightBoxes;   // GpuLight::visBox k is at skyDome[lightBoxes + 2 (k - 1)]
layout(location = 10) uniform int receiverBoxes; // a sample's box k (flags >> BOX_SHIFT) likewise; -1: no cull
layout(location = 11) uniform int visRays;       // the visapprox rays' directions in skyDome (VIS_BOX_PASS only)
const int VIS_BOX_PASS = BT_BAKE_VIS_BOX_PASS;   // firstPass of the dispatch that computes the lights' boxes
const uint LUXEL_SAMPLE_BOX_SHIFT = BT_LUXEL_SAMPLE_BOX_SHIFT;
const uint SUN_SAMPLES = uint(BT_SUN_SAMPLES); // lighting/faithful.h kSunSamples: each penumbra sun's directions

float dirtFactorAt(GpuLight light, float occlusion, float dist) {
#ifdef BT_FAITHFUL_DIRT
  return lightDirtFactor(light, occlusion, dist);
#else
  return 1.0;
#endif
}

// lighting/vis_approx.cpp visBoxesApart: ericw-tools' CullLight without vis data, light box
// `light` (GpuLight::visBox) against compiled-face box `face` (a sample's), both 1-based.
bool visCulled(uint light, uint face) {
  if (light == 0u || face == 0u || receiverBoxes < 0) return false;
  uint l = uint(lightBoxes) + 2u * (light - 1u), f = uint(receiverBoxes) + 2u * (face - 1u);
  bvec3 apart = bvec3(uvec3(lessThan(skyDome[l + 1u].xyz, skyDome[f].xyz - VIS_BOX_EPSILON)) |
                      uvec3(greaterThan(skyDome[l].xyz, skyDome[f + 1u].xyz + VIS_BOX_EPSILON)));
  return any(apart);
}

bool softLight(GpuLight light) { return (light.type == LIGHT_POINT || light.type == LIGHT_SUN) && light.deviance > 0.0; }

// The program's one traversal: NVIDIA inlines every call site into a full copy of it, and a copy
// per kind of ray multiplied its compile time (bench/README.md). Kinds of query, as renderer/cpu:
const uint QUERY_SHADOW = 0u; // occluded(): 1 when no face that blocks light lies before tMax, else 0
const uint QUERY_SKY = 1u;    // reachesSky() with a sun's _suntexture (skyMaterial: material + 1, 0 any): 1 or 0
const uint QUERY_DIRT = 2u;   // blockedDistance(): how far the ray gets, at most tMax
const uint QUERY_FACE = 3u;   // faceDistance(): the same, sky stopping it too (the visapprox rays)

// `param`: a shadow ray's pass word (visible.glsl shadowPassFlags), a sky ray's skyMaterial.
float query(uint kind, vec3 origin, vec3 dir, float tMax, uint param) {
  if (kind == QUERY_SHADOW) return traceRay(makeTraceRay(origin, dir, 0.0, tMax), true, param).face == NO_FACE ? 1.0 : 0.0;
  uint skyMaterial = param;
  float tMin = 0.0, lastT = tMax;
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceRay(makeTraceRay(origin, dir, tMin, tMax), false, 0u);
    if (hit.face == NO_FACE) return kind == QUERY_SKY ? float(skyMaterial == 0u) : tMax;
    uint flags = faceFlags[hit.face];
    bool through = hit.inside || maskedOut(hit.face, origin + dir * hit.t);
    if (!through && (flags & FACE_SKY) != 0u)
      return kind == QUERY_SKY ? float(skyMaterial == 0u || faces[hit.face].material + 1u == skyMaterial)
           : kind == QUERY_FACE ? min(hit.t, tMax)
                                : tMax;
    if (!through && blocksLight(flags, false)) return kind == QUERY_SKY ? 0.0 : min(hit.t, tMax);
    lastT = hit.t;
    tMin = hit.t + SKIP_STEP;
  }
  return kind == QUERY_SKY ? 0.0 : lastT;
}

// Where a light's share goes (lighting LuxelSums).
const uint TO_FIXED = 0u, TO_LOCAL_MIN = 1u, TO_DOME = 2u, TO_SOFT = 3u, TO_DIRT = 4u, TO_NEGATIVE = 5u;

// One item of a pass: a ray, and what its answer adds where.
struct Item {
  bool needed;
  uint kind;
  vec3 origin, dir;
  float tMax;
  uint param; // query()'s: the pass word or the sky material
  vec3 gain;
  uint target;
};

// lighting addFaithfulLight and domeSunLight up to their ray, in `pass` (the passes split the
// lights as faithfulLuxelPass does).
// `receiver`: the face's channels; a point light lights only faces on one of its channels, suns
// the default channel's (the dome's suns every face, as faithfulLuxelPass).
// `box`: the sample's compiled face's visapprox box (0: none).
Item lightItem(GpuLight light, vec3 p, vec3 normal, bool twoSided, uint receiver, uint box, float occlusion, inout Rng rng) {
  Item it = Item(false, QUERY_SHADOW, vec3(0.0), vec3(0.0), 0.0, 0u, vec3(0.0), TO_FIXED);
  bool soft = softLight(light);
  if (light.type == LIGHT_DOME) {
    if (pass >= domeSuns) return it;
    vec3 toSky = skyDome[pass].xyz;
    if (light.direction.z < 0.0) toSky.z = -toSky.z;
    vec3 facing = facingNormal(normal, toSky, twoSided);
    float angle = sunAngleTerm(dot(toSky, facing), light.anglescale);
    if (angle <= 0.0) return it;
    it = Item(true, QUERY_SKY, offsetPoint(p, facing), toSky, INFINITY, light.skyMaterial,
              light.value * angle * dirtFactorAt(light, occlusion, 0.0) * light.color, TO_DOME);
    return it;
  }
  if (soft ? pass >= softSamples : pass != 0) return it;
  if (((light.type == LIGHT_POINT ? light.lightChannels : DEFAULT_CHANNELS) & receiver) == 0u) return it;
  if (visCulled(light.visBox, box)) return it; // before any of the light's random numbers, as the CPU
  if (light.type == LIGHT_POINT) {
    vec3 pos = jitteredOrigin(light, rng);
    vec3 d = pos - p;
    float dist = length(d);
    vec3 toLight = d / dist;
    if (!(dist >= NEAREST_LIGHT)) {
      dist = NEAREST_LIGHT, toLight = vec3(0.0, 0.0, 1.0);
      pos = p + toLight * dist;
    }
    vec3 n = facingNormal(normal, toLight, twoSided);
    float value = pointLightValue(light, n, toLight, dist, world.scaledist) * dirtFactorAt(light, occlusion, dist);
    if (value == 0.0) return it;
    vec3 origin = offsetPoint(p, n);
    vec3 toLightFromOrigin = pos - origin;
    float len = length(toLightFromOrigin);
    uint target = light.formula == FORMULA_LOCAL_MIN ? TO_LOCAL_MIN : soft ? TO_SOFT : subtractedLight(light) ? TO_NEGATIVE : TO_FIXED;
    it = Item(true, QUERY_SHADOW, origin, toLightFromOrigin / len, len, shadowPassFlags(false, light.shadowChannels), value * light.color,
              target);
  }
#ifdef BT_FAITHFUL_SKY
  else if (light.type == LIGHT_SUN) {
    vec3 toSun = -light.direction;
    if ((light.flags & LIGHT_FLAG_SUN_TABLE) != 0u) toSun = -skyDome[uint(domeSuns) + light.sunTable + uint(pass) % SUN_SAMPLES].xyz;
    else if (light.deviance > 0.0) toSun = sampleCone(toSun, light.deviance, rngNext2(rng));
    vec3 n = facingNormal(normal, toSun, twoSided);
    float value = sunValue(light, -toSun, n) * dirtFactorAt(light, occlusion, 0.0);
    if (value == 0.0) return it;
    it = Item(true, QUERY_SKY, offsetPoint(p, n), toSun, INFINITY, light.skyMaterial, value * light.color,
              soft ? TO_SOFT : subtractedLight(light) ? TO_NEGATIVE : TO_FIXED);
  }
#endif
  return it;
}

// lighting faithfulLuxelPass for sample `index`, passes firstPass .. + passCount: pass 0's
// dirt rays, then the lights, one item at a time through the one query.
void runPasses(uint index) {
  GpuLuxelSample s = luxelSamples[index];
  if ((s.flags & LUXEL_SAMPLE_OCCLUDED) != 0u) return;
  vec3 p = s.position, n = faces[s.face].plane.xyz;
  bool twoSided = (s.flags & LUXEL_SAMPLE_TWO_SIDED) != 0u;
  uint receiver = faceChannels(s.face);
  uint box = s.flags >> LUXEL_SAMPLE_BOX_SHIFT;
  vec4 fixedSum = firstPass == 0 ? vec4(0.0) : luxelSums[4u * index];
  vec4 localMin = firstPass == 0 ? vec4(0.0) : luxelSums[4u * index + 1u];
  vec4 dome = firstPass == 0 ? vec4(0.0) : luxelSums[4u * index + 2u];
  vec4 soft = firstPass == 0 ? vec4(0.0) : luxelSums[4u * index + 3u];
  uint cell = lightGridCell(p);
  for (pass = firstPass; pass < firstPass + passCount; ++pass) {
    Rng rng = pixelRng(index, uint(pass), 0u, bakeSeed);
    // After pass 0 only soft lights and domes take part: the fixed list's, unless point lights jitter.
    uint lightCount = pass == 0 || JITTERED_LIGHTS ? faithfulLightCount(cell) : lightGrid.fixedCount;
    uint dirtRays = 0u;
#ifdef BT_FAITHFUL_DIRT
    if (pass == 0) dirtRays = uint(DIRT_RAYS);
#endif
    float dirtSum = 0.0;
    for (uint k = 0u; k < dirtRays + lightCount; ++k) {
      Item it;
      if (k < dirtRays) {
#ifdef BT_FAITHFUL_DIRT
        vec3 v;
        if (world.dirtMode == 1u) {
          float u0 = rngNext(rng), u1 = rngNext(rng);
          v = dirtRandomVector(u0, u1, world.dirtAngle);
        } else {
          v = dirtPatternVector(int(k), world.dirtAngle);
        }
        it = Item(true, QUERY_DIRT, p, dirtRayDirection(n, v), world.dirtDepth, 0u, vec3(0.0), TO_DIRT);
#endif
      } else {
        if (k == dirtRays && dirtRays > 0u) fixedSum.w = 1.0 - dirtSum / (float(dirtRays) * world.dirtDepth);
        it = lightItem(lights[faithfulLight(cell, k - dirtRays)], p, n, twoSided, receiver, box, fixedSum.w, rng);
      }
      if (!it.needed) continue;
      float answer = query(it.kind, it.origin, it.dir, it.tMax, it.param);
      if (it.target == TO_DIRT) dirtSum += answer;
      else if (answer > 0.0) {
        if (it.target == TO_FIXED) fixedSum.xyz += it.gain;
        else if (it.target == TO_LOCAL_MIN) localMin.xyz = max(localMin.xyz, it.gain);
        else if (it.target == TO_DOME) dome.xyz += it.gain;
        else if (it.target == TO_NEGATIVE) localMin.w += it.gain.r, dome.w += it.gain.g, soft.w += it.gain.b;
        else soft.xyz += it.gain;
      }
    }
    if (lightCount == 0u && dirtRays > 0u) fixedSum.w = 1.0 - dirtSum / (float(dirtRays) * world.dirtDepth);
  }
  luxelSums[4u * index] = fixedSum;
  luxelSums[4u * index + 1u] = localMin;
  luxelSums[4u * index + 2u] = dome;
  luxelSums[4u * index + 3u] = soft;
}

// lighting applyFloors: the floors, then the negative lights, then nothing below 0.
vec3 applyFloors(vec3 sum, vec3 localMin, vec3 faceMinlight, float occlusion, vec3 negative) {
  float minlightDirt = 1.0;
#ifdef BT_FAITHFUL_DIRT
  if (world.minlightDirt != 0u) minlightDirt = 1.0 - dirtAmount(occlusion, world.dirtGain, world.dirtScale);
#endif
  return max(max(max(sum + world.ambient, localMin), max(world.minlight, faceMinlight) * minlightDirt) + negative, vec3(0.0));
}

// lighting faithfulLuxelLight of sample `index` after passesDone passes.
vec3 sampleLight(uint index) {
  GpuLuxelSample s = luxelSamples[index];
  if ((s.flags & LUXEL_SAMPLE_OCCLUDED) != 0u) return applyFloors(vec3(0.0), vec3(0.0), s.faceMinlight, 0.0, vec3(0.0));
  vec4 fixedSum = luxelSums[4u * index];
  vec3 sum = fixedSum.xyz;
  int domePasses = min(passesDone, domeSuns);
  int softPasses = min(passesDone, softSamples);
  vec4 localMin = luxelSums[4u * index + 1u], dome = luxelSums[4u * index + 2u], soft = luxelSums[4u * index + 3u];
  if (domePasses > 0) sum += dome.xyz / float(domePasses);
  if (softPasses > 0) sum += soft.xyz / float(softPasses);
  return applyFloors(sum, localMin.xyz, s.faceMinlight, fixedSum.w, vec3(localMin.w, dome.w, soft.w));
}

// lightmap_bake.cpp storedLuxel and lightmaps.h packLuxel.
uint storedLuxel(vec3 light, float range) {
  vec3 stored = max(light * range, vec3(0.0));
  float peak = max(stored.x, max(stored.y, stored.z));
  if (peak > 255.0) stored *= 255.0 / peak;
  uvec3 b = uvec3(clamp(floor(stored), 0.0, 255.0));
  return b.x | (b.y << 8) | (b.z << 16) | (255u << 24);
}

// lighting/vis_approx.cpp visibleBounds on the GPU, one workgroup per light box (firstItem +
// its place in the row): each invocation casts every 64th of the compiler's rays from the origin
// in the box's rows, the first then takes the bounds of all and writes the grown box over them.
// `precise`: one rounding per product and sum, as the CPU computes them, so that the same t
// give the same box bit for bit.
const uint VIS_RAYS = uint(BT_VIS_RAYS);
const float VIS_RAY_LENGTH = BT_VIS_RAY_LENGTH;
const float VIS_BOX_GROWTH = BT_VIS_BOX_GROWTH;
shared vec3 visLo[64], visHi[64];

void visBoxRays(uint row) {
  vec3 origin = skyDome[row].xyz, lo = origin, hi = origin;
  for (uint i = gl_LocalInvocationIndex; i < VIS_RAYS; i += 64u) {
    vec3 dir = skyDome[uint(visRays) + i].xyz;
    precise vec3 stop = origin + dir * query(QUERY_FACE, origin, dir, VIS_RAY_LENGTH, 0u);
    lo = min(lo, stop), hi = max(hi, stop);
  }
  visLo[gl_LocalInvocationIndex] = lo, visHi[gl_LocalInvocationIndex] = hi;
}

void visBoxBounds(uint row) {
  vec3 lo = visLo[0], hi = visHi[0];
  for (uint k = 1u; k < 64u; ++k) lo = min(lo, visLo[k]), hi = max(hi, visHi[k]);
  precise vec3 grow = (hi - lo) * VIS_BOX_GROWTH;
  precise vec3 mins = lo - grow, maxs = hi + grow;
  skyDome[row] = vec4(mins, 0.0), skyDome[row + 1u] = vec4(maxs, 0.0);
}

void main() {
  if (firstPass == VIS_BOX_PASS) { // uniform: the whole workgroup comes here, for its barrier
    bool inRange = gl_WorkGroupID.x < itemCount;
    uint row = uint(lightBoxes) + 2u * (firstItem + gl_WorkGroupID.x);
    if (inRange) visBoxRays(row);
    barrier();
    if (inRange && gl_LocalInvocationIndex == 0u) visBoxBounds(row);
    return;
  }
  uint offset = gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex;
  if (offset >= itemCount) return;
  uint item = firstItem + offset;
  if (firstPass >= 0) {
    runPasses(item);
    return;
  }
  vec3 light = vec3(0.0);
  for (uint k = 0u; k < samplesPerLuxel; ++k) light += sampleLight(item * samplesPerLuxel + k);
  lightmapData[lightmapData[2] + item] = storedLuxel(light / float(samplesPerLuxel), world.range);
}

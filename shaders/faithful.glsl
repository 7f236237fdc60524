// lighting/faithful.h in GLSL: what ericw-tools `light` computes for one light at one
// point (ltface.cc GetLightValue / GetLightValueWithAngle). Light units, Quake units.

#include "light_constants.glsl"
const float FORMULA_SCALE = BT_FORMULA_SCALE;

const float SURFACE_HOTSPOT_CLAMP = BT_SURFACE_HOTSPOT_CLAMP;
const float BOUNCE_HOTSPOT_CLAMP = BT_BOUNCE_HOTSPOT_CLAMP;
const float BOUNCE_GATE = BT_BOUNCE_GATE;
const float LIGHT_ANGLE_EPSILON = BT_LIGHT_ANGLE_EPSILON;
const float SUN_ANGLE_EPSILON = BT_SUN_ANGLE_EPSILON;
const float Q3_HOTSPOT_CLAMP = BT_Q3_HOTSPOT_CLAMP;
const float Q3_SPOT_EDGE = BT_Q3_SPOT_EDGE;
const float NEAREST_LIGHT = BT_NEAREST_LIGHT; // lighting/faithful.h kNearestLight
const float VIS_BOX_EPSILON = BT_VIS_BOX_EPSILON; // lighting/vis_approx.cpp visBoxesApart
const uint BOUNCE_SHADOW_RAYS = BT_BOUNCE_SHADOW_RAYS;

// Programs for a level without _deviance (renderer/gl FaithfulFeatures) compile without it.
#if defined(BT_LIGHTING_PHYSICAL) || defined(BT_FAITHFUL_JITTER)
const bool JITTERED_LIGHTS = true;
#else
const bool JITTERED_LIGHTS = false;
#endif

// One of ericw-tools' `_samples` jittered copies of a point light: uniform in the cube of
// half-size `_deviance` (lighting/faithful_light.h jitteredOrigin). Needs sampling.glsl.
vec3 jitteredOrigin(GpuLight light, inout Rng rng) {
  if (!JITTERED_LIGHTS || light.deviance <= 0.0) return light.origin;
  vec3 u = vec3(rngNext(rng), rngNext(rng), rngNext(rng));
  return light.origin + light.deviance * (2.0 * u - 1.0);
}

// The normal the surface turns to light from `toLight`: a lit liquid is lit from both sides
// (lighting facingNormal).
vec3 facingNormal(vec3 n, vec3 toLight, bool twoSided) { return twoSided && dot(n, toLight) < 0.0 ? -n : n; }

// lighting/faithful.h q3map2Value: q3map2's point and linear lights.
float q3map2Value(GpuLight light, float dist) {
  if (dist >= light.falloff) return 0.0;
  float d = max(dist, Q3_HOTSPOT_CLAMP);
  if (light.formula == FORMULA_Q3_LINEAR) return max(light.value - d * light.atten, 0.0);
  return light.value * (FORMULA_SCALE * FORMULA_SCALE) / (d * d);
}

float copyDistanceValue(GpuLight light, float dist, float scaledist) {
  float value = light.value;
  if (light.formula == FORMULA_Q3_POINT || light.formula == FORMULA_Q3_LINEAR || light.formula == FORMULA_Q3_AREA)
    return q3map2Value(light, dist);
  if (light.formula == FORMULA_SURFACE_RADIOSITY) {
    float d = max(dist, SURFACE_HOTSPOT_CLAMP);
    return value / (d * d);
  }
  if (light.formula == FORMULA_BOUNCE) {
    float d = max(dist, BOUNCE_HOTSPOT_CLAMP);
    return value / (d * d);
  }
  if (light.falloff > 0.0 && light.formula == FORMULA_LINEAR)
    return dist < light.falloff ? value * (1.0 - dist / light.falloff) : 0.0;
  if (light.formula == FORMULA_INFINITE || light.formula == FORMULA_LOCAL_MIN) return value;

  float scaled = scaledist * light.atten * dist;
  if (light.formula == FORMULA_INVERSE) return value / (max(scaled, 1e-3) / FORMULA_SCALE);
  if (light.formula == FORMULA_INVERSE2A) {
    scaled += FORMULA_SCALE;
    return value / ((scaled * scaled) / (FORMULA_SCALE * FORMULA_SCALE));
  }
  if (light.formula == FORMULA_INVERSE2) {
    scaled = max(scaled, 1e-3);
    return value / ((scaled * scaled) / (FORMULA_SCALE * FORMULA_SCALE));
  }
  // Linear; negative lights ("darklights") fall off towards zero from below.
  if (value > 0.0) return max(value - scaled, 0.0);
  return min(value + scaled, 0.0);
}

// ... summed over the light's copies (faithfulScale: ericw-tools' unsplit jittered copies).
float distanceValue(GpuLight light, float dist, float scaledist) {
  return light.faithfulScale * copyDistanceValue(light, dist, scaledist);
}

// Half-Lambert: anglescale 0.5 lights a grazing surface at half strength.
float angleTerm(float cosIncidence, float anglescale) { return (1.0 - anglescale) + anglescale * cosIncidence; }

float spotTerm(GpuLight light, vec3 toLight) {
  if (light.cosOuter < -1.0) return 1.0;
  float cosAxis = -dot(light.direction, toLight);
  if (cosAxis < light.cosOuter) return 0.0;
  if (cosAxis >= light.cosInner) return 1.0;
  return (cosAxis - light.cosOuter) / (light.cosInner - light.cosOuter);
}

// lighting/faithful.h q3map2SpotTerm: q3map2's cone, radiusByDist in cosInner.
float q3map2SpotTerm(GpuLight light, vec3 toLight, float dist) {
  if ((light.flags & LIGHT_FLAG_Q3_SPOT) == 0u) return 1.0;
  float along = -dot(light.direction, toLight) * dist;
  if (along < 0.0) return 0.0;
  float radiusAtDist = light.cosInner * along;
  float sampleRadius = sqrt(max(dist * dist - along * along, 0.0));
  if (sampleRadius >= radiusAtDist) return 0.0;
  return min((radiusAtDist - sampleRadius) / Q3_SPOT_EDGE, 1.0);
}

// lighting/faithful.h behindCosine: radiosity points count a little behind (LIGHT_ANGLE_EPSILON).
float behindCosine(GpuLight light) {
  return light.formula == FORMULA_SURFACE_RADIOSITY ? -LIGHT_ANGLE_EPSILON : 0.0;
}

// A radiosity surface light point: half-Lambert on the emitting face's side too; a bounce light:
// the plain cosine there.
float emitterTerm(GpuLight light, vec3 toLight) {
  bool radiosity = light.formula == FORMULA_SURFACE_RADIOSITY;
  if (!radiosity && light.formula != FORMULA_BOUNCE && light.formula != FORMULA_Q3_AREA) return 1.0;
  float cosEmit = -dot(light.direction, toLight);
  if (cosEmit < behindCosine(light)) return 0.0;
  return radiosity ? angleTerm(cosEmit, 0.5) : cosEmit;
}

// lighting/faithful.h subtractedLight: a negative light the compiler takes off after the floors.
bool subtractedLight(GpuLight light) {
  return light.value < 0.0 && light.deviance <= 0.0 && light.formula <= FORMULA_INVERSE2A && light.formula != FORMULA_LOCAL_MIN &&
         (light.type == LIGHT_POINT || light.type == LIGHT_SUN);
}

float pointLightValue(GpuLight light, vec3 normal, vec3 toLight, float dist, float scaledist) {
  float cosIncidence = dot(toLight, normal);
  if ((light.flags & LIGHT_FLAG_BLEED) != 0u) cosIncidence = abs(cosIncidence);
  if (cosIncidence < behindCosine(light)) return 0.0;
  float value = distanceValue(light, dist, scaledist) * angleTerm(cosIncidence, light.anglescale) *
                spotTerm(light, toLight) * emitterTerm(light, toLight) * q3map2SpotTerm(light, toLight, dist);
  vec3 c = light.color;
  if (light.formula == FORMULA_BOUNCE && value * max(c.x, max(c.y, c.z)) <= BOUNCE_GATE) return 0.0;
  return value;
}

// The floor a face's own radiosity _surface template puts under its light.
vec3 surfaceFaceMinlight(GpuLight surfaceTemplate) {
  if ((surfaceTemplate.flags & LIGHT_FLAG_FACE_MINLIGHT) == 0u) return vec3(0.0);
  return surfaceTemplate.value * surfaceTemplate.faithfulScale * surfaceTemplate.color;
}

// lighting/faithful.h sunAngleTerm: a sun along the face's plane still gives it (1 - a).
float sunAngleTerm(float cosIncidence, float anglescale) {
  if (cosIncidence < -SUN_ANGLE_EPSILON) return 0.0;
  return angleTerm(max(cosIncidence, 0.0), anglescale);
}

float sunValue(GpuLight sun, vec3 direction, vec3 normal) {
  return sun.value * sunAngleTerm(dot(-direction, normal), sun.anglescale);
}

#ifdef BT_FAITHFUL_DIRT
// Dirt (lighting/faithful.h): ericw-tools' ambient occlusion, in programs built for a level
// that uses it.
const int DIRT_AZIMUTH_STEPS = BT_DIRT_AZIMUTH_STEPS;
const int DIRT_ELEVATION_STEPS = BT_DIRT_ELEVATION_STEPS;
const int DIRT_RAYS = DIRT_AZIMUTH_STEPS * DIRT_ELEVATION_STEPS;
const float DIRT_SAMPLE_LIFT = BT_DIRT_SAMPLE_LIFT;

vec3 dirtPatternVector(int index, float coneRadians) {
  float azimuth = float(index / DIRT_ELEVATION_STEPS) * (2.0 * 3.14159265358979 / float(DIRT_AZIMUTH_STEPS));
  float elevation = (float(index % DIRT_ELEVATION_STEPS) + 0.5) * (coneRadians / float(DIRT_ELEVATION_STEPS));
  return vec3(sin(elevation) * cos(azimuth), sin(elevation) * sin(azimuth), cos(elevation));
}

vec3 dirtRandomVector(float u0, float u1, float coneRadians) {
  float azimuth = u0 * 2.0 * 3.14159265358979;
  float elevation = u1 * coneRadians;
  return vec3(cos(azimuth) * sin(elevation), sin(azimuth) * sin(elevation), cos(elevation));
}

// The compiler's tangent frame: unit axes after the normal's largest component.
vec3 dirtRayDirection(vec3 n, vec3 v) {
  int axis = 0;
  float largest = 0.0;
  for (int i = 0; i < 3; ++i)
    if (abs(n[i]) > largest) {
      largest = abs(n[i]);
      axis = i;
    }
  vec3 a = vec3(0.0), b = vec3(0.0);
  a[(axis + 1) % 3] = 1.0;
  b[(axis + 2) % 3] = 1.0;
  vec3 tangent = cross(n, a), bitangent = cross(n, b);
  if (dot(cross(tangent, bitangent), n) < 0.0) {
    vec3 t = tangent;
    tangent = bitangent;
    bitangent = t;
  }
  return normalize(bitangent) * v.x + normalize(tangent) * v.y + n * v.z;
}

float dirtAmount(float occlusion, float gain, float scale) {
  if (occlusion <= 0.0) return 0.0;
  return min(min(pow(occlusion, gain), 1.0) * scale, 1.0);
}

float lightDirtFactor(GpuLight light, float occlusion, float dist) {
  if ((light.flags & LIGHT_FLAG_DIRT) == 0u) return 1.0;
  float dirt = dirtAmount(occlusion, light.dirtGain, light.dirtScale);
  if ((light.flags & LIGHT_FLAG_DIRT_RADIUS) != 0u) {
    if (dist < light.dirtOffRadius) dirt = 0.0;
    else if (dist < light.dirtOnRadius) dirt *= (dist - light.dirtOffRadius) / (light.dirtOnRadius - light.dirtOffRadius);
  }
  return 1.0 - dirt;
}
#endif

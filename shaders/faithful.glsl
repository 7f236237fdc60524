// renderer/cpu/faithful.h in GLSL: what ericw-tools `light` computes for one light at one
// point (ltface.cc GetLightValue / GetLightValueWithAngle). Light units, Quake units.

const float FORMULA_SCALE = 128.0;  // ericw-tools LF_SCALE
const float OVERBRIGHT_ONE = 128.0; // the engine maps lightmap 128 to the texture's colour

const float SURFACE_HOTSPOT_CLAMP = 16.0; // radiosity surface lights: ltface.cc's hotspot clamp

float copyDistanceValue(GpuLight light, float dist, float scaledist) {
  float value = light.value;
  if (light.formula == FORMULA_SURFACE_RADIOSITY) {
    float d = max(dist, SURFACE_HOTSPOT_CLAMP);
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

// A radiosity surface light point: half-Lambert on the emitting face's side too.
float emitterTerm(GpuLight light, vec3 toLight) {
  if (light.formula != FORMULA_SURFACE_RADIOSITY) return 1.0;
  float cosEmit = -dot(light.direction, toLight);
  return cosEmit < 0.0 ? 0.0 : angleTerm(cosEmit, 0.5);
}

float pointLightValue(GpuLight light, vec3 normal, vec3 toLight, float dist, float scaledist) {
  float cosIncidence = dot(toLight, normal);
  if ((light.flags & LIGHT_FLAG_BLEED) != 0u) cosIncidence = abs(cosIncidence);
  if (cosIncidence < 0.0) return 0.0;
  return distanceValue(light, dist, scaledist) * angleTerm(cosIncidence, light.anglescale) * spotTerm(light, toLight) *
         emitterTerm(light, toLight);
}

// The floor a face's own radiosity _surface template puts under its light.
vec3 surfaceFaceMinlight(GpuLight surfaceTemplate) {
  if ((surfaceTemplate.flags & LIGHT_FLAG_FACE_MINLIGHT) == 0u) return vec3(0.0);
  return surfaceTemplate.value * surfaceTemplate.faithfulScale * surfaceTemplate.color;
}

float sunValue(GpuLight sun, vec3 direction, vec3 normal) {
  float cosIncidence = dot(-direction, normal);
  if (cosIncidence < 0.0) return 0.0;
  return sun.value * angleTerm(cosIncidence, sun.anglescale);
}

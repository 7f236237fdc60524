// Physical mode's materials (renderer/cpu's GGX + diffuse BSDF): evaluation, sampling and the
// normal-map horizon fix. Needs sampling.glsl.

#include "light_constants.glsl"
struct Bsdf {
  vec3 albedo;
  float roughness;
  float metallic;
  bool specular;
  vec3 n; // shading normal: the face's, or its normal map's (physicalSurface)
};

const float SPECULAR_LOBE_PROBABILITY = BT_SPECULAR_LOBE_PROBABILITY;

float ggxD(float noh, float alpha) {
  float a2 = alpha * alpha;
  float d = noh * noh * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}

float smithG1(float nov, float alpha) {
  float a2 = alpha * alpha;
  return 2.0 * nov / (nov + sqrt(a2 + (1.0 - a2) * nov * nov));
}

// ng: the face's own normal; light from behind the face never reaches its front (renderer/cpu).
vec3 bsdfEval(Bsdf b, vec3 ng, vec3 wo, vec3 wi, out float pdf) {
  vec3 n = b.n;
  float nol = dot(n, wi);
  float nov = dot(n, wo);
  pdf = 0.0;
  if (nol <= 0.0 || nov <= 0.0 || dot(ng, wi) <= 0.0) return vec3(0.0);
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

vec3 bsdfSample(Bsdf b, vec3 wo, inout Rng rng) {
  vec3 n = b.n;
  if (!b.specular || rngNext(rng) >= SPECULAR_LOBE_PROBABILITY) return sampleCosineHemisphere(n, rngNext2(rng));
  float alpha = max(b.roughness * b.roughness, 1e-3);
  vec2 u = rngNext2(rng);
  float cosTheta = sqrt((1.0 - u.x) / (1.0 + (alpha * alpha - 1.0) * u.x));
  float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
  float phi = 2.0 * PI * u.y;
  vec3 h = toWorld(vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta), n);
  return reflect(-wo, h);
}

// A normal map's shading normal made usable for wo (renderer/cpu keepAboveHorizon, Iray's fix):
// where wo's mirror direction about ns comes within HORIZON_MARGIN of the face or below, it is
// lifted to that height and ns becomes the half vector of wo and the lifted direction.
const float HORIZON_MARGIN = BT_HORIZON_MARGIN;

vec3 keepAboveHorizon(vec3 ns, vec3 ng, vec3 wo) {
  vec3 mirror = 2.0 * dot(ns, wo) * ns - wo;
  float height = dot(mirror, ng);
  if (height >= HORIZON_MARGIN) return ns;
  vec3 lifted = normalize(mirror + ng * (HORIZON_MARGIN - height));
  vec3 halfway = wo + lifted;
  float length2 = dot(halfway, halfway);
  return length2 > 1e-12 ? halfway / sqrt(length2) : ng;
}

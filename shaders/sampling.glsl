// lighting/sampling.h in GLSL: the same PCG streams, so a pixel's sample n draws the same
// numbers on both tracers.
#include "light_constants.glsl"
const float PI = BT_PI;

uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

struct Rng { uint state; };

float rngNext(inout Rng rng) {
  rng.state = rng.state * 747796405u + 2891336453u;
  uint word = ((rng.state >> ((rng.state >> 28u) + 4u)) ^ rng.state) * 277803737u;
  return float(((word >> 22u) ^ word) >> 8) * (1.0 / 16777216.0);
}

vec2 rngNext2(inout Rng rng) {
  float a = rngNext(rng);
  return vec2(a, rngNext(rng));
}

Rng pixelRng(uint x, uint y, uint sampleIndex, uint seed) {
  return Rng(pcgHash(x ^ pcgHash(y ^ pcgHash(sampleIndex ^ pcgHash(seed)))));
}

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
vec3 toWorld(vec3 local, vec3 n) {
  float sgn = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (sgn + n.z);
  float c = n.x * n.y * a;
  vec3 t = vec3(1.0 + sgn * n.x * n.x * a, sgn * c, -sgn * n.x);
  vec3 b = vec3(c, sgn + n.y * n.y * a, -n.y);
  return local.x * t + local.y * b + local.z * n;
}

vec3 sampleCosineHemisphere(vec3 n, vec2 u) {
  float r = sqrt(u.x);
  float phi = 2.0 * PI * u.y;
  return toWorld(vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x))), n);
}

vec3 sampleUniformHemisphere(vec3 n, vec2 u) {
  float z = u.x;
  float r = sqrt(max(0.0, 1.0 - z * z));
  float phi = 2.0 * PI * u.y;
  return toWorld(vec3(r * cos(phi), r * sin(phi), z), n);
}

vec3 sampleCone(vec3 axis, float halfAngle, vec2 u) {
  float cosMax = cos(halfAngle);
  float z = 1.0 - u.x * (1.0 - cosMax);
  float r = sqrt(max(0.0, 1.0 - z * z));
  float phi = 2.0 * PI * u.y;
  return toWorld(vec3(r * cos(phi), r * sin(phi), z), axis);
}

vec3 sampleTriangle(vec3 a, vec3 b, vec3 c, vec2 u) {
  float su = sqrt(u.x);
  return a * (1.0 - su) + b * (su * (1.0 - u.y)) + c * (su * u.y);
}

float powerHeuristic(float a, float b) {
  float a2 = a * a;
  return a2 / (a2 + b * b);
}

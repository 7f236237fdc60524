// lighting/sampling.h in GLSL: the same PCG streams and Sobol sequences, so a pixel's sample n
// draws the same numbers on both tracers.
#include "light_constants.glsl"
const float PI = BT_PI;

uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Physical mode's programs (BT_LOW_DISCREPANCY) draw their main decisions from the pixel's
// scrambled Sobol sequence (lighting/sampling.h pixelSampler, Rng::at): the path carries the
// pixel's scramble and the dimension it is at in one word (seedDim); the sample index is the
// dispatch's (BT_SAMPLE_INDEX, the program's uniform), not a register along the path.
#ifdef BT_LOW_DISCREPANCY
struct Rng { uint state; uint seedDim; };
#else
struct Rng { uint state; };
#endif

// lighting/sampling.h owenScramble, sobolSecond, sobolPairSeed, sobolValue, sobolDraw, sobolPair.
uint owenScramble(uint v, uint seed) {
  v = bitfieldReverse(v);
  v += seed;
  v ^= v * 0x6c50b47cu;
  v ^= v * 0xb82f1e52u;
  v ^= v * 0xc7afe638u;
  v ^= v * 0x8d22f6e6u;
  return bitfieldReverse(v);
}

uint sobolSecond(uint index) {
  index ^= (index >> 1u) & 0x55555555u;
  index ^= (index >> 2u) & 0x33333333u;
  index ^= (index >> 4u) & 0x0f0f0f0fu;
  index ^= (index >> 8u) & 0x00ff00ffu;
  index ^= (index >> 16u) & 0x0000ffffu;
  return bitfieldReverse(index);
}

uint sobolPairSeed(uint pixelSeed, uint dim) { return pcgHash(pixelSeed ^ pcgHash(dim >> 1u)); }

float sobolValue(uint sobol, uint pairSeed, uint component) {
  return float(owenScramble(sobol, pcgHash(pairSeed + 1u + component)) >> 8) * (1.0 / 16777216.0);
}

float sobolDraw(uint pixelSeed, uint index, uint dim) {
  uint seed = sobolPairSeed(pixelSeed, dim);
  uint shuffled = owenScramble(index, seed);
  return (dim & 1u) == 0u ? sobolValue(bitfieldReverse(shuffled), seed, 0u) : sobolValue(sobolSecond(shuffled), seed, 1u);
}

vec2 sobolPair(uint pixelSeed, uint index, uint dim) {
  uint seed = sobolPairSeed(pixelSeed, dim);
  uint shuffled = owenScramble(index, seed);
  return vec2(sobolValue(bitfieldReverse(shuffled), seed, 0u), sobolValue(sobolSecond(shuffled), seed, 1u));
}

float rngNext(inout Rng rng) {
#ifdef BT_LOW_DISCREPANCY
  uint dim = rng.seedDim & BT_DIM_PCG;
  if (dim != BT_DIM_PCG) {
    rng.seedDim++;
    return sobolDraw(rng.seedDim >> BT_DIM_BITS, BT_SAMPLE_INDEX, dim);
  }
#endif
  rng.state = rng.state * 747796405u + 2891336453u;
  uint word = ((rng.state >> ((rng.state >> 28u) + 4u)) ^ rng.state) * 277803737u;
  return float(((word >> 22u) ^ word) >> 8) * (1.0 / 16777216.0);
}

vec2 rngNext2(inout Rng rng) {
#ifdef BT_LOW_DISCREPANCY
  if ((rng.seedDim & BT_DIM_PCG) != BT_DIM_PCG) {
    rng.seedDim += rng.seedDim & 1u; // a Sobol pair, stratified in 2D
    vec2 u = sobolPair(rng.seedDim >> BT_DIM_BITS, BT_SAMPLE_INDEX, rng.seedDim & BT_DIM_PCG);
    rng.seedDim += 2u;
    return u;
  }
#endif
  float a = rngNext(rng);
  return vec2(a, rngNext(rng));
}

// lighting/sampling.h Rng::at and Rng::atPcg; no-ops without BT_LOW_DISCREPANCY.
void rngAt(inout Rng rng, int depth, uint offset) {
#ifdef BT_LOW_DISCREPANCY
  rng.seedDim = (rng.seedDim & ~BT_DIM_PCG) | (BT_DIM_FIRST_SURFACE + uint(depth) * BT_DIMS_PER_SURFACE + offset);
#endif
}

void rngAtPcg(inout Rng rng) {
#ifdef BT_LOW_DISCREPANCY
  rng.seedDim |= BT_DIM_PCG;
#endif
}

Rng pixelRng(uint x, uint y, uint sampleIndex, uint seed) {
  uint state = pcgHash(x ^ pcgHash(y ^ pcgHash(sampleIndex ^ pcgHash(seed))));
#ifdef BT_LOW_DISCREPANCY
  return Rng(state, BT_DIM_PCG);
#else
  return Rng(state);
#endif
}

#ifdef BT_LOW_DISCREPANCY
Rng pixelSampler(uint x, uint y, uint sampleIndex, uint seed) {
  Rng rng = pixelRng(x, y, sampleIndex, seed);
  rng.seedDim = (pcgHash(x ^ pcgHash(y ^ pcgHash(pcgHash(seed) + 1u))) & ~BT_DIM_PCG) | BT_DIM_CAMERA;
  return rng;
}
#endif

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

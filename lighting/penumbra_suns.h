// The compiler's sun directions: ericw-tools `light` turns a sun with a penumbra
// (`_sunlight_penumbra`, or `_deviance` on a `_sun 1` light) into `-sunsamples` (64) suns whose
// directions come from the C library's rand() (entities.cc SetupSun, from q3map2). The compiled
// levels of the oracle were lit on Linux, so those are glibc's numbers from its default seed:
// fixed, not noise. Both tracers' luxel bakes read the table made here, so a penumbra lights the
// same luxels as in the compiled game.
#pragma once

#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace bt {

// glibc's rand() (stdlib/random_r.c, the default TYPE_3 state): an additive feedback generator
// r[i] = r[i-3] + r[i-31] over 34 words seeded by a Lehmer generator (16807 mod 2^31 - 1), the
// first 310 outputs discarded, each output the word shifted right by one. Seed 1 is the state a
// program starts in without srand().
class GlibcRand {
public:
  explicit GlibcRand(uint32_t seed = 1);
  int32_t next(); // 0 .. RAND_MAX (2^31 - 1)
  // ericw-tools' Random(): rand() / RAND_MAX, in [0, 1].
  double unit() { return double(next()) / 2147483647.0; }

private:
  uint32_t r_[34];
  int i_ = 0; // where the next word goes in the ring
};

// How many rand() draws ericw-tools makes before its suns (JitterEntities: three per extra copy
// of every light entity with `_deviance`, `_samples` of them, 16 by default). Copies of `_surface`
// points with `_deviance` draw too and are not counted: the points are made later here.
uint64_t randDrawsBeforeSuns(const Scene& scene);
// ... and between the `_sun 1` lights' suns and the world's: a `_sun 1` light with `_deviance` is
// jittered into `_samples` copies like any light, and each copy becomes a sun with a penumbra of
// its own after every entity's (2 draws for each of its 63 jittered directions). Only the first
// copy's suns light here.
uint64_t randDrawsOfSunCopies(const Scene& scene);

// One sun's `count` directions as SetupSun makes them, `shine` being the direction it shines
// (unit) and `penumbraDegrees` its spread: `shine` itself, then `count - 1` with azimuth and
// elevation each moved by a uniform amount in ±penumbra. The rejection loop compares radians²
// with degrees² and so never rejects; it is kept, as the compiler draws.
std::vector<glm::vec3> penumbraDirections(GlibcRand& rand, const glm::vec3& shine, double penumbraDegrees, int count);

} // namespace bt

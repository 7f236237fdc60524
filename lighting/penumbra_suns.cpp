#include "lighting/penumbra_suns.h"

#include "quake/entity_keys.h"
#include "shaders/light_constants.glsl"

#include <cmath>

namespace bt {

GlibcRand::GlibcRand(uint32_t seed) {
  // srandom_r: a seed of 0 is taken as 1; Schrage's method keeps 16807 * word in 31 bits.
  int32_t word = seed == 0 ? 1 : int32_t(seed);
  r_[0] = uint32_t(word);
  for (int i = 1; i < 31; ++i) {
    const int32_t hi = word / 127773, lo = word % 127773;
    word = 16807 * lo - 2836 * hi;
    if (word < 0) word += 2147483647;
    r_[i] = uint32_t(word);
  }
  for (int i = 31; i < 34; ++i) r_[i] = r_[i - 31];
  i_ = 34 % 34;
  for (int k = 0; k < 310; ++k) next();
}

int32_t GlibcRand::next() {
  // The ring holds the last 34 words; r[i] = r[i-31] + r[i-3], i.e. 3 and 31 places back.
  const uint32_t word = r_[(i_ + 34 - 31) % 34] + r_[(i_ + 34 - 3) % 34];
  r_[i_] = word;
  i_ = (i_ + 1) % 34;
  return int32_t(word >> 1);
}

namespace {

// A light entity's extra jittered copies (CheckEntityFields: `_samples` 16 when only `_deviance`
// is given; none unless both are above 0 and 1).
int extraCopies(const quake::EntityKeys& keys) {
  const float deviance = keys.number("_deviance", 0.0f);
  int samples = keys.integer("_samples", 0);
  if (deviance > 0.0f && samples == 0) samples = 16;
  return deviance > 0.0f && samples > 1 ? samples - 1 : 0;
}

} // namespace

uint64_t randDrawsBeforeSuns(const Scene& scene) {
  uint64_t draws = 0;
  for (const Entity& entity : scene.entities)
    if (entity.classname().starts_with("light")) draws += 3u * uint64_t(extraCopies(quake::EntityKeys(entity, scene.sourcePath)));
  return draws;
}

uint64_t randDrawsOfSunCopies(const Scene& scene) {
  uint64_t draws = 0;
  for (const Entity& entity : scene.entities) {
    if (!entity.classname().starts_with("light")) continue;
    const quake::EntityKeys keys(entity, scene.sourcePath);
    if (keys.integer("_sun", 0) == 1 && keys.number("light", 300.0f) >= 1.0f)
      draws += uint64_t(extraCopies(keys)) * 2u * uint64_t(BT_SUN_SAMPLES - 1);
  }
  return draws;
}

std::vector<glm::vec3> penumbraDirections(GlibcRand& rand, const glm::vec3& shine, double penumbraDegrees, int count) {
  const double x = shine.x, y = shine.y, z = shine.z;
  const double len = std::sqrt(x * x + y * y + z * z);
  const double sx = x / len, sy = y / len, sz = z / len;
  const double radians = penumbraDegrees * (2.0 * 3.14159265358979323846 / 360.0);
  const double degreesSq = penumbraDegrees * penumbraDegrees;
  std::vector<glm::vec3> out;
  out.emplace_back(float(sx), float(sy), float(sz));
  for (int i = 1; i < count; ++i) {
    double angle = std::atan2(sy, sx), elevation = std::atan2(sz, std::sqrt(sx * sx + sy * sy));
    double da = 0.0, de = 0.0;
    do {
      da = (rand.unit() * 2.0 - 1.0) * radians;
      de = (rand.unit() * 2.0 - 1.0) * radians;
    } while (da * da + de * de > degreesSq);
    angle += da;
    elevation += de;
    out.emplace_back(float(std::cos(angle) * std::cos(elevation)), float(std::sin(angle) * std::cos(elevation)),
                     float(std::sin(elevation)));
  }
  return out;
}

} // namespace bt

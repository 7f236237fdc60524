// Helpers shared by the bvh tests: brute-force closest hit and random rays.
#pragma once

#include "bvh/trace_scene.h"

#include <glm/geometric.hpp>

#include <optional>
#include <random>
#include <string>
#include <vector>

namespace bt::test {

// The closest hit by testing every brush, with the tie-break that trace_scene.h states: at
// equal t an entering hit beats a leaving one, then the higher face index (the later brush).
// Mesh triangles count as well, by the same order.
inline std::optional<Hit> bruteForceClosestHit(const TraceScene& ts, const Ray& ray) {
  std::optional<Hit> best;
  auto consider = [&](const std::optional<Hit>& h) {
    if (!h) return;
    const bool better = !best || h->t < best->t || (h->t == best->t && (h->inside != best->inside ? !h->inside : h->face > best->face));
    if (better) best = h;
  };
  for (uint32_t b = 0; b < ts.brushes().size(); ++b) consider(ts.intersectBrush(ray, b));
  for (uint32_t t = 0; t < ts.triangles().size(); ++t) consider(ts.intersectTriangle(ray, t));
  return best;
}

// Walks the tree from the root and checks everything a traversal relies on: every node and
// brush reached exactly once, bounds nested, depth within kBvhMaxDepth.
void expectWellFormed(const TraceScene& ts);
// The same of wideNodes() (expectWellFormed checks it too).
void expectWideWellFormed(const TraceScene& ts);
// Every scene brush with a winding is in brushes() exactly once, its sides from its own faces.
void expectAllBrushesPresent(const Scene& scene, const TraceScene& ts);
// The binned SAH cost is within 3 % of the full-sweep reference on the same brush boxes.
void expectSahNearFullSweep(const TraceScene& ts, int leafSize, const std::string& what);

inline glm::vec3 randomUnitVector(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  glm::vec3 d;
  do d = {u(rng), u(rng), u(rng)};
  while (glm::dot(d, d) > 1.0f || glm::dot(d, d) < 1e-6f);
  return glm::normalize(d);
}

// A mix of ray kinds over a scene's bounds: random origins (inside brushes too, for inside
// hits), origins outside the bounds, axis-aligned directions (zero components), and
// finite tMin/tMax intervals.
inline std::vector<Ray> randomRays(const Bounds& bounds, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const dvec3 lo = bounds.min - bounds.extent() * 0.1, hi = bounds.max + bounds.extent() * 0.1;
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray r;
    r.origin = glm::vec3(lo + (hi - lo) * dvec3(u(rng), u(rng), u(rng)));
    r.direction = randomUnitVector(rng);
    const int kind = i % 8;
    if (kind == 1) r.direction = glm::vec3(0.0f), r.direction[i % 3] = (i & 8) ? 1.0f : -1.0f;
    if (kind == 2) r.direction[i % 3] = 0.0f;                       // in a coordinate plane
    if (kind == 3) r.origin = glm::round(r.origin / 16.0f) * 16.0f; // on the grid planes of boxes
    if (kind == 4) r.tMin = static_cast<float>(u(rng) * 200.0);
    if (kind == 5) r.tMax = static_cast<float>(u(rng) * 400.0);
    if (kind == 6) r.direction *= 37.5f; // t in units of a longer direction
    rays.push_back(r);
  }
  return rays;
}

} // namespace bt::test

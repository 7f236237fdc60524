#include "lighting/vis_approx.h"

#include "lighting/game_rules.h"
#include "lighting/render_scene.h"
#include "lighting/visibility.h"
#include "scene/parallel_for.h"
#include "shaders/light_constants.glsl" // BT_VIS_BOX_EPSILON, shared with bake.comp

#include <glm/common.hpp>

#include <cmath>
#include <string_view>

namespace bt {

namespace {

constexpr int kRaysPerAxis = 32; // EstimateVisibleBoundsAtPoint's N
static_assert(kRaysPerAxis * kRaysPerAxis == kVisRays);
constexpr double kPi = 3.14159265358979323846;

// UniformPointOnSphere (entities.cc, after mathworld's sphere point picking): u1, u2 in [0, 1].
glm::dvec3 uniformPointOnSphere(double u1, double u2) {
  const double theta = u1 * 2.0 * kPi;
  const double u = 2.0 * u2 - 1.0;
  const double s = std::sqrt(1.0 - u * u);
  return {s * std::cos(theta), s * std::sin(theta), u};
}

bool compiledFormat(std::string_view format) {
  for (std::string_view f : {"bsp29", "bsp2", "2psb", "bsp30", "ibsp38", "ibsp46"})
    if (format == f) return true;
  return false;
}

} // namespace

bool compilerCullsByRays(const Scene& scene) {
  return gameOf(scene) != Game::Quake3 && !compiledFormat(scene.format);
}

const std::vector<glm::vec3>& visRayDirections() {
  static const std::vector<glm::vec3> directions = [] {
    std::vector<glm::vec3> out;
    out.reserve(kVisRays);
    for (int x = 0; x < kRaysPerAxis; ++x)
      for (int y = 0; y < kRaysPerAxis; ++y)
        out.emplace_back(uniformPointOnSphere(double(x) / (kRaysPerAxis - 1), double(y) / (kRaysPerAxis - 1)));
    return out;
  }();
  return directions;
}

// The stop points and the growth in float, one rounding per product and per sum (no fused
// multiply-add: the build targets x86-64 without FMA, and bake.comp marks them precise), so that
// the GPU, given the same t, gets the same box bit for bit.
GpuVisBox visibleBounds(const RenderScene& rs, const glm::vec3& point) {
  glm::vec3 lo = point, hi = point;
  for (const glm::vec3& dir : visRayDirections()) {
    const float t = faceDistance(rs, point, dir, kVisRayLength);
    const glm::vec3 stop = point + dir * t;
    lo = glm::min(lo, stop), hi = glm::max(hi, stop);
  }
  const glm::vec3 grow = (hi - lo) * kVisBoxGrowth;
  return {glm::vec4(lo - grow, 0.0f), glm::vec4(hi + grow, 0.0f)};
}

GpuVisBox polygonBounds(const Winding& polygon) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const dvec3& v : polygon) lo = glm::min(lo, v), hi = glm::max(hi, v);
  return {glm::vec4(glm::vec3(lo), 0.0f), glm::vec4(glm::vec3(hi), 0.0f)};
}

bool visBoxesApart(const GpuVisBox& light, const GpuVisBox& face) {
  constexpr float e = BT_VIS_BOX_EPSILON;
  for (int a = 0; a < 3; ++a)
    if (light.maxs[a] < face.mins[a] - e || light.mins[a] > face.maxs[a] + e) return true;
  return false;
}

void numberVisBoxLights(RenderScene& rs) {
  rs.visBoxes.clear();
  rs.visBoxLights.clear();
  const bool culls = compilerCullsByRays(*rs.scene);
  for (uint32_t i = 0; i < rs.lights.size(); ++i) {
    GpuLight& l = rs.lights[i];
    l.visBox = 0;
    if (!culls || l.type != uint32_t(LightType::Point) || l.formula == uint32_t(LightFormula::Bounce)) continue;
    if (l.lightChannels != kDefaultChannels || l.shadowChannels != kDefaultChannels) continue;
    rs.visBoxLights.push_back(i);
    l.visBox = uint32_t(rs.visBoxLights.size());
  }
}

std::vector<GpuVisBox> computeVisBoxes(const RenderScene& rs, unsigned threads, size_t first) {
  std::vector<GpuVisBox> boxes(rs.visBoxLights.size() - std::min(first, rs.visBoxLights.size()));
  parallelFor(boxes.size(), threads, [&](size_t k) { boxes[k] = visibleBounds(rs, rs.lights[rs.visBoxLights[first + k]].origin); });
  return boxes;
}

void assignVisBoxes(RenderScene& rs, unsigned threads) {
  numberVisBoxLights(rs);
  rs.visBoxes = computeVisBoxes(rs, threads);
}

void assignBounceVisBoxes(RenderScene& rs, uint32_t firstBounce, unsigned threads) {
  if (!compilerCullsByRays(*rs.scene)) return;
  // Numbered after the entity lights, whose boxes are all there, so that visBoxLights and visBoxes
  // stay pairs (the bakes' boxedLights and lightBoxes).
  const size_t first = rs.visBoxLights.size();
  for (uint32_t i = firstBounce; i < rs.lights.size(); ++i)
    if (rs.lights[i].formula == uint32_t(LightFormula::Bounce)) {
      rs.visBoxLights.push_back(i);
      rs.lights[i].visBox = uint32_t(rs.visBoxLights.size());
    }
  const std::vector<GpuVisBox> boxes = computeVisBoxes(rs, threads, first);
  rs.visBoxes.insert(rs.visBoxes.end(), boxes.begin(), boxes.end());
}

} // namespace bt

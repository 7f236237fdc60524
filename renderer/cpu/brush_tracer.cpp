#include "renderer/cpu/brush_tracer.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

BrushTracer::BrushTracer(const Scene& scene, const std::function<bool(uint32_t)>& includeBrush) {
  planes_.reserve(scene.faces.size());
  for (const Face& f : scene.faces) planes_.emplace_back(glm::vec3(f.plane.normal), float(f.plane.dist));
  for (uint32_t i = 0; i < scene.brushes.size(); ++i) {
    const Brush& b = scene.brushes[i];
    if (b.bounds.empty() || b.faceCount == 0 || !includeBrush(i)) continue;
    // Pad the box a little so that rays grazing a face are still clipped by the planes.
    brushes_.push_back({glm::vec3(b.bounds.min) - 0.01f, glm::vec3(b.bounds.max) + 0.01f, b.firstFace, b.faceCount, i});
  }
}

static bool slabTest(const Ray& ray, const glm::vec3& invDir, const glm::vec3& lo, const glm::vec3& hi, float tmax) {
  const glm::vec3 t0 = (lo - ray.origin) * invDir;
  const glm::vec3 t1 = (hi - ray.origin) * invDir;
  const glm::vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1);
  const float enter = std::max(std::max(tn.x, tn.y), std::max(tn.z, ray.tMin));
  const float exit = std::min(std::min(tf.x, tf.y), std::min(tf.z, tmax));
  return enter <= exit;
}

std::optional<Hit> BrushTracer::closestHit(const Ray& ray) const {
  const glm::vec3 invDir = 1.0f / ray.direction;
  std::optional<Hit> best;
  float tmax = ray.tMax;
  for (const BrushBox& box : brushes_) {
    if (!slabTest(ray, invDir, box.min, box.max, tmax)) continue;
    // Haines: clip [tmin, tmax] by every plane; the last entering plane is the hit face.
    float tNear = ray.tMin, tFar = tmax;
    int64_t nearFace = -1, farFace = -1;
    bool miss = false;
    for (uint32_t f = box.firstFace; f < box.firstFace + box.faceCount; ++f) {
      const glm::vec4& pl = planes_[f];
      const float denom = glm::dot(glm::vec3(pl), ray.direction);
      const float dist = glm::dot(glm::vec3(pl), ray.origin) - pl.w;
      if (denom == 0.0f) {
        if (dist > 0.0f) { miss = true; break; }
        continue;
      }
      const float t = -dist / denom;
      if (denom < 0.0f) {
        if (t > tNear) { tNear = t; nearFace = f; }
      } else if (t < tFar) {
        tFar = t;
        farFace = f;
      }
      if (tNear > tFar) { miss = true; break; }
    }
    if (miss) continue;
    if (nearFace >= 0) {
      tmax = tNear;
      best = Hit{tNear, uint32_t(nearFace), box.sceneBrush, false};
    } else if (farFace >= 0) {
      tmax = tFar;
      best = Hit{tFar, uint32_t(farFace), box.sceneBrush, true};
    }
  }
  return best;
}

} // namespace bt

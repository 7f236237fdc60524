// Ray queries against the scene's brushes, by brute force over brush bounds.
//
// Stand-in until the `bvh` part's TraceScene lands: same queries (closest hit with face index,
// any hit), same per-brush clipping, no acceleration structure, so it is exact but only fast
// enough for small scenes and tests. Follows the hit rules of bvh/trace_scene.h.
#pragma once

#include "bvh/trace_scene.h" // Ray, Hit
#include "scene/scene.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace bt {

class BrushTracer {
public:
  // includeBrush(i) false leaves brush i out (e.g. all-clip brushes).
  BrushTracer(const Scene& scene, const std::function<bool(uint32_t)>& includeBrush);

  std::optional<Hit> closestHit(const Ray& ray) const;

private:
  struct BrushBox {
    glm::vec3 min, max;
    uint32_t firstFace, faceCount, sceneBrush;
  };
  std::vector<BrushBox> brushes_;
  std::vector<glm::vec4> planes_; // xyz normal, w dist; parallel to Scene::faces
};

} // namespace bt

#include "tests/support/scene_builder.h"

#include "scene/winding.h"

#include <glm/geometric.hpp>

namespace bt::test {

namespace {

// Quake's texture base axes (qbsp TextureAxisFromPlane): the axis pair of the closest of
// floor, ceiling, and the four walls.
void axialFrame(const dvec3& n, dvec3& tangent, dvec3& bitangent) {
  const dvec3 a = glm::abs(n);
  if (a.z >= a.x && a.z >= a.y) {
    tangent = {1, 0, 0};
    bitangent = {0, -1, 0};
  } else if (a.x >= a.y) {
    tangent = {0, 1, 0};
    bitangent = {0, 0, -1};
  } else {
    tangent = {1, 0, 0};
    bitangent = {0, 0, -1};
  }
}

// The face of an axial box on side `side` (0: -, 1: +) of `axis`.
Face boxFace(const dvec3& lo, const dvec3& hi, int axis, int side) {
  Face f;
  dvec3 n(0.0);
  n[axis] = side ? 1.0 : -1.0;
  f.plane.normal = n;
  f.plane.dist = side ? hi[axis] : -lo[axis];
  // Quake's axial texture projection: drop the normal's axis.
  const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
  f.frame.origin = dvec3(0.0);
  f.frame.origin[axis] = side ? hi[axis] : lo[axis];
  f.frame.tangent = dvec3(0.0);
  f.frame.tangent[u] = 1.0;
  f.frame.bitangent = dvec3(0.0);
  f.frame.bitangent[v] = -1.0;
  // Rectangle on the plane, counter-clockwise seen from outside.
  const double w = f.frame.origin[axis];
  dvec3 c[4];
  const double us[4] = {lo[u], hi[u], hi[u], lo[u]}, vs[4] = {lo[v], lo[v], hi[v], hi[v]};
  for (int k = 0; k < 4; ++k) {
    c[k][axis] = w;
    c[k][u] = us[k];
    c[k][v] = vs[k];
  }
  const dvec3 e1 = c[1] - c[0], e2 = c[2] - c[0];
  const bool ccw = glm::dot(glm::cross(e1, e2), n) > 0.0;
  for (int k = 0; k < 4; ++k) f.winding.push_back(c[ccw ? k : 3 - k]);
  return f;
}

} // namespace

uint32_t addBrush(Scene& scene, std::span<const Plane> planes, const BrushFaces& faces, const WindingClip& clip,
                  const std::optional<Bounds>& bounds) {
  Brush brush;
  brush.entity = faces.entity;
  brush.firstFace = static_cast<uint32_t>(scene.faces.size());
  brush.faceCount = static_cast<uint32_t>(planes.size());
  const uint32_t brushIndex = static_cast<uint32_t>(scene.brushes.size());
  for (size_t i = 0; i < planes.size(); ++i) {
    Face f;
    f.brush = brushIndex;
    f.material = faces.material;
    f.texture = faces.texture;
    f.plane = planes[i];
    axialFrame(planes[i].normal, f.frame.tangent, f.frame.bitangent);
    f.frame.origin = planes[i].normal * planes[i].dist; // on the plane
    f.winding = baseWinding(planes[i], clip.radius);
    for (size_t j = 0; j < planes.size(); ++j)
      if (j != i) f.winding = clipBehind(f.winding, planes[j], clip.epsilon);
    if (!bounds)
      for (const dvec3& p : f.winding) brush.bounds.grow(p);
    scene.faces.push_back(std::move(f));
  }
  if (bounds) brush.bounds = *bounds;
  scene.brushes.push_back(brush);
  scene.bounds.grow(brush.bounds);
  return brushIndex;
}

uint32_t addBox(Scene& scene, const dvec3& min, const dvec3& max, const BrushFaces& faces) {
  Brush brush;
  brush.entity = faces.entity;
  brush.firstFace = static_cast<uint32_t>(scene.faces.size());
  brush.faceCount = 6;
  brush.bounds.grow(min);
  brush.bounds.grow(max);
  const uint32_t brushIndex = static_cast<uint32_t>(scene.brushes.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      Face f = boxFace(min, max, axis, side);
      f.brush = brushIndex;
      f.material = faces.material;
      f.texture = faces.texture;
      scene.faces.push_back(std::move(f));
    }
  }
  scene.brushes.push_back(brush);
  scene.bounds.grow(brush.bounds);
  return brushIndex;
}

} // namespace bt::test

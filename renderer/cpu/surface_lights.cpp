#include "renderer/cpu/surface_lights.h"

#include "renderer/cpu/color.h"
#include "scene/names.h"
#include "scene/winding.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

namespace {

constexpr double kQ1SurfaceGrid = 128.0; // `light -surflight_subdivide` default
constexpr double kMinPieceWidth = 8.0;   // GLQuake does not cut off slivers thinner than this
constexpr double kRadiosityLift = 1.0;   // surflight.cc lifts a radiosity point 1 unit off the face
constexpr double kMinEmitterArea = 1.0;  // surflight.cc skips smaller faces
constexpr double kInsideEpsilon = 0.01;  // a point this far behind every plane is inside the brush

void subdivide(const Winding& w, double size, std::vector<Winding>& pieces) {
  if (w.size() < 3) return;
  dvec3 lo = w[0], hi = w[0];
  for (const dvec3& p : w) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (int axis = 0; axis < 3; ++axis) {
    const double cut = size * std::floor((lo[axis] + hi[axis]) * 0.5 / size + 0.5);
    if (hi[axis] - cut < kMinPieceWidth || cut - lo[axis] < kMinPieceWidth) continue;
    Plane plane;
    plane.normal = dvec3(0.0);
    plane.normal[axis] = 1.0;
    plane.dist = cut;
    const SplitWinding split = splitWinding(w, plane, 0.0);
    subdivide(split.front, size, pieces);
    subdivide(split.back, size, pieces);
    return;
  }
  pieces.push_back(w);
}

// qbsp's SubdivideFace: Quake 1 faces wider than 240 texels are cut every 224 texels (the
// subdivide size less 16) along each texture axis, from the smallest texel coordinate up, so
// that each one fits the engine's surface cache. ericw-tools `light` sees these pieces.
void subdivideForQbsp(const Winding& w, const TextureFrame& frame, std::vector<Winding>& pieces) {
  constexpr double kSubdivideTexels = 240.0, kCutMargin = 16.0;
  std::vector<Winding> todo{w}, next;
  for (const dvec3& axis : {frame.tangent, frame.bitangent}) {
    const double scale = glm::length(axis);
    if (scale <= 0.0) continue;
    for (Winding rest : todo) {
      while (rest.size() >= 3) {
        double lo = 1e300, hi = -1e300;
        for (const dvec3& p : rest) lo = std::min(lo, glm::dot(p, axis)), hi = std::max(hi, glm::dot(p, axis));
        if (std::ceil(hi) - std::floor(lo) <= kSubdivideTexels) break;
        const Plane cut{axis / scale, (lo + kSubdivideTexels - kCutMargin) / scale};
        SplitWinding split = splitWinding(rest, cut, 0.0);
        if (split.front.size() < 3 || split.back.size() < 3) break; // nothing cut off: keep it whole
        next.push_back(std::move(split.back));
        rest = std::move(split.front);
      }
      if (rest.size() >= 3) next.push_back(std::move(rest));
    }
    todo.swap(next);
    next.clear();
  }
  for (Winding& piece : todo) pieces.push_back(std::move(piece));
}

dvec3 vertexMean(const Winding& w) {
  dvec3 sum(0.0);
  for (const dvec3& p : w) sum += p;
  return sum / double(w.size());
}

// Area-weighted centroid (ericw-tools' PolyCentroid); the vertex mean for a degenerate polygon.
dvec3 centroid(const Winding& w) {
  dvec3 sum(0.0);
  double totalArea = 0.0;
  for (size_t i = 1; i + 1 < w.size(); ++i) {
    const double a = glm::length(glm::cross(w[i] - w[0], w[i + 1] - w[0])) * 0.5;
    sum += a * (w[0] + w[i] + w[i + 1]) / 3.0;
    totalArea += a;
  }
  return totalArea > 0.0 ? sum / totalArea : vertexMean(w);
}

bool insideSolid(const Scene& scene, const std::vector<bool>& solidBrush, const dvec3& p) {
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    const Brush& brush = scene.brushes[b];
    if (!solidBrush[b] || brush.faceCount == 0) continue;
    bool inside = true;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount && inside; ++f)
      inside = scene.faces[f].plane.distanceTo(p) < -kInsideEpsilon;
    if (inside) return true;
  }
  return false;
}

// The Q1 kind: a full copy of the template on every grid piece of the face.
void addGridLights(const Face& face, const SurfaceTemplate& t, const Scene& scene, const std::vector<bool>& solidBrush,
                   std::vector<GpuLight>& out) {
  std::vector<Winding> qbspPieces;
  subdivideForQbsp(face.winding, face.frame, qbspPieces);
  for (const Winding& qbspPiece : qbspPieces)
  for (const Winding& piece : subdivideOnGrid(qbspPiece, kQ1SurfaceGrid)) {
    const dvec3 origin = centroid(piece) + face.plane.normal * double(t.offset);
    if (insideSolid(scene, solidBrush, origin)) continue;
    GpuLight light = t.light;
    light.origin = glm::vec3(origin);
    light.flags |= kLightFlagFromSurface;
    if (t.spotlight) light.direction = glm::vec3(face.plane.normal);
    out.push_back(light);
  }
}

// The radiosity kind: one point for the whole face, value x area, falling off as 1/d^2.
void addRadiosityLight(const Face& face, const SurfaceTemplate& t, const Scene& scene, const std::vector<bool>& solidBrush,
                       const std::vector<GpuMaterial>& materials, const WorldLighting& world, std::vector<GpuLight>& out) {
  const double faceArea = area(face.winding);
  if (faceArea < kMinEmitterArea) return;
  const dvec3 origin = vertexMean(face.winding) + face.plane.normal * kRadiosityLift;
  if (insideSolid(scene, solidBrush, origin)) return;

  // surflight.cc: colour (0..1) x light value; its brightest channel is the intensity, and the
  // colour is normalised by it only when that is above 1.
  glm::vec3 color = t.light.color;
  if (!t.hasColor && face.material < materials.size() && !scene.materials[face.material].baseColor.empty())
    color = linearToSrgb(glm::vec3(materials[face.material].averageAlbedo));
  color *= t.light.value;
  const float intensity = std::max({color.x, color.y, color.z});
  if (intensity <= 0.0f) return; // ericw-tools has no negative surface lights
  if (intensity > 1.0f) color /= intensity;

  GpuLight light;
  light.type = uint32_t(LightType::Point);
  light.formula = uint32_t(LightFormula::SurfaceRadiosity);
  light.origin = glm::vec3(origin);
  light.direction = glm::vec3(face.plane.normal);
  light.color = color;
  light.value = intensity * float(faceArea) * world.surflightScale;
  light.anglescale = 0.5f; // the receiver's (0.5 + 0.5 cos): ericw-tools' "rescale"
  light.flags = (t.light.flags & ~kLightFlagBleed) | kLightFlagFromSurface;
  out.push_back(light);
}

} // namespace

std::vector<Winding> subdivideOnGrid(const Winding& winding, double size) {
  std::vector<Winding> pieces;
  subdivide(winding, size, pieces);
  return pieces;
}

std::vector<GpuLight> spreadSurfaceLights(const Scene& scene, const std::vector<SurfaceTemplate>& templates,
                                          const std::vector<bool>& solidBrush, const std::vector<GpuMaterial>& materials,
                                          const WorldLighting& world) {
  std::vector<GpuLight> lights;
  for (const SurfaceTemplate& t : templates)
    for (const Face& face : scene.faces) {
      if (face.winding.size() < 3 || !equalsIgnoreCase(face.texture, t.texture)) continue;
      if (t.radiosity) addRadiosityLight(face, t, scene, solidBrush, materials, world, lights);
      else addGridLights(face, t, scene, solidBrush, lights);
    }
  return lights;
}

} // namespace bt

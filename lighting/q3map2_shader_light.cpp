#include "lighting/q3map2_shader_light.h"

#include "lighting/faithful.h"
#include "lighting/q3map2_light.h"
#include "scene/winding.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <future>

namespace bt::q3map2 {

namespace {

glm::vec3 shaderColor(const Q3ShaderLight& q3) {
  return {q3.color[0], q3.color[1], q3.color[2]};
}

GpuLight sun(const glm::vec3& toSun, float photons, const glm::vec3& color) {
  GpuLight light;
  light.type = uint32_t(LightType::Sun);
  light.value = photons;
  light.color = color;
  light.direction = -toSun;
  light.anglescale = 1.0f; // LIGHT_ATTEN_ANGLE: plain Lambert
  return light;
}

// One q3map_sun line: VectorNormalize'd colour; q3map_sunExt spreads it over `samples` suns
// within `deviance` degrees, which the tracers take as the mean over that cone.
GpuLight shaderSun(const Q3ShaderSun& s) {
  glm::vec3 color(s.color[0], s.color[1], s.color[2]);
  const float length = glm::length(color);
  color = length > 0.0f ? color / length : glm::vec3(0.0f);
  GpuLight light = sun(sunDirection(s.degrees, s.elevation), s.intensity, color);
  if (s.samples > 1) light.deviance = glm::radians(std::max(s.deviance, 0.0f));
  return light;
}

using dvec3 = glm::dvec3;

dvec3 boundsCentre(const Winding& w, dvec3& extent) {
  dvec3 lo(w[0]), hi(w[0]);
  for (const dvec3& p : w) lo = glm::min(lo, p), hi = glm::max(hi, p);
  extent = hi - lo;
  return (lo + hi) * 0.5;
}

// RadSubdivideDiffuseLight: cut at the middle of the bounds on the first axis wider than
// `subdivide`, recursively; then one area light per piece, and its backsplash.
void subdivide(const Winding& w, const dvec3& normal, const Q3ShaderLight& q3, float size, std::vector<GpuLight>& out, int depth = 0) {
  if (w.size() < 3 || out.size() > kMaxShaderLights) return;
  dvec3 extent;
  const dvec3 centre = boundsCentre(w, extent);
  for (int axis = 0; axis < 3; ++axis) {
    if (extent[axis] <= double(size) || depth > 40) continue;
    Plane plane;
    plane.normal = dvec3(0.0);
    plane.normal[axis] = 1.0;
    plane.dist = centre[axis];
    const SplitWinding halves = splitWinding(w, plane, 0.125); // RADIOSITY_CLIP_EPSILON
    subdivide(halves.front, normal, q3, size, out, depth + 1);
    subdivide(halves.back, normal, q3, size, out, depth + 1);
    return;
  }
  const double pieceArea = area(w);
  if (pieceArea < 1.0) return;
  const float photons = q3.surfaceLight * float(pieceArea) * kAreaScale;
  GpuLight light;
  light.type = uint32_t(LightType::Point);
  light.formula = uint32_t(LightFormula::Q3Area);
  light.origin = glm::vec3(centre + normal * double(kAreaLightLift));
  light.direction = glm::vec3(normal);
  light.color = shaderColor(q3);
  light.anglescale = 1.0f;
  light.value = photons / (faithful::kFormulaScale * faithful::kFormulaScale);
  light.falloff = std::sqrt(photons / kFalloffTolerance); // the envelope of -fast: beyond it, less than 1
  out.push_back(light);
  if (q3.backsplashFraction <= 0.0f) return;
  // The 2.5.17 backsplash: a plain q3map2 point light further out along the normal.
  GpuLight splash = light;
  const float splashPhotons = photons * q3.backsplashFraction;
  splash.formula = uint32_t(LightFormula::Q3Point);
  splash.origin = light.origin + glm::vec3(normal) * q3.backsplashDistance;
  splash.value = splashPhotons / (faithful::kFormulaScale * faithful::kFormulaScale);
  splash.falloff = std::sqrt(splashPhotons / kFalloffTolerance);
  splash.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  out.push_back(splash);
}

// What a face emits from: the compiled faces of a brush side (in fans of triangles, as q3map2
// triangulates planar surfaces), or a mesh triangle's front side.
std::vector<Winding> emittingTriangles(const Scene& scene, uint32_t f, const std::vector<BrushContents>& contents) {
  const Face& face = scene.faces[f];
  std::vector<Winding> polygons;
  if (face.brush != kNoBrush) {
    polygons = visibleFragments(scene, f, contents);
  } else {
    polygons.push_back(face.winding);
  }
  std::vector<Winding> triangles;
  for (const Winding& p : polygons)
    for (size_t i = 1; i + 1 < p.size(); ++i) triangles.push_back({p[0], p[i], p[i + 1]});
  return triangles;
}

bool isMeshBackSide(const Scene& scene, uint32_t f) {
  if (scene.faces[f].brush != kNoBrush) return false;
  for (const Mesh& m : scene.meshes)
    if (f >= m.firstFace && f < m.firstFace + m.faceCount) return (f - m.firstFace) % 2 == 1;
  return false;
}

} // namespace

glm::vec3 sunDirection(float degrees, float elevation) {
  const float a = glm::radians(degrees), e = glm::radians(elevation);
  return {std::cos(a) * std::cos(e), std::sin(a) * std::cos(e), std::sin(e)};
}

std::vector<glm::vec3> skyLightDirections(int iterations) {
  return faithful::skyDomeRings(iterations);
}

void addShaderSuns(const Scene& scene, SceneLights& out) {
  // A scene's materials are the textures its faces name (a .bsp's, those of its shader lump).
  for (const Material& material : scene.materials) {
    const Q3ShaderLight& q3 = material.q3;
    if (!q3.defined) continue;
    for (const Q3ShaderSun& s : q3.suns) out.lights.push_back(shaderSun(s));
    if (q3.skyLightValue <= 0.0f) continue;
    const std::vector<glm::vec3> dome = skyLightDirections(q3.skyLightIterations);
    const float photons = q3.skyLightValue / float(dome.size());
    for (const glm::vec3& toSky : dome) out.lights.push_back(sun(toSky, photons, shaderColor(q3)));
  }
}

std::vector<GpuLight> shaderSurfaceLights(const Scene& scene, const std::vector<BrushContents>& contents, const TraceScene& tracer,
                                          Diagnostics& diagnostics) {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    const Material& m = scene.materials[scene.faces[f].material];
    if (m.q3.surfaceLight > 0.0f && !m.q3.nodraw && !isMeshBackSide(scene, f)) faces.push_back(f);
  }
  if (faces.empty()) return {};
  const VoidTest inVoid(scene, tracer);
  std::vector<GpuLight> lights;
  for (uint32_t f : faces) {
    const Face& face = scene.faces[f];
    const Q3ShaderLight& q3 = scene.materials[face.material].q3;
    const float size = q3.subdivide > 0.0f ? q3.subdivide : kDefaultLightSubdivide;
    for (const Winding& triangle : emittingTriangles(scene, f, contents)) {
      const dvec3 middle = (triangle[0] + triangle[1] + triangle[2]) / 3.0;
      if (face.brush != kNoBrush && inVoid.inVoid(middle + face.plane.normal * kVoidProbeDistance)) continue;
      subdivide(triangle, face.plane.normal, q3, size, lights);
    }
    if (lights.size() > kMaxShaderLights) {
      lights.resize(kMaxShaderLights);
      diagnostics.push_back(
          {Severity::Warning, scene.sourcePath, face.line, 0,
           fmt::format("q3map_surfacelight: more than {} surface light pieces; the rest are left out", kMaxShaderLights)});
      break;
    }
  }
  return lights;
}

uint32_t shaderFaceFlags(const Material& material) {
  uint32_t flags = 0;
  if (material.q3.sky) flags |= kFaceSky;
  if (material.q3.nodraw && !material.q3.sky) flags |= kFaceHidden;
  // A blended shader is drawn over what lies behind it and unlit (its image alone, as a
  // one-stage shader without $lightmap is drawn), as the liquids are (lighting/liquids.h), and casts no shadow: q3map2's light_trace.c
  // PopulateWithBSPModel leaves out `surfaceparm trans` surfaces without alphashadow or
  // lightfilter (the blended ones without `trans` cast a shadow there; not here).
  if (material.blend != ShaderBlend::Opaque && !material.q3.sky) flags |= kFaceLiquid;
  return flags;
}

} // namespace bt::q3map2

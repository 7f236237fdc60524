#include "viewer/picking.h"

#include "lighting/faithful_light.h"
#include "lighting/visibility.h"
#include "renderer/cpu/integrator.h"
#include "quake/entity_keys.h"
#include "scene/gpu_structs.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace bt {

namespace {

constexpr size_t kPickNamedLights = 8;  // the largest shares named in the panel
constexpr int kPickSoftSamples = 64;    // draws of each soft light (penumbra, _deviance, dome)
constexpr int kPickPhysicalPaths = 256; // physical mode: paths along the picked pixel's ray

std::string at(const std::string& file, int line) {
  return line > 0 ? fmt::format("{}:{}", file, line) : file + " (no line: a compiled level)";
}

// What qbsp and the tracers make of the face: Quake 2/3 contents where the format has them.
std::string kindOf(const RenderScene& rs, const Face& face, uint32_t index) {
  const uint32_t flags = rs.faceFlags[index];
  std::string kind = (flags & kFaceSky) ? "sky" : (flags & kFaceLiquid) ? "liquid" : "solid";
  if (flags & kFaceNoShadow) kind += ", casts no shadow";
  if (flags & kFaceEmissive) kind += ", emissive";
  if (face.surface)
    kind += fmt::format(" | contents 0x{:x}, surface flags 0x{:x}, value {:g}", uint32_t(face.surface->contents),
                        uint32_t(face.surface->flags), face.surface->value);
  return kind;
}

float brightness(const glm::vec3& rgb) {
  return rgb.r + rgb.g + rgb.b;
}

// The light entity a point light came from, found by its origin (lights do not keep their
// entity): its classname and file:line, or what kind of light it is when no entity has it.
std::string lightName(const Scene& scene, const GpuLight& light) {
  if (light.type == uint32_t(LightType::Sun)) return "sun";
  if (light.type == uint32_t(LightType::Dome)) return "sky dome";
  if (light.flags & kLightFlagFromSurface)
    return fmt::format("surface light point ({:g} {:g} {:g})", light.origin.x, light.origin.y, light.origin.z);
  for (const Entity& e : scene.entities) {
    if (!e.classname().starts_with("light")) continue;
    const auto origin = quake::EntityKeys(e).vec3("origin");
    if (origin && glm::all(glm::lessThan(glm::abs(*origin - light.origin), glm::vec3(0.01f))))
      return fmt::format("{} ({:g} {:g} {:g}) {}:{}", e.classname(), light.origin.x, light.origin.y, light.origin.z, scene.sourcePath,
                         e.line);
  }
  return fmt::format("light ({:g} {:g} {:g})", light.origin.x, light.origin.y, light.origin.z);
}

// The lights' shares as lines: the largest named, the rest summed. `grouped(i)`: a light summed
// in a line of its own (faithful mode's bounce lights), not named.
template <typename Grouped> void addNamedShares(const RenderScene& rs, const std::vector<glm::vec3>& perLight, float total,
                                                const Grouped& grouped, std::vector<std::string>& lines) {
  const auto percent = [&](const glm::vec3& rgb) { return 100.0f * brightness(rgb) / total; };
  std::vector<size_t> order;
  for (size_t i = 0; i < perLight.size(); ++i)
    if (brightness(perLight[i]) > 0.0f && !grouped(i)) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return brightness(perLight[a]) > brightness(perLight[b]); });
  glm::vec3 rest(0.0f);
  for (size_t k = 0; k < order.size(); ++k) {
    if (k < kPickNamedLights)
      lines.push_back(fmt::format("  {:5.1f} %  {}", percent(perLight[order[k]]), lightName(*rs.scene, rs.lights[order[k]])));
    else
      rest += perLight[order[k]];
  }
  if (order.size() > kPickNamedLights)
    lines.push_back(fmt::format("  {:5.1f} %  {} more lights", percent(rest), order.size() - kPickNamedLights));
}

// Physical mode: the light leaving the point towards the camera, each light's direct share, and
// emitters and bounced light as the rest of the paths' mean (physicalLightShares).
void addPhysicalShares(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, std::vector<std::string>& lines) {
  Rng rng(0x9e3779b9u);
  const PhysicalShares shares = physicalLightShares(rs, settings, ray, kPickPhysicalPaths, rng);
  lines.push_back(fmt::format("physical light here {:.4g} {:.4g} {:.4g} (linear, before exposure; {} paths)", shares.shown.r,
                              shares.shown.g, shares.shown.b, shares.samples));
  const float total = brightness(shares.shown);
  if (!(total > 0.0f)) return;
  const auto noneGrouped = [](size_t) { return false; };
  addNamedShares(rs, shares.perLight, total, noneGrouped, lines);
  if (brightness(shares.minlight) > 0.0f)
    lines.push_back(fmt::format("  {:5.1f} %  minlight", 100.0f * brightness(shares.minlight) / total));
  lines.push_back(fmt::format("  {:5.1f} %  sky, emitting surfaces and bounced light ({} bounces)",
                              100.0f * brightness(shares.rest) / total, settings.bounces));
}

// The light at the picked point, light by light: the largest shares named, bounce lights and
// the rest summed, then the floors, so that the percentages add up to the light shown.
void addLightShares(const RenderScene& rs, const SurfaceHit& hit, std::vector<std::string>& lines) {
  FaithfulQuery q;
  q.p = hit.position;
  q.n = hit.normal;
  q.twoSided = rs.faceFlags[hit.face] & kFaceLiquid;
  q.channels = objectChannels(rs, hit.face);
  q.faceMinlight = faithfulFaceMinlight(rs, hit.face);
  Rng rng(0x9e3779b9u);
  const LightShares shares = faithfulLightShares(rs, q, kPickSoftSamples, rng);
  const float total = brightness(shares.shown);
  lines.push_back(fmt::format("faithful light here {:.0f} {:.0f} {:.0f} (light units, before the display)", shares.shown.r, shares.shown.g,
                              shares.shown.b));
  if (!(total > 0.0f)) return;
  const auto percent = [&](const glm::vec3& rgb) { return 100.0f * brightness(rgb) / total; };
  const auto isBounce = [&](size_t i) {
    return rs.lights[i].formula == uint32_t(LightFormula::Bounce) && rs.lights[i].type == uint32_t(LightType::Point);
  };
  addNamedShares(rs, shares.perLight, total, isBounce, lines);
  glm::vec3 bounce(0.0f);
  size_t bounceCount = 0;
  for (size_t i = 0; i < shares.perLight.size(); ++i)
    if (isBounce(i) && brightness(shares.perLight[i]) > 0.0f) bounce += shares.perLight[i], ++bounceCount;
  if (bounceCount > 0) lines.push_back(fmt::format("  {:5.1f} %  bounce ({} bounce lights)", percent(bounce), bounceCount));
  if (brightness(shares.ambient) > 0.0f) lines.push_back(fmt::format("  {:5.1f} %  _ambient", percent(shares.ambient)));
  if (brightness(shares.floors) > 0.0f) lines.push_back(fmt::format("  {:5.1f} %  minlight floors", percent(shares.floors)));
  if (shares.occlusion > 0.0f) lines.push_back(fmt::format("  dirt {:.2f} (0 open, 1 enclosed)", shares.occlusion));
}

} // namespace

PickedFace pickFace(const RenderScene& rs, const CameraPose& pose, int width, int height, float x, float y,
                    const IntegratorSettings& lighting) {
  PickedFace picked;
  const Ray ray = Camera(pose, width, height).ray(x, y);
  const SurfaceHit hit = traceVisible(rs, ray);
  if (!hit.found) return picked;
  const Scene& scene = *rs.scene;
  const Face& face = scene.faces[hit.face];
  const std::string& file = scene.sourcePath;
  picked.hit = true;
  picked.fileLine = face.line > 0 ? fmt::format("{}:{}", file, face.line) : "";
  picked.lines.push_back(fmt::format("face {}: {}", hit.face, at(file, face.line)));
  if (face.brush != kNoBrush)
    picked.lines.push_back(fmt::format("brush {}: {}", face.brush, at(file, scene.brushes[face.brush].line)));
  else
    picked.lines.push_back("a curve or triangle-soup triangle");
  const Material& material = scene.materials[face.material];
  picked.lines.push_back(fmt::format("texture {} ({}x{}, {})", face.texture, material.width, material.height, toString(material.source)));
  const uint32_t entity = scene.faceEntity(hit.face);
  if (entity < scene.entities.size())
    picked.lines.push_back(
        fmt::format("entity {} {}: {}", entity, scene.entities[entity].classname(), at(file, scene.entities[entity].line)));
  picked.lines.push_back(kindOf(rs, face, hit.face));
  picked.lines.push_back(fmt::format("point ({:g} {:g} {:g}), normal ({:g} {:g} {:g})", hit.position.x, hit.position.y, hit.position.z,
                                     hit.normal.x, hit.normal.y, hit.normal.z));
  if (lighting.mode == LightingMode::Physical)
    addPhysicalShares(rs, lighting, ray, picked.lines);
  else if (!(rs.faceFlags[hit.face] & kFaceSky))
    addLightShares(rs, hit, picked.lines);
  return picked;
}

} // namespace bt

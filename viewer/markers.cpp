#include "viewer/markers.h"

#include "lighting/faithful.h"
#include "lighting/physical_light.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace bt {

namespace {

constexpr float kEntityHalfSize = 8.0f;        // a point entity's box, in units
constexpr float kUnboundedConeLength = 256.0f; // how far a cone is drawn for a light that never ends
constexpr int kCircleSegments = 48;

bool lightFromEntity(const GpuLight& light) {
  if (light.type != uint32_t(LightType::Point) || (light.flags & kLightFlagFromSurface)) return false;
  const auto formula = LightFormula(light.formula);
  return formula != LightFormula::Bounce && formula != LightFormula::SurfaceRadiosity && formula != LightFormula::Q3Area;
}

LightMarker lightMarker(const GpuLight& light, float scaledist) {
  LightMarker m;
  m.origin = light.origin;
  m.color = light.color;
  m.reach = physical::reach(light, scaledist);
  m.axis = light.direction;
  m.cosOuter = light.cosOuter;
  // The formula's light along the axis (facing the light, so the angle term is 1), against its
  // light 16 units away: the rings fade as the light does.
  const auto value = [&](float d) {
    return std::abs(faithful::pointLightValue(light, glm::vec3(0, 0, 1), glm::vec3(0, 0, 1), d, scaledist));
  };
  const float near = std::max(value(16.0f), 1e-6f);
  const float shown = std::isfinite(m.reach) ? m.reach : 512.0f;
  for (int k = 0; k < 4; ++k) m.rings[k] = std::clamp(value(shown * float(k + 1) / 4.0f) / near, 0.0f, 1.0f);
  return m;
}

ImU32 colour(const glm::vec3& rgb, float alpha) {
  const auto byte = [](float c) { return int(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); };
  return IM_COL32(byte(rgb.r), byte(rgb.g), byte(rgb.b), byte(alpha));
}

// Image pixels to window coordinates.
struct Projector {
  const Camera& camera;
  glm::vec2 scale;
  std::optional<ImVec2> operator()(const glm::vec3& p) const {
    const auto pixel = camera.project(p);
    if (!pixel) return std::nullopt;
    return ImVec2(pixel->x * scale.x, pixel->y * scale.y);
  }
};

// A circle in 3D (centre, radius, the plane's two axes) as a polyline of the segments in front.
void circle3d(ImDrawList& draw, const Projector& at, glm::vec3 centre, float radius, glm::vec3 u, glm::vec3 v, ImU32 col) {
  std::optional<ImVec2> previous;
  for (int i = 0; i <= kCircleSegments; ++i) {
    const float a = 2.0f * std::numbers::pi_v<float> * float(i) / float(kCircleSegments);
    const auto point = at(centre + radius * (std::cos(a) * u + std::sin(a) * v));
    if (point && previous) draw.AddLine(*previous, *point, col, 1.5f);
    previous = point;
  }
}

void drawLight(ImDrawList& draw, const LightMarker& light, const Projector& at, const Camera& camera) {
  const auto centre = at(light.origin);
  if (centre) draw.AddCircleFilled(*centre, 3.0f, colour(light.color, 255));
  const bool bounded = std::isfinite(light.reach);
  const float shown = bounded ? light.reach : kUnboundedConeLength;
  // The rings face the camera: a sphere's outline wherever it is seen from.
  const glm::vec3 forward = camera.forward();
  const glm::vec3 u =
      glm::normalize(std::abs(forward.z) < 0.9f ? glm::cross(forward, glm::vec3(0, 0, 1)) : glm::cross(forward, glm::vec3(1, 0, 0)));
  const glm::vec3 v = glm::cross(forward, u);
  if (bounded)
    for (int k = 0; k < 4; ++k)
      circle3d(draw, at, light.origin, shown * float(k + 1) / 4.0f, u, v, colour(light.color, 60.0f + 195.0f * light.rings[k]));
  else if (centre)
    draw.AddText(ImVec2(centre->x + 5, centre->y - 7), colour(light.color, 255), "no end");
  if (light.cosOuter < -1.0f) return;
  const glm::vec3 axis = glm::normalize(light.axis);
  const glm::vec3 a = glm::normalize(std::abs(axis.z) < 0.9f ? glm::cross(axis, glm::vec3(0, 0, 1)) : glm::cross(axis, glm::vec3(1, 0, 0)));
  const glm::vec3 b = glm::cross(axis, a);
  const float sine = std::sqrt(std::max(0.0f, 1.0f - light.cosOuter * light.cosOuter));
  const glm::vec3 end = light.origin + axis * (shown * light.cosOuter);
  const float endRadius = shown * sine;
  for (const glm::vec3& side : {a, b, -a, -b}) {
    const auto from = at(light.origin), to = at(end + side * endRadius);
    if (from && to) draw.AddLine(*from, *to, colour(light.color, 200), 1.5f);
  }
  circle3d(draw, at, end, endRadius, a, b, colour(light.color, 200));
}

// A point entity's box; true when the cursor is inside its outline.
bool drawEntity(ImDrawList& draw, const EntityMarker& entity, const Projector& at, ImVec2 mouse) {
  ImVec2 corners[8];
  ImVec2 lo(1e30f, 1e30f), hi(-1e30f, -1e30f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 offset((i & 1) ? kEntityHalfSize : -kEntityHalfSize, (i & 2) ? kEntityHalfSize : -kEntityHalfSize,
                           (i & 4) ? kEntityHalfSize : -kEntityHalfSize);
    const auto p = at(entity.origin + offset);
    if (!p) return false; // partly behind the camera: not drawn
    corners[i] = *p;
    lo = ImVec2(std::min(lo.x, p->x), std::min(lo.y, p->y)), hi = ImVec2(std::max(hi.x, p->x), std::max(hi.y, p->y));
  }
  const bool hovered = mouse.x >= lo.x && mouse.x <= hi.x && mouse.y >= lo.y && mouse.y <= hi.y;
  const ImU32 col = hovered ? IM_COL32(255, 255, 0, 255) : IM_COL32(0, 255, 160, 200);
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) draw.AddLine(corners[i], corners[i | bit], col, 1.0f);
  return hovered;
}

} // namespace

Markers collectMarkers(const RenderScene& rs) {
  Markers markers;
  const Scene& scene = *rs.scene;
  for (const Entity& e : scene.entities) {
    if (e.brushCount > 0 || e.classname() == "worldspawn") continue;
    const auto origin = quake::EntityKeys(e).vec3("origin");
    if (!origin) continue;
    markers.entities.push_back({*origin, fmt::format("{} {}:{}", e.classname(), scene.sourcePath, e.line)});
  }
  for (const GpuLight& light : rs.lights)
    if (lightFromEntity(light)) markers.lights.push_back(lightMarker(light, rs.world.scaledist));
  return markers;
}

std::string drawMarkers(ImDrawList& draw, const Markers& markers, const Camera& camera, glm::vec2 imageSize, glm::vec2 displaySize,
                        glm::vec2 mouse) {
  const Projector at{camera, displaySize / glm::max(imageSize, glm::vec2(1.0f))};
  for (const LightMarker& light : markers.lights) drawLight(draw, light, at, camera);
  std::string hovered;
  for (const EntityMarker& entity : markers.entities)
    if (drawEntity(draw, entity, at, ImVec2(mouse.x, mouse.y))) hovered = entity.label;
  return hovered;
}

void MarkerLayer::draw(const Camera& camera, int width, int height) const {
  if (!shown_) return;
  const ImGuiIO& io = ImGui::GetIO();
  const std::string hovered = drawMarkers(*ImGui::GetBackgroundDrawList(), markers_, camera, glm::vec2(width, height),
                                          glm::vec2(io.DisplaySize.x, io.DisplaySize.y), glm::vec2(io.MousePos.x, io.MousePos.y));
  if (!hovered.empty()) ImGui::SetTooltip("%s", hovered.c_str());
}

} // namespace bt

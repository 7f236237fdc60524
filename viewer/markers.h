// Light and point-entity markers over the image (key L), the feature TrenchBroom users have
// asked for since 2016 (TrenchBroom issue #1348): every point entity a box, named with its
// classname and file:line when the cursor is on it; every light a gizmo of its reach, the
// distance where the compiler's falloff ends (physical::reach), as rings in its `_color` whose
// brightness follows the light's formula (the `delay` gradient), with its cone for spotlights.
#pragma once

#include "lighting/render_scene.h"
#include "renderer/camera.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

struct ImDrawList;

namespace bt {

struct EntityMarker {
  glm::vec3 origin{0.0f};
  std::string label; // classname and file:line
};

struct LightMarker {
  glm::vec3 origin{0.0f};
  glm::vec3 color{1.0f};
  float reach = 0.0f;   // where its light ends; infinity for lights that never fall off
  float rings[4] = {};  // the formula's light at reach x 1/4, 2/4, 3/4, 1, relative to its light at 16 units
  glm::vec3 axis{0.0f}; // spotlights: the cone's axis, and cos of its half angle (below -1: no cone)
  float cosOuter = -2.0f;
};

struct Markers {
  std::vector<EntityMarker> entities;
  std::vector<LightMarker> lights;
};

// Once per level: the point entities (no brushes, an origin) and the lights that came from
// entities (not `_surface` points, not bounce lights, not suns or domes).
Markers collectMarkers(const RenderScene& rs);

// Draws them for a camera whose image of width x height pixels fills `displaySize` (window
// coordinates); `mouse` in window coordinates. Returns the label under the cursor ("" if none).
std::string drawMarkers(ImDrawList& draw, const Markers& markers, const Camera& camera, glm::vec2 imageSize, glm::vec2 displaySize,
                        glm::vec2 mouse);

// The viewer's marker layer: the markers of the level on screen, shown or not (key L).
class MarkerLayer {
public:
  void setLevel(const RenderScene& rs) { markers_ = collectMarkers(rs); }
  void toggle() { shown_ = !shown_; }
  bool shown() const { return shown_; }
  // Into the current imgui frame, over the image (width x height pixels scaled to the window),
  // with the hovered entity's label as a tooltip.
  void draw(const Camera& camera, int width, int height) const;

private:
  Markers markers_;
  bool shown_ = false;
};

} // namespace bt

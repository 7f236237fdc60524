// Light selection data: which lights a point has to look at, so that a hit does not loop over
// every light of the level (lq_e4m3 has over a thousand). The flat layout is scene/gpu_structs.h's
// GpuLightGrid/GpuLightCell plus one index array; the GL tracer uploads the three unchanged and
// shaders/light_select.glsl reads them the way lightGridCell() below does.
//
// Quake's linear lights (delay 0, and _falloff) reach a finite distance, so a uniform grid can
// list, per cell, the lights that can light anything in it. The other formulas and the suns
// reach everywhere and sit in lists of their own (see gpu_structs.h for the ranges).
#pragma once

#include "lighting/light_tree.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <span>
#include <vector>

namespace bt {

struct LightGrid {
  GpuLightGrid header;
  std::vector<GpuLightCell> cells;
  std::vector<uint32_t> indices; // into RenderScene::lights
  // A light tree over the physical list (light_tree.h): IntegratorSettings::PhysicalPick::Tree.
  std::vector<LightTreeNode> physicalTree;

  // Suns, domes and local-minlight lights: evaluated one by one everywhere.
  std::span<const uint32_t> fixedLights() const { return {indices.data(), header.fixedCount}; }
  // Faithful point lights of infinite reach: candidates everywhere.
  std::span<const uint32_t> globalLights() const { return {indices.data() + header.globalFirst, header.globalCount}; }
  // Physical mode's point-light candidates.
  std::span<const uint32_t> physicalLights() const { return {indices.data() + header.physicalFirst, header.physicalCount}; }
  // Faithful point lights of finite reach that can light p.
  std::span<const uint32_t> cellLights(const glm::vec3& p) const;
  // Physical mode: the lights of the physical list likely to matter most at p (see
  // kPhysicalNearLights); the rest stay reachable through the whole physical list.
  std::span<const uint32_t> physicalNearLights(const glm::vec3& p) const;
  // Physical mode: every other light of the physical list whose windowed reach (physical_light.h)
  // touches p's cell, in index order; the pick's uniform draw. A light in neither list gives p
  // exactly 0.
  std::span<const uint32_t> physicalRestLights(const glm::vec3& p) const;
};

// Physical point lights reach everywhere (1/d^2), so a cell cannot list all that light it.
// Each cell lists at most this many, ranked by an upper bound of their irradiance in the cell
// (power / squared distance to the cell); selection samples them by their actual unshadowed
// irradiance at the hit and, with a small probability, one of the cell's other lights in reach
// uniformly (physicalRestLights).
inline constexpr uint32_t kPhysicalNearLights = 32;

// Beyond this distance from its origin a faithful point light gives exactly 0 (for any _deviance
// jitter of its position), or +infinity when its formula never reaches 0.
float faithfulReach(const GpuLight& light, float scaledist);

// How many lights at the end of `list` (indices into `lights`) are bounce lights
// (LightFormula::Bounce). buildLightGrid lists a cell's bounce lights after its others, so these
// are all of the cell's: a level's hundreds of them that the renderer draws among instead of
// shadow-testing each (faithful_light.h kBounceShadowRays).
size_t trailingBounceLights(const std::vector<GpuLight>& lights, std::span<const uint32_t> list);

// Grid resolution: at most this many cells along the longest axis (and cells no smaller than 64
// units). The renderer's grid; a coarser one lists more lights per cell but is built sooner.
inline constexpr uint32_t kMaxLightGridCellsPerAxis = 32;

// The grid over `bounds` (the level's traceable brushes; points outside it still get a correct
// list). Point lights of value 0 light nothing in either mode and are in no list.
LightGrid buildLightGrid(const std::vector<GpuLight>& lights, const Bounds& bounds, float scaledist,
                         uint32_t maxCellsPerAxis = kMaxLightGridCellsPerAxis);

// buildLightGrid(lights, bounds, scaledist, maxCellsPerAxis), from `grid`, that of lights' first
// `first` (with the same bounds, scaledist and cells): the same grid, sooner where the new lights
// are none of physical mode's (bounce lights), whose near lists it keeps instead of ranking again.
LightGrid extendLightGrid(const LightGrid& grid, const std::vector<GpuLight>& lights, uint32_t first, const Bounds& bounds, float scaledist,
                          uint32_t maxCellsPerAxis = kMaxLightGridCellsPerAxis);

// The cell holding p, clamped to the grid (NaN goes to cell 0).
uint32_t lightGridCell(const GpuLightGrid& grid, const glm::vec3& p);

} // namespace bt

// Quake 3 curves: a grid of biquadratic Bezier patches tessellated into a grid of points on the
// surface, as the Quake 3 engine does it (R_SubdividePatchToGrid in ioquake3's
// code/renderergl1/tr_curve.c), so that the preview shows the curves the game shows at full
// detail (no distance LOD; the engine's r_subdivisions 4 is the error bound).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace bt {

struct PatchPoint {
  glm::dvec3 position{0.0};
  glm::dvec2 st{0.0}; // any units; interpolated with the position
};

// points[row * width + column]. A control grid has odd width and height, at least 3 each:
// 3x3 points per biquadratic patch, neighbours sharing their edge row or column.
struct PatchGrid {
  int width = 0;
  int height = 0;
  std::vector<PatchPoint> points;

  const PatchPoint& at(int row, int column) const { return points[static_cast<size_t>(row * width + column)]; }
};

// The engine's r_subdivisions default: the most a chord may lie off the curve, in units.
inline constexpr double kPatchMaxError = 4.0;
// tr_curve.c's MAX_GRID_SIZE: the tessellated grid has at most this many points a side.
inline constexpr int kPatchMaxGridSize = 65;

// Why a control grid cannot be tessellated ("" when it can): sizes that are even, below 3, or
// above 65 (the engine's MAX_GRID_SIZE), or a point count that does not match.
std::string patchGridProblem(const PatchGrid& control);

// The tessellated grid: every point lies on the Bezier surface. As tr_curve.c: each column
// (then row) span of a patch is halved by de Casteljau until the curve lies within maxError of
// its chords, measured at the span's midpoint against the line through its ends; spans that are
// straight (within 0.1 unit) on every row lose their middle column. Requires a valid grid.
PatchGrid tessellatePatch(const PatchGrid& control, double maxError = kPatchMaxError);

// The point of the Bezier surface at (u, v) in [0, 1]^2 of patch (patchRow, patchColumn) of a
// control grid (patch k spans control rows/columns 2k .. 2k + 2): what tests hold the grid to.
PatchPoint evaluatePatch(const PatchGrid& control, int patchRow, int patchColumn, double u, double v);

} // namespace bt

#include "scene/curves.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt {
namespace {

PatchPoint lerpHalf(const PatchPoint& a, const PatchPoint& b) {
  return {(a.position + b.position) * 0.5, (a.st + b.st) * 0.5};
}

// A grid being subdivided: rows of points, transposed between the two passes as tr_curve.c does.
using Rows = std::vector<std::vector<PatchPoint>>;

Rows transposed(const Rows& rows) {
  Rows out(rows.front().size(), std::vector<PatchPoint>(rows.size()));
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < rows[i].size(); ++j) out[j][i] = rows[i][j];
  return out;
}

// How far the curve of span (j, j+1, j+2) lies off its chord, the worst row: tr_curve.c
// measures the Bezier midpoint's distance from the line through the span's ends (not from the
// chord's midpoint: it gives fewer triangles and ignores texture warping, as the engine does).
double spanError(const Rows& rows, size_t j) {
  double worst = 0.0;
  for (const auto& row : rows) {
    const glm::dvec3 mid = (row[j].position + row[j + 1].position * 2.0 + row[j + 2].position) * 0.25 - row[j].position;
    glm::dvec3 dir = row[j + 2].position - row[j].position;
    const double length = glm::length(dir);
    if (length > 0.0) dir /= length;
    const glm::dvec3 off = mid - dir * glm::dot(mid, dir);
    worst = std::max(worst, glm::dot(off, off));
  }
  return std::sqrt(worst);
}

// One pass of tr_curve.c's subdivision along the rows; returns for each column whether it is
// the middle of a straight span (the engine's errorTable 999), to be removed at the end.
std::vector<bool> subdivideRows(Rows& rows, double maxError) {
  std::vector<bool> straight(rows.front().size(), false);
  for (size_t j = 0; j + 2 < rows.front().size(); j += 2) {
    const double error = spanError(rows, j);
    if (error < 0.1) {
      straight[j + 1] = true;
      continue;
    }
    if (rows.front().size() + 2 > size_t(kPatchMaxGridSize) || error <= maxError) continue;
    // Halve the span: its quadratic becomes two, (a, prev, mid) and (mid, next, c).
    for (auto& row : rows) {
      const PatchPoint prev = lerpHalf(row[j], row[j + 1]), next = lerpHalf(row[j + 1], row[j + 2]);
      const PatchPoint mid = lerpHalf(prev, next);
      row[j + 1] = prev;
      row.insert(row.begin() + std::ptrdiff_t(j + 2), {mid, next});
    }
    straight.insert(straight.begin() + std::ptrdiff_t(j + 2), {false, false});
    j -= 2; // look at the first half again: it may need more
  }
  return straight;
}

// tr_curve.c's PutPointsOnCurve: after subdivision every span is a quadratic whose odd point is
// a control point; its curve point at the middle is (a + 2 b + c) / 4.
void putPointsOnCurve(Rows& rows) {
  for (size_t i = 1; i + 1 < rows.size(); i += 2)
    for (size_t j = 0; j < rows[i].size(); ++j)
      rows[i][j] = lerpHalf(lerpHalf(rows[i][j], rows[i + 1][j]), lerpHalf(rows[i][j], rows[i - 1][j]));
  for (auto& row : rows)
    for (size_t j = 1; j + 1 < row.size(); j += 2) row[j] = lerpHalf(lerpHalf(row[j], row[j + 1]), lerpHalf(row[j], row[j - 1]));
}

void removeColumns(Rows& rows, const std::vector<bool>& remove) {
  for (auto& row : rows) {
    std::vector<PatchPoint> kept;
    for (size_t j = 0; j < row.size(); ++j)
      if (!remove[j]) kept.push_back(row[j]);
    row = std::move(kept);
  }
}

} // namespace

std::string patchGridProblem(const PatchGrid& control) {
  auto bad = [](int n) { return n < 3 || n % 2 == 0 || n > kPatchMaxGridSize; };
  if (bad(control.width) || bad(control.height))
    return fmt::format("a patch of {}x{} control points (each side must be odd, 3 to {})", control.width, control.height,
                       kPatchMaxGridSize);
  if (control.points.size() != size_t(control.width) * size_t(control.height))
    return fmt::format("a {}x{} patch with {} control points", control.width, control.height, control.points.size());
  return {};
}

PatchGrid tessellatePatch(const PatchGrid& control, double maxError) {
  Rows rows(size_t(control.height), std::vector<PatchPoint>(size_t(control.width)));
  for (int i = 0; i < control.height; ++i)
    for (int j = 0; j < control.width; ++j) rows[size_t(i)][size_t(j)] = control.at(i, j);
  // Along the rows, then (transposed) along the columns, as the engine's two passes.
  const std::vector<bool> straightColumns = subdivideRows(rows, maxError);
  rows = transposed(rows);
  const std::vector<bool> straightRows = subdivideRows(rows, maxError);
  rows = transposed(rows);
  putPointsOnCurve(rows);
  removeColumns(rows, straightColumns);
  rows = transposed(rows);
  removeColumns(rows, straightRows);
  rows = transposed(rows);

  PatchGrid grid;
  grid.height = int(rows.size());
  grid.width = int(rows.front().size());
  for (const auto& row : rows) grid.points.insert(grid.points.end(), row.begin(), row.end());
  return grid;
}

PatchPoint evaluatePatch(const PatchGrid& control, int patchRow, int patchColumn, double u, double v) {
  auto basis = [](double x) { return glm::dvec3((1 - x) * (1 - x), 2 * x * (1 - x), x * x); };
  const glm::dvec3 bu = basis(u), bv = basis(v);
  PatchPoint p{glm::dvec3(0.0), glm::dvec2(0.0)};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const PatchPoint& c = control.at(2 * patchRow + i, 2 * patchColumn + j);
      p.position += c.position * (bv[i] * bu[j]);
      p.st += c.st * (bv[i] * bu[j]);
    }
  return p;
}

} // namespace bt

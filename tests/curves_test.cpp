// Quake 3 curves (scene/curves.h) and mesh triangles' faces (Scene::addMeshTriangle).
#include "scene/curves.h"
#include "scene/scene.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>

namespace bt {
namespace {

// A control grid from a function of (row, column).
template <class Point> PatchGrid grid(int width, int height, const Point& point) {
  PatchGrid g{width, height, {}};
  for (int i = 0; i < height; ++i)
    for (int j = 0; j < width; ++j) g.points.push_back(point(i, j));
  return g;
}

// The st of the control points are their parameters (column / 2, row / 2): a quadratic Bezier of
// evenly spaced values is linear, so each tessellated point's st is the (u, v) it lies at.
PatchPoint parametric(const glm::dvec3& p, int i, int j) {
  return {p, {j * 0.5, i * 0.5}};
}

// A half pipe along y (the arch a mapper makes from a 3x3 patch), then a second patch bending back.
PatchGrid pipe() {
  const glm::dvec3 arc[5] = {{128, 0, 0}, {128, 0, 128}, {0, 0, 128}, {-128, 0, 128}, {-128, 0, 0}};
  return grid(5, 3, [&](int i, int j) { return parametric(arc[j] + glm::dvec3(0, 64.0 * i, 0), i, j); });
}

TEST(Curves, FlatPatchStaysFlatWithExactSt) {
  // Control points on the plane z = 40 in an irregular (but planar) layout; st an affine function
  // of the position, as a texture projected onto the plane.
  auto st = [](const glm::dvec3& p) { return glm::dvec2(p.x / 64.0 + 0.25, -p.y / 32.0 + 1.0); };
  const PatchGrid control = grid(3, 3, [&](int i, int j) {
    const glm::dvec3 p(64.0 * j + (i == 1 ? 40.0 : 0.0), 64.0 * i + (j == 1 ? -24.0 : 0.0), 40.0);
    return PatchPoint{p, st(p)};
  });
  ASSERT_EQ(patchGridProblem(control), "");
  const PatchGrid tessellated = tessellatePatch(control);
  ASSERT_GE(tessellated.width, 3); // the control polygon bends within the plane: it is subdivided
  for (const PatchPoint& p : tessellated.points) {
    EXPECT_EQ(p.position.z, 40.0);
    EXPECT_NEAR(p.st.x, st(p.position).x, 1e-12);
    EXPECT_NEAR(p.st.y, st(p.position).y, 1e-12);
  }
  // A straight, evenly spaced patch keeps only its corners (tr_curve.c drops colinear columns).
  const PatchGrid square = grid(3, 3, [&](int i, int j) { return parametric(glm::dvec3(32.0 * j, 32.0 * i, 0.0), i, j); });
  const PatchGrid corners = tessellatePatch(square);
  EXPECT_EQ(corners.width, 2);
  EXPECT_EQ(corners.height, 2);
  EXPECT_EQ(corners.at(1, 1).position, glm::dvec3(64, 64, 0));
  EXPECT_EQ(corners.at(1, 1).st, glm::dvec2(1, 1));
}

TEST(Curves, PointsLieOnTheBezierSurfaceWithinTheEnginesError) {
  const PatchGrid control = pipe();
  const PatchGrid tessellated = tessellatePatch(control);
  // Along the pipe (straight) only the ends stay; around it the arcs are halved until their
  // chords lie within 4 units of the curve.
  EXPECT_EQ(tessellated.height, 2);
  EXPECT_GT(tessellated.width, 5);
  for (const PatchPoint& p : tessellated.points) {
    // Which patch and (u, v) the point lies at, from its st (see parametric()).
    const int patch = std::min(int(p.st.x), 1);
    const PatchPoint expected = evaluatePatch(control, 0, patch, p.st.x - patch, p.st.y);
    EXPECT_NEAR(glm::length(p.position - expected.position), 0.0, 1e-9) << p.st.x << " " << p.st.y;
  }
  // Between neighbours the chord stays within r_subdivisions (4 units) of the surface.
  for (int j = 0; j + 1 < tessellated.width; ++j) {
    const PatchPoint& a = tessellated.at(0, j);
    const PatchPoint& b = tessellated.at(0, j + 1);
    const double u = (a.st.x + b.st.x) * 0.5;
    const int patch = std::min(int(u), 1);
    const glm::dvec3 onCurve = evaluatePatch(control, 0, patch, u - patch, 0.0).position;
    EXPECT_LE(glm::length(onCurve - (a.position + b.position) * 0.5), kPatchMaxError);
  }
  // A finer error bound gives more points, all still on the surface.
  const PatchGrid fine = tessellatePatch(control, 0.5);
  EXPECT_GT(fine.width, tessellated.width);
}

TEST(Curves, RefusesSizesTheEngineRefuses) {
  EXPECT_NE(patchGridProblem(PatchGrid{4, 3, std::vector<PatchPoint>(12)}), "");
  EXPECT_NE(patchGridProblem(PatchGrid{1, 3, std::vector<PatchPoint>(3)}), "");
  EXPECT_NE(patchGridProblem(PatchGrid{3, 3, std::vector<PatchPoint>(8)}), "");
  EXPECT_NE(patchGridProblem(PatchGrid{67, 3, std::vector<PatchPoint>(201)}), "");
  EXPECT_EQ(patchGridProblem(PatchGrid{5, 3, std::vector<PatchPoint>(15)}), "");
}

TEST(MeshTriangles, TwoFacesWithTheVerticesSt) {
  Scene scene;
  scene.entities.resize(2);
  scene.meshes.push_back(Mesh{7, 1, MeshKind::Curve, 0, 0, {}});
  Face model;
  model.texture = "curve";
  const MeshVertex a{{0, 0, 0}, 3, 5}, b{{64, 0, 16}, 35, 7}, c{{0, 64, 8}, -13, 69};
  ASSERT_TRUE(scene.addMeshTriangle(a, b, c, model));
  EXPECT_FALSE(scene.addMeshTriangle(a, b, a, model)); // no area
  ASSERT_EQ(scene.faces.size(), 2u);
  EXPECT_EQ(scene.meshes[0].faceCount, 2u);
  const Face& front = scene.faces[0];
  const Face& back = scene.faces[1];
  EXPECT_EQ(front.brush, kNoBrush);
  EXPECT_NEAR(glm::dot(front.plane.normal, glm::cross(b.position - a.position, c.position - a.position)),
              glm::length(glm::cross(b.position - a.position, c.position - a.position)), 1e-9);
  EXPECT_EQ(back.plane.normal, -front.plane.normal);
  for (const Face* f : {&front, &back})
    for (const MeshVertex* v : {&a, &b, &c}) {
      EXPECT_NEAR(f->frame.s(v->position), v->s, 1e-9);
      EXPECT_NEAR(f->frame.t(v->position), v->t, 1e-9);
      EXPECT_NEAR(f->plane.distanceTo(v->position), 0.0, 1e-9);
    }
  EXPECT_EQ(scene.faceEntity(0), 1u);
  EXPECT_EQ(scene.faceEntity(1), 1u);
  EXPECT_EQ(scene.faceEntity(2), 2u); // no such face
}

} // namespace
} // namespace bt

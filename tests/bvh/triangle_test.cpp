// Mesh triangles (Quake 3 curves) beside brushes: the two BVHs together against brute force over
// every brush and triangle, and the rules of a triangle hit (double-sided, the side's face).
#include "bvh/trace_scene.h"
#include "scene/curves.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/bvh/generated_scenes.h"

#include <gtest/gtest.h>

namespace bt {
namespace {

// A tessellated pipe of radius `r` along z at (x, y), as a mesh of the scene's first entity.
void addPipe(Scene& scene, double x, double y, double r, double height) {
  const double ring[9][2] = {{r, 0}, {r, r}, {0, r}, {-r, r}, {-r, 0}, {-r, -r}, {0, -r}, {r, -r}, {r, 0}};
  PatchGrid control{9, 3, {}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 9; ++j) control.points.push_back({{x + ring[j][0], y + ring[j][1], height * i / 2}, {j * 0.25, i * 0.5}});
  const PatchGrid grid = tessellatePatch(control);
  scene.meshes.push_back(Mesh{0, 0, MeshKind::Curve, uint32_t(scene.faces.size()), 0, {}});
  Face model;
  model.texture = "pipe";
  auto v = [&](int i, int j) { return MeshVertex{grid.at(i, j).position, grid.at(i, j).st.x * 64, grid.at(i, j).st.y * 64}; };
  for (int i = 0; i + 1 < grid.height; ++i)
    for (int j = 0; j + 1 < grid.width; ++j) {
      scene.addMeshTriangle(v(i, j), v(i + 1, j), v(i + 1, j + 1), model);
      scene.addMeshTriangle(v(i, j), v(i + 1, j + 1), v(i, j + 1), model);
    }
}

TEST(Triangles, ClosestHitEqualsBruteForceAmongBrushes) {
  test::GeneratedLevel level = test::generateLevel(300, 41);
  const Bounds b = level.scene.bounds;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 12; ++k)
    addPipe(level.scene, b.min.x + u(rng) * b.extent().x, b.min.y + u(rng) * b.extent().y, 16 + 64 * u(rng), 32 + 256 * u(rng));
  const TraceScene ts = TraceScene::build(level.scene);
  ASSERT_FALSE(ts.triangles().empty());
  const std::vector<Ray> rays = test::randomRays(ts.bounds(), 3000, 43);
  int hits = 0, triangleHits = 0, failures = 0;
  for (size_t i = 0; i < rays.size() && failures < 10; ++i) {
    const std::optional<Hit> bvh = ts.closestHit(rays[i]);
    const std::optional<Hit> brute = test::bruteForceClosestHit(ts, rays[i]);
    const bool same = bvh.has_value() == brute.has_value() && (!bvh || (bvh->t == brute->t && bvh->face == brute->face));
    if (!same) ++failures;
    EXPECT_TRUE(same) << "ray " << i << ": bvh " << (bvh ? bvh->face : kNoFace) << ", brute force " << (brute ? brute->face : kNoFace);
    EXPECT_EQ(ts.occluded(rays[i]), brute.has_value()) << "ray " << i;
    hits += brute.has_value();
    triangleHits += brute && brute->brush == kNoBrush;
  }
  EXPECT_GT(triangleHits, 50);
  EXPECT_GT(hits, triangleHits);
}

TEST(Triangles, DoubleSidedWithTheFaceOfTheSideMet) {
  Scene scene;
  scene.entities.resize(1);
  addPipe(scene, 0, 0, 64, 128);
  const TraceScene ts = TraceScene::build(scene);
  // From outside the pipe towards its axis: the outside, then (from inside) the far wall.
  const std::optional<Hit> outside = ts.closestHit(Ray{{-200, 1, 50}, 0.0f, {1, 0, 0}});
  ASSERT_TRUE(outside);
  EXPECT_NEAR(outside->t, 200 - 64, kPatchMaxError);
  EXPECT_FALSE(outside->inside);
  EXPECT_EQ(outside->brush, kNoBrush);
  const Face& front = scene.faces[outside->face];
  EXPECT_LT(glm::dot(glm::vec3(front.plane.normal), glm::vec3(1, 0, 0)), 0.0f) << "the face met faces the ray";
  const std::optional<Hit> far = ts.closestHit(Ray{{0, 1, 50}, 0.0f, {1, 0, 0}});
  ASSERT_TRUE(far);
  EXPECT_NEAR(far->t, 64, kPatchMaxError);
  EXPECT_LT(glm::dot(glm::vec3(scene.faces[far->face].plane.normal), glm::vec3(1, 0, 0)), 0.0f);
  // Along the axis the ray meets nothing.
  EXPECT_FALSE(ts.closestHit(Ray{{0, 0, -50}, 0.0f, {0, 0, 1}}));
}

} // namespace
} // namespace bt

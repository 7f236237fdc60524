#include "quake/view_angles.h"

#include <gtest/gtest.h>

namespace bt::quake {
namespace {

void expectNear(glm::vec3 a, glm::vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-6f);
  EXPECT_NEAR(a.y, b.y, 1e-6f);
  EXPECT_NEAR(a.z, b.z, 1e-6f);
}

TEST(ViewAngles, AngleVectorsTurnAsQuakesMathlib) {
  const ViewVectors level = angleVectors(0, 0, 0);
  expectNear(level.forward, {1, 0, 0});
  expectNear(level.right, {0, -1, 0});
  expectNear(level.up, {0, 0, 1});
  expectNear(angleVectors(0, 90, 0).forward, {0, 1, 0}); // yaw turns left
  const ViewVectors down = angleVectors(90, 0, 0);       // positive pitch looks down
  expectNear(down.forward, {0, 0, -1});
  expectNear(down.up, {1, 0, 0});
  expectNear(angleVectors(0, 0, 90).right, {0, 0, -1}); // roll to the right
}

} // namespace
} // namespace bt::quake

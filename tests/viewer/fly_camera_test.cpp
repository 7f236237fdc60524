#include "viewer/fly_camera.h"

#include <gtest/gtest.h>

namespace bt {
namespace {

constexpr double kTol = 1e-9;

TEST(FlyCamera, YawFollowsQuakeAxes) {
  FlyCamera cam({0, 0, 0}, 0, 90);
  EXPECT_NEAR(cam.forward().x, 0.0, kTol);
  EXPECT_NEAR(cam.forward().y, 1.0, kTol);
  // Looking along +Y, right is +X.
  EXPECT_NEAR(cam.rightVector().x, 1.0, kTol);
  EXPECT_NEAR(cam.rightVector().z, 0.0, kTol);
}

TEST(FlyCamera, PositivePitchLooksDown) {
  FlyCamera cam({0, 0, 0}, 30, 0);
  EXPECT_LT(cam.forward().z, 0.0);
}

TEST(FlyCamera, WMovesForwardAtSpeed) {
  FlyCamera cam({0, 0, 0}, 0, 0);
  FlyInput in;
  in.forward = true;
  EXPECT_TRUE(cam.update(in, 0.5));
  EXPECT_NEAR(cam.position.x, 160.0, kTol);
  in.fast = true;
  cam.update(in, 0.5);
  EXPECT_NEAR(cam.position.x, 160.0 + 640.0, kTol);
}

TEST(FlyCamera, QAndEMoveVerticallyWhateverThePitch) {
  FlyCamera cam({0, 0, 0}, 45, 0);
  FlyInput in;
  in.up = true;
  cam.update(in, 1.0);
  EXPECT_NEAR(cam.position.z, 320.0, kTol);
  EXPECT_NEAR(cam.position.x, 0.0, kTol);
}

TEST(FlyCamera, RightDragLooksAndClampsPitch) {
  FlyCamera cam({0, 0, 0}, 0, 0);
  FlyInput in;
  in.looking = true;
  in.mouseDx = 50; // 10 degrees to the right = yaw decreases
  in.mouseDy = 10000;
  EXPECT_TRUE(cam.update(in, 0.0));
  EXPECT_NEAR(cam.yaw, 350.0, kTol);
  EXPECT_NEAR(cam.pitch, 89.0, kTol);
  // Mouse movement without the right button does nothing.
  FlyInput idle;
  idle.mouseDx = 100;
  EXPECT_FALSE(cam.update(idle, 0.0));
}

TEST(FlyCamera, WheelMovesForwardButChangesSpeedWhileLooking) {
  FlyCamera cam({0, 0, 0}, 0, 0);
  FlyInput wheel;
  wheel.wheel = 2;
  EXPECT_TRUE(cam.update(wheel, 0.0));
  EXPECT_NEAR(cam.position.x, 64.0, kTol);

  FlyInput looking;
  looking.looking = true;
  looking.wheel = 1;
  EXPECT_FALSE(cam.update(looking, 0.0));
  EXPECT_NEAR(cam.speed, 400.0, kTol);
  EXPECT_NEAR(cam.position.x, 64.0, kTol);
}

} // namespace
} // namespace bt

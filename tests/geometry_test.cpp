#include "plumetrace/core/geometry.hpp"

#include <gtest/gtest.h>

namespace plumetrace {
namespace {

TEST(Geometry, WrapAngleMapsIntoHalfOpenRange) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), -kPi);  // [-pi, pi)
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), -kPi);
  EXPECT_NEAR(wrap_angle(3.0 * kPi / 2.0), -kPi / 2.0, 1e-15);
  EXPECT_NEAR(wrap_angle(-3.0 * kPi / 2.0), kPi / 2.0, 1e-15);
  EXPECT_NEAR(wrap_angle(10.0 * kPi + 0.25), 0.25, 1e-13);
  for (double a = -20.0; a < 20.0; a += 0.37) {
    const double w = wrap_angle(a);
    EXPECT_GE(w, -kPi);
    EXPECT_LT(w, kPi);
    // same direction
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-12);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-12);
  }
}

TEST(Geometry, RelativePoseIsThePoseSeenFromTheOrigin) {
  const Pose origin{15.5, 0.0, kPi};
  // one metre upwind of a robot facing upwind is one metre straight ahead in its frame
  const Pose p = relative_pose(origin, {14.5, 0.0, kPi});
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 0.0, 1e-12);
  EXPECT_NEAR(p.heading, 0.0, 1e-12);
  // world -y is the robot's left (+y) when it faces -x
  const Pose q = relative_pose(origin, {15.5, -0.5, kPi / 2.0});
  EXPECT_NEAR(q.x, 0.0, 1e-12);
  EXPECT_NEAR(q.y, 0.5, 1e-12);
  EXPECT_NEAR(q.heading, -kPi / 2.0, 1e-12);
}

}  // namespace
}  // namespace plumetrace

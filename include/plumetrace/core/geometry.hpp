#pragma once

#include <cmath>
#include <numbers>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

/// A 3-D vector (m or m/s, world frame unless named otherwise).
struct Vec3 {
  double x = 0.0;  ///< downwind
  double y = 0.0;  ///< lateral
  double z = 0.0;  ///< up
};

/// A 2-D vector (m or m/s).
struct Vec2 {
  double x = 0.0;  ///< first component
  double y = 0.0;  ///< second component
};

/// A planar pose: position (m) and heading (rad, counter-clockwise from +x).
struct Pose {
  double x = 0.0;        ///< position x (m)
  double y = 0.0;        ///< position y (m)
  double heading = 0.0;  ///< heading (rad)
};

/// pi.
inline constexpr double kPi = std::numbers::pi;

/// Converts degrees to radians.
constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }

/// Converts radians to degrees.
constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }

/// Wraps an angle (rad) into [-pi, pi).
inline double wrap_angle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

/// Rotates a planar vector by angle a (rad).
inline Vec2 rotate(const Vec2& v, double a) {
  const double c = math::cos(a), s = math::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}

/// Pose p expressed in the frame of `origin` (origin at (0, 0) with heading 0).
inline Pose relative_pose(const Pose& origin, const Pose& p) {
  const Vec2 d = rotate({p.x - origin.x, p.y - origin.y}, -origin.heading);
  return {d.x, d.y, wrap_angle(p.heading - origin.heading)};
}

/// Squared Euclidean distance between two points (m^2).
inline double distance_squared(const Vec3& a, const Vec3& b) {
  const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace plumetrace

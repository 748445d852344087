#pragma once

#include <vector>

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// Parameters of Hayes' spiral-surge for teams (Hayes, Martinoli & Goodman 2002, 2003;
/// docs/algorithms.md, "hayes"). Every default is chosen for this tunnel, none is the papers'.
struct HayesParams {
  /// Path length of an upwind surge after the last hit (m); a hit during the surge restarts it.
  double d_surge = 0.614;
  /// Gap between the turns of the spiral that looks for the plume again after a surge (m).
  double d_gap = 0.222;
  /// Gap between the turns of the spiral that looks for the plume from the release point (m).
  double d_gap_find = 0.4;
  /// Radius on the spiral r = b theta at which every spiral starts (m), as surge-spiral's.
  double start_radius = 0.049;
  /// Distance to a teammate's reported hit at which the robot counts as there (m).
  double d_arrive = 0.05;
  /// This robot's release pose in the team's shared frame (m, m, rad): hit positions travel in
  /// that frame. Robot 0's defaults make its odometry frame the team's.
  double origin_x = 0.0;
  double origin_y = 0.0;        ///< see origin_x (m)
  double origin_heading = 0.0;  ///< see origin_x (rad)
  /// Hits (own and teammates') within declare_radius of the robot and declare_window of now
  /// that make it declare the source at their mean; 0: never declare.
  int declare_hits = 0;
  /// Radius of the disc around the robot in which hits count toward a declaration (m).
  double declare_radius = 0.3;
  /// How long a hit counts toward a declaration (s).
  double declare_window = 20.0;

  /// The config keys (core/config.hpp), in the table "hayes".
  template <class V>
  void fields(V& v) {
    const double deg = kPi / 180.0;
    v("d_surge", d_surge, "path length of an upwind surge after the last odor hit (m)", kPositive);
    v("d_gap", d_gap, "gap between spiral turns when the plume is lost after a surge (m)",
      kPositive);
    v("d_gap_find", d_gap_find,
      "gap between spiral turns when looking for the plume from the release point (m)", kPositive);
    v("start_radius", start_radius, "radius on the spiral r = b theta where spiralling starts (m)",
      NumberSpec{.min = 0.0, .max = 5.0});
    v("d_arrive", d_arrive,
      "distance to a teammate's reported hit at which the robot is there and spirals (m)",
      NumberSpec{.min = 0.0, .max = 5.0, .min_open = true});
    v("origin_x", origin_x,
      "this robot's release x in the team's shared frame, the frame hit positions are sent in "
      "(m; set per robot with member.K.hayes.origin_x)",
      kAnyNumber);
    v("origin_y", origin_y, "this robot's release y in the team's shared frame (m)", kAnyNumber);
    v("origin_heading_deg", origin_heading,
      "this robot's release heading in the team's shared frame (deg)",
      NumberSpec{.min = -360.0 * deg, .max = 360.0 * deg, .scale = deg});
    v("declare_hits", declare_hits,
      "odor hits (own and teammates') near the robot within declare_window that make it declare "
      "the source at their mean (0: never declare)",
      IntegerSpec{0, 100000});
    v("declare_radius", declare_radius,
      "radius around the robot within which hits count toward a declaration (m)", kPositive);
    v("declare_window", declare_window, "how long a hit counts toward a declaration (s)",
      kPositive);
  }
};

/// Hayes' spiral-surge for teams: spiral from the release point until odor, surge upwind
/// d_surge past the last hit, spiral again when the surge ends; every hit is broadcast with its
/// position in the team's frame, and a robot without odor of its own heads to the newest
/// teammate hit; hits pooled near the robot declare the source.
class Hayes final : public Controller {
 public:
  /// States of the machine.
  enum class State { kFind, kSurge, kSpiral, kGoto };
  /// A message's data[2] saying "an odor hit of hayes at (data[0], data[1])".
  static constexpr double kHitTag = 1.0;
  /// The most pooled hits remembered; older ones are forgotten first.
  static constexpr std::size_t kHitMemory = 4096;

  /// An odor hit in the team's frame.
  struct Hit {
    double time = 0.0;  ///< when it was perceived (s since release)
    Vec2 at;            ///< where (m, team frame)
  };

  /// Creates the controller; `rng` picks each spiral's curl.
  Hayes(const HayesParams& params, Rng rng);
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override;
  int losses() const override { return losses_; }
  unsigned reads() const override { return kReadsMessages; }
  Snapshot snapshot() const override;

  /// The message a hit at `where` (m, odometry frame) broadcasts.
  std::array<double, kMessageSize> hit_message(const Vec2& where) const;
  /// A point of the odometry frame in the team's frame (m).
  Vec2 to_team(const Vec2& p) const;
  /// A point of the team's frame in the odometry frame (m).
  Vec2 from_team(const Vec2& p) const;
  /// The teammate's hit the robot heads to in kGoto (m, odometry frame).
  Vec2 target() const { return from_team(target_); }
  /// Direction the current spiral curls: +1 counter-clockwise, -1 clockwise.
  int curl() const { return spiral_.curl(); }
  /// Pooled hits remembered, oldest first.
  std::size_t hits() const { return count_; }

 private:
  void remember(const Hit& hit);
  const Hit& hit(std::size_t i) const { return memory_[(first_ + i) % kHitMemory]; }
  void begin_spiral(double d_gap, double odometer);
  bool heads_to(const Vec2& hit) const;
  bool declares(Vec2& where) const;

  HayesParams params_;
  Rng rng_;
  State state_ = State::kFind;
  bool started_ = false;
  double heading_ = 0.0;          // surge heading (rad, odometry frame)
  double last_hit_odometer_ = 0;  // odometer at the last own hit (m)
  bool has_hit_ = false;          // an own hit since release
  Vec2 last_hit_;                 // where the last own hit was (m, team frame)
  Vec2 target_;                   // goto: the teammate's hit (m, team frame)
  Pose pose_;                     // the pose at the last step (odometry frame)
  double odometer_ = 0.0;         // the odometer at the last step (m)
  double time_ = 0.0;             // the time of the last step (s)
  SpiralPath spiral_;
  int losses_ = 0;
  std::vector<Hit> memory_;  // ring of kHitMemory pooled hits
  std::size_t first_ = 0;
  std::size_t count_ = 0;
};

}  // namespace plumetrace

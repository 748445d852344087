#include "plumetrace/agent/controllers/hayes.hpp"

#include <cmath>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

Hayes::Hayes(const HayesParams& params, Rng rng)
    : params_(params), rng_(rng), memory_(kHitMemory) {}

Vec2 Hayes::to_team(const Vec2& p) const {
  const Vec2 r = rotate(p, params_.origin_heading);
  return {params_.origin_x + r.x, params_.origin_y + r.y};
}

Vec2 Hayes::from_team(const Vec2& p) const {
  return rotate({p.x - params_.origin_x, p.y - params_.origin_y}, -params_.origin_heading);
}

std::array<double, kMessageSize> Hayes::hit_message(const Vec2& where) const {
  const Vec2 t = to_team(where);
  return {t.x, t.y, kHitTag, 0.0};
}

void Hayes::remember(const Hit& hit) {
  if (count_ == kHitMemory) {
    first_ = (first_ + 1) % kHitMemory;
    --count_;
  }
  memory_[(first_ + count_) % kHitMemory] = hit;
  ++count_;
}

void Hayes::begin_spiral(double d_gap, double odometer) {
  // why: Hayes' spiral does not start upwind (Lochmatter & Martinoli 2008, section 2.2): it
  // starts on the heading the robot has, curling to a side drawn at random (docs/algorithms.md)
  spiral_.start(d_gap, params_.start_radius, rng_.sign());
  spiral_.anchor(odometer);
}

bool Hayes::heads_to(const Vec2& hit) const {
  // a robot that has met the plume itself follows a teammate's hit only when it is not
  // downwind of its own last hit: the upwind direction is that of its last surge
  if (!has_hit_) return true;
  const double up = heading_ + params_.origin_heading;
  return (hit.x - last_hit_.x) * math::cos(up) + (hit.y - last_hit_.y) * math::sin(up) >= 0.0;
}

bool Hayes::declares(Vec2& where) const {
  if (params_.declare_hits <= 0) return false;
  const Vec2 here = to_team({pose_.x, pose_.y});
  const double r2 = params_.declare_radius * params_.declare_radius;
  int n = 0;
  Vec2 sum;
  for (std::size_t i = 0; i < count_; ++i) {
    const Hit& h = hit(i);
    const double dx = h.at.x - here.x, dy = h.at.y - here.y;
    if (h.time < time_ - params_.declare_window || dx * dx + dy * dy > r2) continue;
    ++n;
    sum.x += h.at.x;
    sum.y += h.at.y;
  }
  if (n < params_.declare_hits) return false;
  where = from_team({sum.x / n, sum.y / n});
  return true;
}

Command Hayes::step(const Observation& obs, WindProbe& wind) {
  pose_ = obs.odometry;
  odometer_ = obs.odometer;
  time_ = obs.time;
  // forget the hits older than the window (arrival order is time order but for delays)
  while (count_ > 0 && hit(0).time < time_ - params_.declare_window) {
    first_ = (first_ + 1) % kHitMemory;
    --count_;
  }
  // pool the teammates' hits; the newest one this robot would follow
  bool pooled = false, follow = false;
  Vec2 newest;
  for (const Message& m : obs.messages) {
    if (m.data[2] != kHitTag) continue;
    const Vec2 at{m.data[0], m.data[1]};
    remember({m.sent, at});
    pooled = true;
    if (heads_to(at)) {
      newest = at;
      follow = true;
    }
  }
  const Vec2 here{obs.odometry.x, obs.odometry.y};
  if (obs.odor) {
    last_hit_odometer_ = obs.odometer;
    last_hit_ = to_team(here);
    has_hit_ = true;
    remember({obs.time, last_hit_});
    pooled = true;
  }
  if (!started_) {
    // release: look for the plume on a spiral from here
    started_ = true;
    begin_spiral(params_.d_gap_find, obs.odometer);
  }

  switch (state_) {
    case State::kFind:
    case State::kSpiral:
    case State::kGoto:
      if (obs.odor) {
        heading_ = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        state_ = State::kSurge;
      } else if (follow) {
        target_ = newest;
        state_ = State::kGoto;
      }
      break;
    case State::kSurge:
      if (obs.odometer - last_hit_odometer_ >= params_.d_surge) {
        ++losses_;
        begin_spiral(params_.d_gap, obs.odometer);
        state_ = State::kSpiral;
      }
      break;
  }
  if (state_ == State::kGoto) {
    const Vec2 t = from_team(target_);
    if (math::hypot(t.x - here.x, t.y - here.y) <= params_.d_arrive) {
      // there without odor: look for the plume around the teammate's hit
      begin_spiral(params_.d_gap, obs.odometer);
      state_ = State::kSpiral;
    }
  }

  Vec2 source;
  if (pooled && declares(source)) return Command::declare_source(source);
  Command command;
  switch (state_) {
    case State::kSurge:
      command = Command::go(heading_);
      break;
    case State::kGoto: {
      const Vec2 t = from_team(target_);
      command = Command::go(math::atan2(t.y - here.y, t.x - here.x));
      break;
    }
    case State::kFind:
    case State::kSpiral:
      command = Command::curve(spiral_.curvature(obs.odometer));
      break;
  }
  return obs.odor ? command.with_message(hit_message(here)) : command;
}

std::string_view Hayes::state() const {
  switch (state_) {
    case State::kFind:
      return "find";
    case State::kSurge:
      return "surge";
    case State::kSpiral:
      return "spiral";
    case State::kGoto:
      return "goto";
  }
  return "find";
}

Snapshot Hayes::snapshot() const {
  Snapshot s;
  s.points.reserve(count_);
  for (std::size_t i = 0; i < count_; ++i) s.points.push_back(from_team(hit(i).at));
  const Vec2 here{pose_.x, pose_.y};
  if (state_ == State::kGoto) {
    s.path = {here, from_team(target_)};
  } else if (state_ == State::kSurge) {
    const double left = std::max(0.0, params_.d_surge - (odometer_ - last_hit_odometer_));
    s.path = {here, {here.x + left * math::cos(heading_), here.y + left * math::sin(heading_)}};
  }
  return s;
}

}  // namespace plumetrace

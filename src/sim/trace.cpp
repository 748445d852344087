#include "plumetrace/sim/trace.hpp"

#include <algorithm>
#include <cmath>

#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

namespace {

// steps between snapshots: none for 0; why: an interval beyond any run (kMaxSteps) takes only
// the snapshot at release, and never reaches lround, whose result is unspecified there
long snapshot_steps(double interval, double dt) {
  if (!(interval > 0.0)) return 0L;
  const double steps = interval / dt;
  return steps > kMaxSteps ? static_cast<long>(kMaxSteps) + 1 : std::max(1L, std::lround(steps));
}

}  // namespace

WindGrid trace_wind_grid(const Scenario& scenario) {
  const auto& a = scenario.arena;
  WindGrid g;
  g.nx = std::max(1, static_cast<int>(std::floor((a.x_max - a.x_min) / g.dx)));
  g.ny = std::max(1, static_cast<int>(std::floor((a.y_max - a.y_min) / g.dy)));
  g.dx = (a.x_max - a.x_min) / g.nx;
  g.dy = (a.y_max - a.y_min) / g.ny;
  g.x0 = a.x_min + g.dx / 2.0;
  g.y0 = a.y_min + g.dy / 2.0;
  g.z = scenario.odor.height;
  return g;
}

const std::vector<TraceField>& trace_fields() {
  static const std::vector<TraceField> fields = [] {
    std::vector<TraceField> out;
    const TraceStep none;
    TraceStep::fields(none, [&](const TraceField& f, const auto&) { out.push_back(f); });
    return out;
  }();
  return fields;
}

std::size_t snapshot_values(const Snapshot& snapshot) {
  return 2 * snapshot.points.size() + snapshot.weights.size() + 2 * snapshot.path.size() +
         snapshot.grid.size();
}

Snapshot snapshot_in_world(const Snapshot& odometry, const Pose& start) {
  // why: the transform of Agent::propose's declaration, so an estimate and a declaration of the
  // same odometry point land on the same world point
  const auto world = [&](const Vec2& p) {
    const Vec2 d = rotate(p, start.heading);
    return Vec2{start.x + d.x, start.y + d.y};
  };
  Snapshot out = odometry;
  for (Vec2& p : out.points) p = world(p);
  for (Vec2& p : out.path) p = world(p);
  if (out.has_estimate) out.estimate = world(out.estimate);
  return out;
}

TraceRecorder::TraceRecorder(Trace& trace, double snapshot_interval, double dt)
    : trace_(trace), snapshot_every_(snapshot_steps(snapshot_interval, dt)) {}

namespace {

// the row of an agent's state after its last step
TraceStep step_row(const World& world, const Agent& agent) {
  const auto& sensor = agent.wind_sensor();
  TraceStep row;
  row.time = agent.time();
  row.pose = agent.robot().pose;
  row.odometer = agent.robot().odometer;
  const std::string_view state = agent.controller().state();
  // why: a trace keeps every step's state; one name must not make it gigabytes (G8)
  check_state_name(state);
  row.state = std::string(state);
  row.odor = agent.odor();
  row.concentration = world.environment().odor->concentration(agent.sensed_at());
  row.wind_samples = agent.time() > 0.0 ? sensor.samples() : 0;
  row.wind_body = sensor.last_sample();
  // why: at the sensor's height, where the wind sensor and the trace's wind grid sample it
  const Vec3 wind =
      world.environment().wind->velocity({row.pose.x, row.pose.y, agent.scenario().odor.height});
  row.true_wind = {wind.x, wind.y};
  return row;
}

// the agent's controller snapshot in the world frame; false when it shows nothing
bool controller_snapshot(const Agent& agent, ControllerSnapshot& out) {
  const Snapshot snap = agent.controller().snapshot();
  if (snap.empty()) return false;
  const auto refuse = [&](const std::string& why) {
    throw ConfigError("controller '" +
                      std::string(algorithm_name(agent.scenario().controller.algorithm)) +
                      "' (robot " + std::to_string(agent.index()) + "): its snapshot " + why);
  };
  // why: a trace records a snapshot at every filament snapshot; a grid of a million cells a
  // frame would make traces of gigabytes (kMaxSnapshotValues)
  if (const std::size_t n = snapshot_values(snap); n > kMaxSnapshotValues) {
    refuse("holds " + std::to_string(n) + " numbers, more than the " +
           std::to_string(kMaxSnapshotValues) + " a trace records (points count 2, grid cells 1)");
  }
  if (!snap.weights.empty() && snap.weights.size() != snap.points.size()) {
    refuse("has " + std::to_string(snap.weights.size()) + " weights for " +
           std::to_string(snap.points.size()) + " points");
  }
  if (snap.nx < 0 || snap.ny < 0 ||
      snap.grid.size() != static_cast<std::size_t>(snap.nx) * static_cast<std::size_t>(snap.ny)) {
    refuse("has a grid of " + std::to_string(snap.grid.size()) +
           " values for nx = " + std::to_string(snap.nx) + ", ny = " + std::to_string(snap.ny));
  }
  if (!snap.grid.empty() &&
      !(snap.dx > 0.0 && snap.dy > 0.0 && std::isfinite(snap.dx) && std::isfinite(snap.dy))) {
    refuse("has a grid whose cell size is not positive (dx = " + std::to_string(snap.dx) +
           ", dy = " + std::to_string(snap.dy) + ")");
  }
  out.time = agent.time();
  out.agent = agent.index();
  out.start = agent.start();
  out.snapshot = snapshot_in_world(snap, agent.start());
  return true;
}

}  // namespace

void TraceRecorder::operator()(const World& world) {
  // robot 0's team: the agents a trace records
  const std::size_t team = world.teams().size() > 1 ? world.teams()[1] : world.agent_count();
  if (trace_.agents.empty()) {
    for (std::size_t i = 0; i < team; ++i) {
      const Agent& agent = world.agent(i);
      AgentTrace& recorded = trace_.agents.emplace_back();
      recorded.index = agent.index();
      recorded.start = agent.start();
    }
  }
  const bool snapshot_now = snapshot_every_ > 0 && calls_ % snapshot_every_ == 0;
  // why: the time of the world's last step; robot 0's clock stops where its run ends
  double now = 0.0;
  for (std::size_t i = 0; i < team; ++i) now = std::max(now, world.agent(i).time());
  for (std::size_t i = 0; i < team; ++i) {
    const Agent& agent = world.agent(i);
    AgentTrace& recorded = trace_.agents[i];
    // a robot whose run has ended takes no more steps: its last row is the step that ended it
    const bool stepped = recorded.steps.empty() || agent.steps() > recorded.result.steps;
    if (stepped) recorded.steps.push_back(step_row(world, agent));
    recorded.result = agent.result();
    recorded.declared = agent.declared();
    // the controller's view at the snapshot interval, and once more at the step that ended it
    const bool ended_now = stepped && agent.done();
    ControllerSnapshot snap;
    if ((snapshot_every_ > 0 && stepped && (snapshot_now || ended_now)) &&
        controller_snapshot(agent, snap)) {
      trace_.controller_snapshots.push_back(std::move(snap));
    }
  }

  if (snapshot_now) {
    const OdorSnapshot odor = world.environment().odor->snapshot();
    // why: a trace holds filaments only; an odor model drawn otherwise leaves no snapshots
    if (odor.kind == OdorSnapshotKind::kFilaments) {
      const FilamentSpans& f = odor.filaments;
      FilamentSnapshot snap;
      snap.time = now;
      snap.x.assign(f.x.begin(), f.x.end());
      snap.y.assign(f.y.begin(), f.y.end());
      snap.z.assign(f.z.begin(), f.z.end());
      snap.w.assign(f.w.begin(), f.w.end());
      if (trace_.snapshots.empty()) trace_.wind_grid = trace_wind_grid(world.scenario());
      const WindGrid& g = trace_.wind_grid;
      const WindField& wind = *world.environment().wind;
      for (int j = 0; j < g.ny; ++j) {
        for (int i = 0; i < g.nx; ++i) {
          const Vec3 v = wind.velocity({g.x0 + i * g.dx, g.y0 + j * g.dy, g.z});
          snap.wind_x.push_back(v.x);
          snap.wind_y.push_back(v.y);
        }
      }
      trace_.snapshots.push_back(std::move(snap));
    }
  }
  ++calls_;
}

}  // namespace plumetrace

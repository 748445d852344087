#include "plumetrace/sim/trace.hpp"

#include <algorithm>
#include <cmath>

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

TraceRecorder::TraceRecorder(Trace& trace, double snapshot_interval, double dt)
    : trace_(trace), snapshot_every_(snapshot_steps(snapshot_interval, dt)) {}

void TraceRecorder::operator()(const World& world) {
  const auto& sensor = world.wind_sensor();
  TraceStep row;
  row.time = world.time();
  row.pose = world.robot().pose;
  row.odometer = world.robot().odometer;
  const std::string_view state = world.controller().state();
  // why: a trace keeps every step's state; one name must not make it gigabytes (G8)
  check_state_name(state);
  row.state = std::string(state);
  row.odor = world.odor();
  row.concentration = world.concentration();
  row.wind_samples = world.time() > 0.0 ? sensor.samples() : 0;
  row.wind_body = sensor.last_sample();
  // why: at the sensor's height, where the wind sensor and the trace's wind grid sample it
  const Vec3 wind =
      world.environment().wind->velocity({row.pose.x, row.pose.y, world.scenario().odor.height});
  row.true_wind = {wind.x, wind.y};
  trace_.steps.push_back(std::move(row));

  if (snapshot_every_ > 0 && calls_ % snapshot_every_ == 0) {
    const OdorSnapshot odor = world.environment().odor->snapshot();
    // why: a trace holds filaments only; an odor model drawn otherwise leaves no snapshots
    if (odor.kind == OdorSnapshotKind::kFilaments) {
      const FilamentSpans& f = odor.filaments;
      FilamentSnapshot snap;
      snap.time = world.time();
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

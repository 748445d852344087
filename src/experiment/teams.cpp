#include "plumetrace/experiment/teams.hpp"

#include <algorithm>
#include <map>
#include <tuple>

namespace plumetrace {

std::vector<TeamOutcome> team_outcomes(std::span<const RunRow> rows) {
  std::vector<TeamOutcome> teams;
  std::map<std::tuple<std::string, int, std::uint64_t>, std::size_t> index;
  for (const RunRow& r : rows) {
    const auto [it, added] = index.try_emplace({r.sweep, r.point, r.trial}, teams.size());
    if (added) teams.push_back({.sweep = r.sweep, .point = r.point, .trial = r.trial});
    TeamOutcome& t = teams[it->second];
    ++t.robots;
    t.d_t_sum += r.result.d_t;
    if (r.result.outcome != Outcome::kSuccess) continue;
    ++t.arrivals;
    // the earliest arrival; of arrivals at one time, the robot of the lowest index
    const bool earlier = t.first_agent < 0 || r.result.time < t.t_first_arrival ||
                         (r.result.time == t.t_first_arrival && r.agent < t.first_agent);
    if (earlier) {
      t.first_agent = r.agent;
      t.t_first_arrival = r.result.time;
    }
  }
  return teams;
}

TeamStats summarize_teams(std::span<const TeamOutcome> teams) {
  TeamStats out;
  out.teams = static_cast<std::int64_t>(teams.size());
  double first_arrivals = 0.0, arrivals = 0.0, d_t_sum = 0.0;
  for (const TeamOutcome& t : teams) {
    out.robots = std::max(out.robots, t.robots);
    arrivals += t.arrivals;
    d_t_sum += t.d_t_sum;
    if (t.arrivals == 0) continue;
    ++out.successes;
    first_arrivals += t.t_first_arrival;
  }
  out.success_ci = wilson_interval(out.successes, out.teams);
  if (out.teams == 0) return out;
  const auto n = static_cast<double>(out.teams);
  out.success_rate = static_cast<double>(out.successes) / n;
  out.mean_arrivals = arrivals / n;
  out.mean_d_t_sum = d_t_sum / n;
  if (out.successes > 0) {
    out.mean_first_arrival = first_arrivals / static_cast<double>(out.successes);
  }
  return out;
}

}  // namespace plumetrace

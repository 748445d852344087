#pragma once

#include <cmath>
#include <concepts>
#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// How one team did: the robots of one run (sweep, point, trial) together (docs/experiments.md,
/// "Teams"). For a robot alone it is that robot's run.
struct TeamOutcome {
  std::string sweep;             ///< sweep name
  int point = 0;                 ///< point index in the sweep
  std::uint64_t trial = 0;       ///< trial index
  int robots = 0;                ///< robots in the team (the run's rows)
  int arrivals = 0;              ///< robots that reached the source (outcome success)
  int first_agent = -1;          ///< the robot that arrived first (the lowest index of a tie); -1
                                 ///< when none arrived
  double t_first_arrival = NAN;  ///< time from release to the first arrival (s); NaN when none
  double d_t_sum = 0.0;          ///< the robots' path lengths d_t summed (m)

  /// The one list of a team's columns after its key (sweep, point, trial), in order: calls
  /// `v(ResultField, value)` for each; teams.csv writes them.
  template <class Team, class Visitor>
  requires std::same_as<std::remove_cvref_t<Team>, TeamOutcome>
  static void fields(Team&& t, Visitor&& v) {
    v({.name = "robots"}, t.robots);
    v({.name = "arrivals"}, t.arrivals);
    v({.name = "first_agent"}, t.first_agent);
    v({.name = "t_first_arrival", .unit = "s", .nullable = true}, t.t_first_arrival);
    v({.name = "d_t_sum", .unit = "m"}, t.d_t_sum);
  }
};

/// The team of every run in `rows`, in the order of each run's first row: the rows of one
/// (sweep, point, trial) are its robots, whatever their order.
std::vector<TeamOutcome> team_outcomes(std::span<const RunRow> rows);

/// Statistics of the teams of one sweep point (docs/experiments.md, "Teams").
struct TeamStats {
  std::int64_t teams = 0;           ///< runs (teams) at this point
  int robots = 0;                   ///< robots of its largest team
  std::int64_t successes = 0;       ///< teams in which a robot reached the source
  double success_rate = NAN;        ///< successes / teams
  Interval success_ci;              ///< Wilson 95% interval of the success rate
  double mean_first_arrival = NAN;  ///< mean time of the first arrival over successful teams (s)
  double mean_arrivals = NAN;       ///< mean number of robots that arrived, over all teams
  double mean_d_t_sum = NAN;        ///< mean of the robots' summed path lengths, all teams (m)
};

/// Statistics of a point's teams.
TeamStats summarize_teams(std::span<const TeamOutcome> teams);

}  // namespace plumetrace

#include "plumetrace/experiment/teams.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace plumetrace {
namespace {

RunRow robot(int point, std::uint64_t trial, int agent, Outcome outcome, double time, double d_t) {
  RunRow r;
  r.sweep = "s";
  r.point = point;
  r.trial = trial;
  r.agent = agent;
  r.result.outcome = outcome;
  r.result.time = time;
  r.result.d_t = d_t;
  r.result.trial = trial;
  r.result.agent = agent;
  return r;
}

// three teams of three at point 0 and a robot alone at point 1, their rows interleaved
std::vector<RunRow> hand_made() {
  return {
      robot(0, 0, 0, Outcome::kSuccess, 30.0, 4.0),
      robot(0, 1, 0, Outcome::kWall, 10.0, 1.0),
      robot(0, 0, 1, Outcome::kTimeout, 60.0, 7.0),
      robot(1, 0, 0, Outcome::kSuccess, 40.0, 5.0),
      robot(0, 0, 2, Outcome::kSuccess, 20.0, 3.0),
      robot(0, 1, 1, Outcome::kWall, 12.0, 2.0),
      robot(0, 1, 2, Outcome::kGaveUp, 8.0, 0.5),
      // a tie at 15 s, the higher index first: the first arrival is robot 0's
      robot(0, 2, 1, Outcome::kSuccess, 15.0, 2.0),
      robot(0, 2, 0, Outcome::kSuccess, 15.0, 2.5),
      robot(0, 2, 2, Outcome::kWrongDeclaration, 9.0, 1.0),
  };
}

TEST(Teams, EachRunIsOneTeamInTheOrderOfItsFirstRow) {
  const auto teams = team_outcomes(hand_made());
  ASSERT_EQ(teams.size(), 4u);
  EXPECT_EQ(teams[0].trial, 0u);
  EXPECT_EQ(teams[1].trial, 1u);
  EXPECT_EQ(teams[2].point, 1);
  EXPECT_EQ(teams[3].trial, 2u);
  for (const auto& t : teams) EXPECT_EQ(t.sweep, "s");
}

// expects a team's numbers; a NaN `first_arrival` expects none
void expect_team(const TeamOutcome& t, int robots, int arrivals, int first_agent,
                 double first_arrival, double d_t_sum) {
  EXPECT_EQ(t.robots, robots);
  EXPECT_EQ(t.arrivals, arrivals);
  EXPECT_EQ(t.first_agent, first_agent);
  if (std::isnan(first_arrival)) {
    EXPECT_TRUE(std::isnan(t.t_first_arrival));
  } else {
    EXPECT_EQ(t.t_first_arrival, first_arrival);
  }
  EXPECT_EQ(t.d_t_sum, d_t_sum);
}

TEST(Teams, TheFirstArrivalIsTheEarliestSuccessAndTheDistanceIsTheSum) {
  const auto teams = team_outcomes(hand_made());
  expect_team(teams[0], 3, 2, 2, 20.0, 14.0);  // robots 0 and 2 arrived, 2 first
  expect_team(teams[1], 3, 0, -1, NAN, 3.5);   // none arrived
  expect_team(teams[2], 1, 1, 0, 40.0, 5.0);   // a robot alone
}

TEST(Teams, ATieGoesToTheLowestIndexAndAWrongDeclarationIsNoArrival) {
  // robots 1 and 0 arrive at 15 s (1's row first); robot 2 declared wrongly
  expect_team(team_outcomes(hand_made())[3], 3, 2, 0, 15.0, 5.5);
}

TEST(Teams, APointsStatisticsAreOverItsTeams) {
  const auto all = team_outcomes(hand_made());
  const std::vector<TeamOutcome> point0{all[0], all[1], all[3]};
  const TeamStats st = summarize_teams(point0);
  EXPECT_EQ(st.teams, 3);
  EXPECT_EQ(st.robots, 3);
  EXPECT_EQ(st.successes, 2);
  EXPECT_EQ(st.success_rate, 2.0 / 3.0);
  const Interval wilson = wilson_interval(2, 3);
  EXPECT_EQ(st.success_ci.lo, wilson.lo);
  EXPECT_EQ(st.success_ci.hi, wilson.hi);
  EXPECT_EQ(st.mean_first_arrival, 17.5);  // (20 + 15) / 2, successful teams only
  EXPECT_EQ(st.mean_arrivals, 4.0 / 3.0);
  EXPECT_EQ(st.mean_d_t_sum, 23.0 / 3.0);  // (14 + 3.5 + 5.5) / 3
}

TEST(Teams, NoTeamGivesNoNumbersAndTheWholeInterval) {
  const TeamStats st = summarize_teams({});
  EXPECT_EQ(st.teams, 0);
  EXPECT_TRUE(std::isnan(st.success_rate));
  EXPECT_TRUE(std::isnan(st.mean_first_arrival));
  EXPECT_TRUE(std::isnan(st.mean_arrivals));
  EXPECT_EQ(st.success_ci.lo, 0.0);
  EXPECT_EQ(st.success_ci.hi, 1.0);
}

}  // namespace
}  // namespace plumetrace

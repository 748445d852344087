// The distributed runner's parts that need no MPI job: messages, a job of one, thread counts.
#include "plumetrace/distributed/distributed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <thread>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/rows.hpp"

namespace plumetrace {
namespace {

RunRow sample_row(int point, std::uint64_t trial, int agent = 0) {
  RunRow r;
  r.sweep = "grid-\xc3\xa9";  // any bytes
  r.point = point;
  r.trial = trial;
  r.agent = agent;
  r.result.agent = agent;
  r.config_hash = "0123456789abcdef";
  r.result.outcome = Outcome::kGaveUp;
  r.result.time = 0.1 + 0.2;  // not a short decimal
  r.result.d_t = std::nextafter(1.0, 2.0);
  r.result.d_u = -0.0;
  r.result.overhead = std::numeric_limits<double>::quiet_NaN();
  r.result.losses = 7;
  r.result.odor_fraction = std::numeric_limits<double>::denorm_min();
  r.result.steps = 4000000000LL;
  r.result.wind_samples = 3;
  r.result.seed = std::numeric_limits<std::uint64_t>::max();
  r.result.trial = trial;
  r.result.t_first_odor = 0.25;
  r.result.declaration_error = std::numeric_limits<double>::quiet_NaN();
  return r;
}

TEST(Wire, RowsTravelWithEveryBit) {
  const std::vector<RunRow> rows{sample_row(0, 0), sample_row(12, 1ULL << 40)};
  const auto back = decode_rows(encode_rows(rows));
  testing::expect_same_rows(back, rows);
  EXPECT_TRUE(std::signbit(back[0].result.d_u));
  EXPECT_TRUE(decode_rows(encode_rows({})).empty());
}

TEST(Wire, RowsOfATeamTravelWithTheirAgents) {
  std::vector<RunRow> rows;
  for (int agent = 0; agent < 3; ++agent) rows.push_back(sample_row(2, 5, agent));
  rows.push_back(sample_row(2, 6, kMaxTeam - 1));
  rows.back().result.outcome = Outcome::kWrongDeclaration;
  const auto back = decode_rows(encode_rows(rows));
  testing::expect_same_rows(back, rows);
  EXPECT_EQ(back[2].agent, 2);
  EXPECT_EQ(back[3].result.agent, kMaxTeam - 1);
}

TEST(Wire, AnAgentOutsideATeamIsRefusedLikeAnUnknownOutcome) {
  for (const int agent : {-1, kMaxTeam}) {
    RunRow row = sample_row(1, 2);
    row.agent = agent;
    EXPECT_THROW(decode_rows(encode_rows({row})), IoError) << agent;
    row = sample_row(1, 2);
    row.result.agent = agent;
    EXPECT_THROW(decode_rows(encode_rows({row})), IoError) << agent;
  }
}

TEST(Wire, GroupsTravelWhole) {
  const std::vector<TaskGroup> groups{{{0, 1, 2}, {0, 3, 2}}, {{1, 0, 1ULL << 50}}, {}};
  const auto back = decode_groups(encode_groups(groups));
  ASSERT_EQ(back.size(), groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g) {
    ASSERT_EQ(back[g].size(), groups[g].size());
    for (std::size_t k = 0; k < groups[g].size(); ++k) {
      EXPECT_EQ(back[g][k].sweep, groups[g][k].sweep);
      EXPECT_EQ(back[g][k].point, groups[g][k].point);
      EXPECT_EQ(back[g][k].trial, groups[g][k].trial);
    }
  }
}

TEST(Wire, MalformedMessagesAreRefused) {
  auto bytes = encode_rows({sample_row(1, 2)});
  auto cut = bytes;
  cut.pop_back();
  EXPECT_THROW(decode_rows(cut), IoError);
  bytes.push_back('x');
  EXPECT_THROW(decode_rows(bytes), IoError);
  EXPECT_THROW(decode_groups({'\x01'}), IoError);
}

TEST(Ranks, WithoutALauncherAProcessIsAJobOfOne) {
  ASSERT_FALSE(mpi_launched()) << "run the unit tests without mpirun";
  EXPECT_EQ(launched_ranks(), 1);
  Ranks ranks;
  EXPECT_EQ(ranks.rank(), 0);
  EXPECT_EQ(ranks.size(), 1);
  EXPECT_EQ(ranks.all_gather(5), std::vector<int>{5});
  EXPECT_EQ(ranks.broadcast("definition"), "definition");
  EXPECT_EQ(mpi_library().empty(), !mpi_enabled());
}

TEST(Ranks, ThreadsDefaultToTheCoresOfTheMachine) {
  Ranks ranks;
  EXPECT_EQ(threads_per_rank(ranks, 3), 3);
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  EXPECT_EQ(threads_per_rank(ranks, 0), std::max(1, cores));
}

}  // namespace
}  // namespace plumetrace

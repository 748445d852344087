// Files the library writes: whole or not at all (written as PATH.part, renamed over PATH).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

namespace fs = std::filesystem;

// the message of the IoError that `f` throws, or "" when it throws none
template <class F>
std::string io_error(F f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(OutputFiles, AWrittenFileReplacesTheOldOneAndLeavesNoPart) {
  const std::string path = testing::temp_path("text", ".txt");
  write_text_file(path, "old contents, longer than the new\n");
  write_text_file(path, "new\n");
  EXPECT_EQ(testing::read_file(path), "new\n");
  EXPECT_FALSE(fs::exists(path + ".part"));
}

TEST(OutputFiles, AFileThatCannotTakeItsPlaceLeavesTheTargetAndNoPart) {
  // a directory where the file should go: the part is written, the rename fails
  const std::string path = testing::temp_path("dir", ".csv");
  fs::create_directories(path + "/inside");
  const std::string message = io_error([&] { write_text_file(path, "rows\n"); });
  EXPECT_NE(message.find("cannot write '" + path + "'"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_directory(path + "/inside"));
  EXPECT_FALSE(fs::exists(path + ".part"));
}

TEST(OutputFiles, AMissingFolderIsNamedAndNothingIsCreated) {
  const std::string path = testing::temp_path("no_such_folder", "") + "/runs.csv";
  EXPECT_EQ(io_error([&] { write_text_file(path, "x"); }), "cannot write '" + path + "'");
  EXPECT_EQ(io_error([&] { check_writable(path); }), "cannot write '" + path + "'");
  EXPECT_FALSE(fs::exists(fs::path(path).parent_path()));
}

TEST(OutputFiles, CheckingAPathLeavesNothingBehind) {
  const std::string path = testing::temp_path("checked", ".json");
  check_writable(path);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".part"));
  // an existing file is left as it was
  write_text_file(path, "kept\n");
  check_writable(path);
  EXPECT_EQ(testing::read_file(path), "kept\n");
}

TEST(OutputFiles, ACsvTraceWritesItsThreeFilesWhole) {
  Trace trace;
  trace.agents.emplace_back().steps.resize(3);
  AgentTrace& mate = trace.agents.emplace_back();
  mate.index = 1;
  mate.steps.resize(2);
  mate.steps[1].state = "a, b";
  mate.steps[1].wind_samples = 2;
  mate.steps[1].wind_body = {0.5, -0.25, 0.0};
  mate.steps[1].true_wind = {1.0, NAN};
  trace.snapshots.push_back({0.0, {1.0, 2.0}, {0.0, 0.5}, {0.1, 0.1}, {0.01, 0.02}, {}, {}});
  ControllerSnapshot& c = trace.controller_snapshots.emplace_back();
  c.time = 0.5, c.agent = 1, c.start = {10.0, 0.5, kPi / 2};
  c.snapshot.points = {{1.0, 2.0}};
  c.snapshot.weights = {0.25};
  c.snapshot.nx = 2, c.snapshot.ny = 1, c.snapshot.grid = {3.0, 4.0};
  c.snapshot.x0 = 1.0, c.snapshot.y0 = 0.0, c.snapshot.dx = 1.0, c.snapshot.dy = 1.0;
  c.snapshot.has_estimate = true, c.snapshot.estimate = {7.0, 8.0};
  const std::string path = testing::temp_path("trace", ".csv");
  const std::string stem = path.substr(0, path.size() - 4);
  write_trace(path, trace, Scenario{}, RunResult{}, RunInfo{"casting", 1, 0});
  EXPECT_EQ(testing::read_file(stem + ".filaments.csv"),
            "time,x,y,z,w\n0,1,0,0.10000000000000001,0.01\n"
            "0,2,0.5,0.10000000000000001,0.02\n");
  // every robot's steps in one table, robot by robot, the columns of TraceStep::fields
  const std::string steps = testing::read_file(path);
  EXPECT_EQ(steps.substr(0, steps.find('\n')),
            "agent,time,x,y,heading,odometer,state,odor,concentration,wind_samples,wind_x_body,"
            "wind_y_body,wind_z_body,true_wind_x,true_wind_y");
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 6);  // header and five steps
  EXPECT_NE(steps.find("\n0,0,0,0,0,0,,0,0,0,,,,0,0\n"), std::string::npos) << steps;
  EXPECT_NE(steps.find("\n1,0,0,0,0,0,\"a, b\",0,0,2,0.5,-0.25,0,1,\n"), std::string::npos)
      << steps;
  // the controllers' snapshots: a row per number pair, the grid's cells at their world centres
  // (the odometry frame turned a quarter about (10, 0.5): (1, 0) is (10, 1.5))
  EXPECT_EQ(testing::read_file(stem + ".controller.csv"),
            "time,agent,layer,x,y,value\n"
            "0.5,1,point,1,2,0.25\n"
            "0.5,1,grid,10,1.5,3\n"
            "0.5,1,grid,10,2.5,4\n"
            "0.5,1,estimate,7,8,\n");
  for (const std::string& f : {path, stem + ".filaments.csv", stem + ".controller.csv"}) {
    EXPECT_FALSE(fs::exists(f + ".part")) << f;
  }
}

}  // namespace
}  // namespace plumetrace

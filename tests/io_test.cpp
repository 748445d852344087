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

TEST(OutputFiles, ACsvTraceWritesBothFilesWhole) {
  Trace trace;
  trace.agents.emplace_back().steps.resize(3);
  trace.snapshots.push_back({0.0, {1.0, 2.0}, {0.0, 0.5}, {0.1, 0.1}, {0.01, 0.02}});
  const std::string path = testing::temp_path("trace", ".csv");
  const std::string filaments = path.substr(0, path.size() - 4) + ".filaments.csv";
  write_trace(path, trace, Scenario{}, RunResult{}, RunInfo{"casting", 1, 0});
  EXPECT_EQ(testing::read_file(filaments),
            "time,x,y,z,w\n0,1,0,0.10000000000000001,0.01\n"
            "0,2,0.5,0.10000000000000001,0.02\n");
  const std::string steps = testing::read_file(path);
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 4);  // header and three steps
  EXPECT_FALSE(fs::exists(path + ".part"));
  EXPECT_FALSE(fs::exists(filaments + ".part"));
}

}  // namespace
}  // namespace plumetrace

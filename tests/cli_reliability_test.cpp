// The plumetrace command on bad input and in a hostile environment (issue 13): every case ends
// with the documented exit code (0 ok, 2 bad input, 3 I/O failure or out of memory), a message
// naming the key, file or option, and nothing half-written; never an abort, a hang or a crash.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

using nlohmann::json;
using Output = testing::CommandOutput;
using testing::read_file;

const std::string kCli = PLUMETRACE_CLI;

// runs the command with `args`, capturing stdout, stderr and the exit code
Output cli(const std::string& args) { return testing::run_command(kCli + " " + args); }

// runs the command under bash with `limits` (ulimit options) set first
Output cli_limited(const std::string& limits, const std::string& args) {
  return testing::run_command("bash -c 'ulimit " + limits + " && exec " + kCli + " " + args + "'");
}

// expects bad input: exit 2, nothing on stdout, and `names` in the message
void expect_refused(const Output& o, const std::string& names, const std::string& what) {
  EXPECT_EQ(o.code, 2) << what << "\n" << o.err;
  EXPECT_EQ(o.out, "") << what;
  EXPECT_NE(o.err.find(names), std::string::npos) << what << " said: " << o.err;
}

// F3: any exception reaches main's catch-all; out of memory is exit 3, not an abort (134)
TEST(CliReliability, OutOfMemoryIsReportedWithExitThreeNotAnAbort) {
  // a ring of 1e7 filaments reserves 400 MB: more than the 300 MB the process may map
  const Output o = cli_limited("-v 300000", "run --set plume.capacity=10000000 --json");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_EQ(o.out, "");
  EXPECT_NE(o.err.find("out of memory"), std::string::npos) << o.err;
}

}  // namespace
}  // namespace plumetrace

// The step allocates nothing: a counting global operator new over whole runs.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace plumetrace {
namespace {

TEST(World, StepAllocatesNothingWithTheRingBufferPlume) {
  // the paper's algorithms: a controller registered by a program may allocate
  for (const Algorithm algorithm : builtin_algorithms()) {
    Scenario scenario;
    scenario.controller.algorithm = algorithm;
    for (std::uint64_t trial = 0; trial < 3; ++trial) {
      World world(scenario, 11, trial);
      const long before = g_allocations.load();
      while (!world.done()) world.step();
      EXPECT_EQ(g_allocations.load(), before)
          << algorithm_name(algorithm) << " trial " << trial << " allocated in step()";
      EXPECT_GT(world.result().steps, 100);
    }
  }
}

}  // namespace
}  // namespace plumetrace

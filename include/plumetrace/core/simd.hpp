#pragma once

// Which version of the vectorised loops (the plume's step and query, the meandering wind's
// interpolation) runs. Every version gives the same bits; they differ only in speed
// (docs/performance.md). The choice is the process's: the environment variable PLUMETRACE_SIMD
// names it, select() changes it.

#include <atomic>
#include <string>
#include <string_view>
#include <vector>

namespace plumetrace::simd {

/// A version of the loops, narrowest first.
enum class Path {
  kScalar,    ///< one element at a time, never vectorised
  kBaseline,  ///< as the build compiles for the architecture: SSE2 on x86-64, NEON on aarch64
  kAvx2,      ///< x86-64-v3: AVX2 and FMA (FMA is never used: the bits stay the same)
  kAvx512,    ///< x86-64-v4: AVX-512 F, VL, BW, DQ, CD
};

/// The path's name, as PLUMETRACE_SIMD spells it: "scalar", "sse2" (or "neon", or "baseline"
/// on other architectures), "avx2", "avx512".
std::string_view name(Path path);

/// Every name PLUMETRACE_SIMD takes on this architecture, "auto" first.
std::vector<std::string_view> names();

/// Whether this build has `path` and this processor runs it.
bool available(Path path);

/// The paths this build has and this processor runs, narrowest first (scalar is always one).
std::vector<Path> available();

/// The widest available path: what "auto" means.
Path best();

/// The path `name` names ("auto": best()). Throws std::invalid_argument, naming PLUMETRACE_SIMD
/// and the names this machine runs, when the name is unknown or the build or the processor
/// lacks the path.
Path parse(std::string_view name);

/// Runs `path` from now on, in every thread. Throws std::invalid_argument where it is not
/// available (as parse()).
void select(Path path);

/// Runs the path `name` names from now on (parse(), then select()).
void select(std::string_view name);

namespace detail {
/// The path in use as an int, -1 until the first select() or active().
extern std::atomic<int> selected;
/// active() at its first call: reads PLUMETRACE_SIMD.
Path first_active();
}  // namespace detail

/// The path in use: the last selected, else PLUMETRACE_SIMD's (read at the first call; unset
/// or empty means "auto"). Throws std::invalid_argument while PLUMETRACE_SIMD names no available
/// path and none was selected.
// why: inline, one relaxed load: every odor query asks it
inline Path active() {
  const int path = detail::selected.load(std::memory_order_relaxed);
  return path >= 0 ? static_cast<Path>(path) : detail::first_active();
}

/// One line for people: the path in use and those available, e.g. "avx2 (available: scalar,
/// sse2, avx2)".
std::string describe();

}  // namespace plumetrace::simd

#include "plumetrace/core/simd.hpp"

#include <atomic>
#include <cstdlib>
#include <stdexcept>

#include "simd_targets.hpp"

namespace plumetrace::simd {

namespace {

constexpr Path kPaths[] = {Path::kScalar, Path::kBaseline, Path::kAvx2, Path::kAvx512};

// the paths this architecture has at all (whether built or not)
bool on_this_architecture(Path path) {
#if defined(__x86_64__)
  (void)path;
  return true;
#else
  return path == Path::kScalar || path == Path::kBaseline;
#endif
}

// why the build or the processor lacks `path`, or "" when it runs
std::string missing(Path path) {
  switch (path) {
    case Path::kScalar:
    case Path::kBaseline:
      return "";
    case Path::kAvx2:
#if defined(PLUMETRACE_SIMD_AVX2)
      return __builtin_cpu_supports("x86-64-v3") ? "" : "this processor lacks AVX2 (x86-64-v3)";
#else
      return "this build has no AVX2 path (built without PLUMETRACE_VECTOR_CLONES, or not by GCC)";
#endif
    case Path::kAvx512:
#if defined(PLUMETRACE_SIMD_AVX512)
      return __builtin_cpu_supports("x86-64-v4") ? "" : "this processor lacks AVX-512 (x86-64-v4)";
#else
      return "this build has no AVX-512 path (built with PLUMETRACE_AVX512=OFF or without "
             "PLUMETRACE_VECTOR_CLONES, or not by GCC)";
#endif
  }
  return "unknown path";
}

std::string joined(const std::vector<std::string_view>& words) {
  std::string s;
  for (const auto w : words) s += (s.empty() ? "" : ", ") + std::string(w);
  return s;
}

// "auto" and the names of the available paths
std::vector<std::string_view> runnable_names() {
  std::vector<std::string_view> out{"auto"};
  for (const Path p : available()) out.push_back(name(p));
  return out;
}

}  // namespace

std::atomic<int> detail::selected{-1};

std::string_view name(Path path) {
  switch (path) {
    case Path::kScalar:
      return "scalar";
    case Path::kBaseline:
#if defined(__x86_64__)
      return "sse2";
#elif defined(__aarch64__)
      return "neon";
#else
      return "baseline";
#endif
    case Path::kAvx2:
      return "avx2";
    case Path::kAvx512:
      return "avx512";
  }
  return "?";
}

std::vector<std::string_view> names() {
  std::vector<std::string_view> out{"auto"};
  for (const Path p : kPaths) {
    if (on_this_architecture(p)) out.push_back(name(p));
  }
  return out;
}

bool available(Path path) { return on_this_architecture(path) && missing(path).empty(); }

std::vector<Path> available() {
  std::vector<Path> out;
  for (const Path p : kPaths) {
    if (available(p)) out.push_back(p);
  }
  return out;
}

Path best() {
  // why: a constant found once (the processor does not change under a running program)
  static const Path widest = available().back();
  return widest;
}

Path parse(std::string_view text) {
  if (text == "auto") return best();
  for (const Path p : kPaths) {
    if (!on_this_architecture(p) || name(p) != text) continue;
    const std::string why = missing(p);
    if (!why.empty()) {
      throw std::invalid_argument("PLUMETRACE_SIMD: \"" + std::string(text) + "\": " + why +
                                  "; this machine runs " + joined(runnable_names()));
    }
    return p;
  }
  throw std::invalid_argument("PLUMETRACE_SIMD: unknown path \"" + std::string(text) +
                              "\" (one of " + joined(names()) + "; this machine runs " +
                              joined(runnable_names()) + ")");
}

void select(Path path) {
  if (!available(path)) parse(name(path));  // throws, saying why
  detail::selected.store(static_cast<int>(path), std::memory_order_relaxed);
}

void select(std::string_view text) { select(parse(text)); }

Path detail::first_active() {
  const char* env = std::getenv("PLUMETRACE_SIMD");
  const Path path = env == nullptr || *env == '\0' ? best() : parse(env);
  // why: threads racing here all read the same variable and store the same path, and a path
  // selected meanwhile is kept
  int unset = -1;
  selected.compare_exchange_strong(unset, static_cast<int>(path), std::memory_order_relaxed);
  return static_cast<Path>(selected.load(std::memory_order_relaxed));
}

std::string describe() {
  std::vector<std::string_view> runs;
  for (const Path p : available()) runs.push_back(name(p));
  return std::string(name(active())) + " (available: " + joined(runs) + ")";
}

}  // namespace plumetrace::simd

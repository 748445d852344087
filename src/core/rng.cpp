#include "plumetrace/core/rng.hpp"

#include <array>
#include <cmath>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

// why: a ziggurat needs only a table look-up and a multiply on 98% of draws, uses libm only on
// the rare wedge and tail branches (the plume's random walk has its own vectorised sampler).
constexpr int kLayers = 128;
constexpr double kR = 3.442619855899;       // start of the tail
constexpr double kV = 9.91256303526217e-3;  // area of each layer

struct ZigguratTable {
  std::array<double, kLayers + 1> x{};
  std::array<double, kLayers> ratio{};

  ZigguratTable() {
    const double f = math::exp(-0.5 * kR * kR);
    x[0] = kV / f;
    x[1] = kR;
    x[kLayers] = 0.0;
    for (int i = 2; i < kLayers; ++i) {
      x[i] = std::sqrt(-2.0 * math::log(kV / x[i - 1] + math::exp(-0.5 * x[i - 1] * x[i - 1])));
    }
    for (int i = 0; i < kLayers; ++i) ratio[i] = x[i + 1] / x[i];
  }
};

// why: inlined into normal(), so that a draw pays the guard's load and not a call (GCC stopped
// inlining it once the table's maths became calls into plumetrace::math)
[[gnu::always_inline]] inline const ZigguratTable& table() {
  static const ZigguratTable t;
  return t;
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t derive_seed(std::uint64_t master_seed, std::uint64_t trial, Stream stream) {
  // why: chain the three inputs through the mixer so nearby (seed, trial) pairs share nothing.
  std::uint64_t state = master_seed;
  std::uint64_t h = splitmix64(state);
  state = h ^ (trial * 0xd1b54a32d192ed03ULL);
  h = splitmix64(state);
  state = h ^ (static_cast<std::uint64_t>(stream) * 0xaef17502108ef2d9ULL);
  return splitmix64(state);
}

std::uint64_t derive_seed(std::uint64_t master_seed, std::uint64_t trial, Stream stream,
                          int agent) {
  std::uint64_t state = derive_seed(master_seed, trial, stream);
  if (agent == 0) return state;
  // why: one more round through the mixer, so agent k's stream shares nothing with agent 0's
  state ^= static_cast<std::uint64_t>(agent) * 0x9fb21c651e98df25ULL;
  return splitmix64(state);
}

Rng::Rng(std::uint64_t seed) {
  std::uint64_t state = seed;
  for (auto& word : s_) word = splitmix64(state);
}

double Rng::normal() {
  const auto& t = table();
  const std::uint64_t bits = next_u64();
  const int layer = static_cast<int>(bits & (kLayers - 1));
  const double u = static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;  // in [-1, 1)
  if (std::fabs(u) < t.ratio[layer]) return u * t.x[layer];
  return normal_slow(u, layer);
}

double Rng::normal_slow(double u, int layer) {
  const auto& t = table();
  for (;;) {
    if (layer == 0) {
      // tail beyond kR (Marsaglia 1964)
      double x, y;
      do {
        x = math::log(uniform_open0()) / kR;
        y = math::log(uniform_open0());
      } while (-2.0 * y < x * x);
      return u < 0.0 ? x - kR : kR - x;
    }
    // wedge between two layers
    const double x = u * t.x[layer];
    const double f0 = math::exp(-0.5 * (t.x[layer] * t.x[layer] - x * x));
    const double f1 = math::exp(-0.5 * (t.x[layer + 1] * t.x[layer + 1] - x * x));
    if (f1 + uniform() * (f0 - f1) < 1.0) return x;
    // rejected: draw again
    const std::uint64_t bits = next_u64();
    layer = static_cast<int>(bits & (kLayers - 1));
    u = static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;
    if (std::fabs(u) < t.ratio[layer]) return u * t.x[layer];
  }
}

}  // namespace plumetrace

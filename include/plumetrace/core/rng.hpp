#pragma once

#include <cstdint>

namespace plumetrace {

/// The named random streams of one run (docs/model.md section 10).
enum class Stream : std::uint64_t {
  kPlume = 1,          ///< filament release and random walk
  kWindSensor = 2,     ///< wind-sensor noise
  kController = 3,     ///< the controller's own choices (initial side, tie breaks)
  kWind = 4,           ///< the wind field's own randomness (a constant wind draws none)
  kVirtualSensor = 5,  ///< the plume statistics' virtual surges (their wind readings, side guesses)
  kOdorSensor = 6,     ///< the odor sensor model's noise
  kStart = 7,          ///< a robot's start drawn from a region, and its heading
};

/// One step of the SplitMix64 sequence: advances state and returns a well-mixed 64-bit value.
std::uint64_t splitmix64(std::uint64_t& state);

/// Derives the seed of one stream from (master seed, trial index, stream).
std::uint64_t derive_seed(std::uint64_t master_seed, std::uint64_t trial, Stream stream);

/// Derives the seed of one robot's stream: agent 0's is derive_seed(master, trial, stream), so a
/// robot alone draws what it always drew; every other agent's is mixed from it and its index.
std::uint64_t derive_seed(std::uint64_t master_seed, std::uint64_t trial, Stream stream,
                          int agent);

/// xoshiro256** generator with our own uniform and normal samplers, identical on every platform.
class Rng {
 public:
  /// Seeds the four state words from one 64-bit seed through SplitMix64.
  explicit Rng(std::uint64_t seed);

  /// Next raw 64-bit value.
  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform double in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

  /// Uniform double in (0, 1], safe for logarithms.
  double uniform_open0() { return (static_cast<double>(next_u64() >> 11) + 1.0) * 0x1.0p-53; }

  /// Standard normal sample (ziggurat method, 128 layers).
  double normal();

  /// Normal sample with the given mean and standard deviation.
  double normal(double mean, double stddev) { return mean + stddev * normal(); }

  /// Fair coin: +1 or -1.
  int sign() { return (next_u64() >> 63) ? 1 : -1; }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  double normal_slow(double u, int layer);

  std::uint64_t s_[4];
};

}  // namespace plumetrace

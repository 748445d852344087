#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/env/odor.hpp"
#include "plumetrace/env/plume_params.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// The filament plume (docs/model.md section 4): positions and widths as arrays, advanced one dt
/// at a time.
class FilamentPlume final : public OdorField {
 public:
  /// Filaments per block of the concentration query.
  static constexpr std::size_t kBlock = 64;

  /// Creates an empty plume; filaments at x > removal_x leave under Lifetime::kLeaveArena.
  FilamentPlume(const PlumeParams& params, const SourceParams& source, double removal_x,
                std::uint64_t seed);

  /// One step of dt (s): move existing filaments (the wind plus random walk, width growth), then
  /// release new ones.
  void step(const WindField& wind, double dt) override;

  /// Odor concentration at point u (paper eq. 4).
  double concentration(const Vec3& u) const override;
  /// Whether the concentration at u reaches `threshold`; the same answer as
  /// concentration(u) >= threshold, found sooner (the sum stops once it gets there).
  bool reaches(const Vec3& u, double threshold) const override;
  /// The filaments' arrays.
  OdorSnapshot snapshot() const override;

  /// Number of live filaments.
  std::size_t size() const { return x_.size(); }
  /// Filaments released since construction.
  std::uint64_t released() const { return released_; }
  /// Filament x positions (m).
  std::span<const double> x() const { return x_; }
  /// Filament y positions (m).
  std::span<const double> y() const { return y_; }
  /// Filament z positions (m).
  std::span<const double> z() const { return z_; }
  /// Filament widths (m).
  std::span<const double> w() const { return w_; }
  /// Parameters in use.
  const PlumeParams& params() const { return params_; }

 private:
  void move(const WindField& wind, double dt);
  void release(double dt);
  Vec3 release_position();
  void store(std::size_t i, const Vec3& p, double w);
  double sum_kernels(const Vec3& u, double stop_at) const;
  void update_bounds();

  PlumeParams params_;
  SourceParams source_;
  double removal_x_;
  Rng rng_;
  double release_debt_ = 0.0;
  std::uint64_t released_ = 0;
  std::size_t oldest_ = 0;  // ring buffer: index overwritten next once full
  std::vector<double> x_, y_, z_, w_;
  std::vector<double> h_;  // 1 / w, so that the query needs no division
  // x and y range of each block of kBlock filaments (x min, x max, y min, y max), so a query
  // skips the blocks wholly beyond the cut-off (filaments sit roughly in release order, so
  // along x)
  std::vector<double> bounds_;
  // the least and greatest 1 / w of each block, so that a threshold test can bound what the
  // blocks not yet summed can add (FilamentPlume::sum_kernels)
  std::vector<double> h_range_;
};

}  // namespace plumetrace

#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/registry.hpp"
#include "plumetrace/env/plume_params.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// How an odor model's state is drawn.
enum class OdorSnapshotKind {
  kFilaments,  ///< puffs: a centre and a width each (`OdorSnapshot::filaments`)
  kGrid,       ///< concentrations on a regular grid (`OdorSnapshot::grid`)
};

/// Filament centres and widths, one entry per filament in storage order.
struct FilamentSpans {
  std::span<const double> x;  ///< centres x (m)
  std::span<const double> y;  ///< centres y (m)
  std::span<const double> z;  ///< centres z (m)
  std::span<const double> w;  ///< widths (m)
  /// Number of filaments.
  std::size_t size() const { return x.size(); }
};

/// Concentrations on a regular grid: cell (i, j, k) has its centre at origin + (i, j, k) * cell
/// and its value at values[i + counts[0] * (j + counts[1] * k)].
struct GridSpans {
  Vec3 origin;                          ///< centre of cell (0, 0, 0) (m)
  Vec3 cell;                            ///< cell size along x, y, z (m)
  std::array<std::size_t, 3> counts{};  ///< cells along x, y, z
  std::span<const double> values;       ///< concentrations, x fastest
};

/// What an odor model looks like at one instant, for traces and viewers (robots sense through
/// concentration() and reaches()). The spans point into the model and are valid until its next
/// step.
struct OdorSnapshot {
  /// Which of the members below is filled.
  OdorSnapshotKind kind = OdorSnapshotKind::kFilaments;
  /// The filaments, when kind is kFilaments.
  FilamentSpans filaments;
  /// The grid, when kind is kGrid.
  GridSpans grid;
};

/// An odor model: advanced by the wind, queried for the concentration at points.
class OdorField {
 public:
  virtual ~OdorField() = default;
  /// Advances the model by dt (s) in `wind` (already advanced to the end of this step).
  virtual void step(const WindField& wind, double dt) = 0;
  /// Odor concentration at point p (m).
  virtual double concentration(const Vec3& p) const = 0;
  /// Whether the concentration at p reaches `threshold`: exactly concentration(p) >= threshold
  /// (a model may find the answer sooner).
  virtual bool reaches(const Vec3& p, double threshold) const {
    return concentration(p) >= threshold;
  }
  /// The model's state for drawing and traces.
  virtual OdorSnapshot snapshot() const = 0;
};

/// The odor models: made from the scenario's PlumeParams, its source, the x beyond which odor
/// leaves the arena (m) and the model's own seed (Stream::kPlume).
using OdorRegistry = Registry<OdorField, const SourceParams&, double, std::uint64_t>;

/// The registered odor models (src/env/models.cpp: one line each); the filament plume is
/// "filament".
OdorRegistry& odor_field_registry();

/// Builds the odor model `name` (throws std::invalid_argument for a name not registered).
std::unique_ptr<OdorField> make_odor_field(std::string_view name, const PlumeParams& params,
                                           const SourceParams& source, double removal_x,
                                           std::uint64_t seed);

}  // namespace plumetrace

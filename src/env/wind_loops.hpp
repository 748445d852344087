#pragma once

// The meandering wind's interpolation (private to the library; declared here so that tests can
// compare every vector path with the scalar formulas, bit for bit). MeanderWind::velocity is
// locate() and evaluate(); MeanderWind::advect is advect() on the active path (core/simd.hpp).

#include <cstddef>
#include <cstdint>

#include "plumetrace/core/simd.hpp"

namespace plumetrace::wind_loops {

/// The grid as the interpolation reads it: each cell's bilinear coefficients, 8 per cell (u: a,
/// b, c, d, then v), cell (i, j) at 8 (i + cells_x j). In a cell at fractions (tx, ty),
/// u = (a + b tx) + ty (c + d tx), with a = u00, b = u10 - u00, c = u01 - u00,
/// d = (u11 - u01) - (u10 - u00). why: 6 operations a component, and a constant field's b, c
/// and d are exactly 0, so it gives the constant exactly.
struct CellView {
  double x0, y0;          ///< node (0, 0) (m)
  double inv_dx, inv_dy;  ///< 1 / node spacing (1/m)
  double top_x, top_y;    ///< nx - 1, ny - 1
  int cells_x;            ///< cells along x: nx - 1
  int last_x, last_y;     ///< the last cell's lower node: nx - 2, ny - 2
  const double* coef;     ///< 8 per cell
};

/// The cell k holding (px, py) and the fractions (tx, ty) along it; beyond the grid, its edge
/// (a NaN coordinate counts as the lower edge).
[[gnu::always_inline]] inline void locate(const CellView& g, double px, double py, int& k,
                                          double& tx, double& ty) {
  double fx = (px - g.x0) * g.inv_dx;
  double fy = (py - g.y0) * g.inv_dy;
  fx = fx > 0.0 ? fx : 0.0;
  fy = fy > 0.0 ? fy : 0.0;
  fx = fx < g.top_x ? fx : g.top_x;
  fy = fy < g.top_y ? fy : g.top_y;
  int i = static_cast<int>(fx);
  int j = static_cast<int>(fy);
  i = i < g.last_x ? i : g.last_x;
  j = j < g.last_y ? j : g.last_y;
  tx = fx - static_cast<double>(i);
  ty = fy - static_cast<double>(j);
  k = i + g.cells_x * j;
}

/// Where cell k's coefficients start.
[[gnu::always_inline]] inline const double* cell_coef(const CellView& g, std::ptrdiff_t k) {
  return g.coef + 8 * k;
}

/// (u, v) at fractions (tx, ty) of a cell, from its coefficients c.
[[gnu::always_inline]] inline void evaluate(const double* c, double tx, double ty, double& u,
                                            double& v) {
  u = (c[0] + c[1] * tx) + ty * (c[2] + c[3] * tx);
  v = (c[4] + c[5] * tx) + ty * (c[6] + c[7] * tx);
}

/// Moves points first..n-1 by the grid's wind there times dt and by dz along z, each as
/// locate(), evaluate(), then x += u dt, y += v dt, z += dz, in the version of `path` (scalar
/// and the baseline: one point at a time; AVX2: four; AVX-512: eight), which must be available.
void advect(simd::Path path, const CellView& g, double* x, double* y, double* z, std::int64_t first,
            std::int64_t n, double dt, double dz);

}  // namespace plumetrace::wind_loops

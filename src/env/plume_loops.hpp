#pragma once

// The plume's vectorised inner loops (private to the library; declared here so that tests can
// compare every path with a scalar evaluation of the same formulas, bit for bit). Each runs the
// version of `path` (core/simd.hpp), which must be available; every version gives the same bits.

#include <cstdint>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/env/plume_params.hpp"

namespace plumetrace::loops {

/// One step of filaments 0..n-1: drift d (the wind's displacement, zero where the caller has
/// moved them already), random walk of standard deviation `stddev` and width growth (paper
/// eqs. 2 and 3; w += gamma / (2 w) computed as w += (gamma / 2) h or, with `area`, Farrell et
/// al.'s w = sqrt(w^2 + gamma); then h = 1 / w, kept for the concentration). Normals: the
/// Box-Muller pair of counter 2i gives (x, y) of filament i, that of counter 2j + 1 the z of
/// filaments j and j + n / 2 (and of counter n the z of the last filament when n is odd); each
/// counter c is hashed as mix64(key + c * kGamma).
void drift_walk_grow(simd::Path path, double* __restrict x, double* __restrict y,
                     double* __restrict z, double* __restrict w, double* __restrict h,
                     std::int64_t n, const Vec3& d, std::uint64_t key, double stddev, double gamma,
                     bool area);

/// The concentration of each of m filaments at u (0 at or beyond the cut-off), given their
/// inverse widths h and the kernel's amount factor `scale`; cut2 is the squared cut-off.
void kernels(simd::Path path, const Vec3& u, const double* __restrict x, const double* __restrict y,
             const double* __restrict z, const double* __restrict h, std::int64_t m, double scale,
             Kernel kernel, double cut2, double* __restrict out);

/// kernels() without its path argument.
using KernelsLoop = void (*)(const Vec3& u, const double* __restrict x, const double* __restrict y,
                             const double* __restrict z, const double* __restrict h, std::int64_t m,
                             double scale, Kernel kernel, double cut2, double* __restrict out);

/// The version of kernels() for `path`, for a caller that calls it many times (a query: once
/// per block) as the loader's choice was called, with no path argument to pass or test.
KernelsLoop kernels_for(simd::Path path);

/// What each of `count` blocks can add at most at a query (`most`), given its squared
/// horizontal distance e2 from the query, its filaments' least and greatest 1 / w and their
/// number m (FilamentPlume::sum_kernels).
void block_most(simd::Path path, const double* __restrict e2, const double* __restrict h_lo,
                const double* __restrict h_hi, const double* __restrict m, std::int64_t count,
                double scale, Kernel kernel, double* __restrict most);

/// block_most() without its path argument.
using BlockMostLoop = void (*)(const double* __restrict e2, const double* __restrict h_lo,
                               const double* __restrict h_hi, const double* __restrict m,
                               std::int64_t count, double scale, Kernel kernel,
                               double* __restrict most);

/// The version of block_most() for `path`.
BlockMostLoop block_most_for(simd::Path path);

}  // namespace plumetrace::loops

#include "wind_loops.hpp"

#include "../core/simd_targets.hpp"

#if defined(PLUMETRACE_SIMD_AVX2)
#include <immintrin.h>
#endif

namespace plumetrace::wind_loops {

namespace {

[[gnu::always_inline]] inline void advect_points(const CellView& g, double* x, double* y, double* z,
                                                 std::int64_t first, std::int64_t n, double dt,
                                                 double dz) {
  for (std::int64_t s = first; s < n; ++s) {
    int k;
    double tx, ty, u, v;
    locate(g, x[s], y[s], k, tx, ty);
    evaluate(cell_coef(g, k), tx, ty, u, v);
    x[s] += u * dt;
    y[s] += v * dt;
    z[s] += dz;
  }
}

PLUMETRACE_SCALAR_TARGET void advect_scalar(const CellView& g, double* x, double* y, double* z,
                                            std::int64_t first, std::int64_t n, double dt,
                                            double dz) {
  advect_points(g, x, y, z, first, n, dt, dz);
}

void advect_baseline(const CellView& g, double* x, double* y, double* z, std::int64_t first,
                     std::int64_t n, double dt, double dz) {
  advect_points(g, x, y, z, first, n, dt, dz);
}

#if defined(PLUMETRACE_SIMD_AVX2)

// The vector paths take several points at a time. Each lane takes the coefficients of the
// lowest or of the highest cell of its block, chosen by a mask, without a branch: filaments sit
// in release order, so a block lies in one cell or across one cell edge; a block in three cells
// or more (about 1 in 100 on the default grid) is taken point by point. why: every lane
// computes locate() and evaluate() as written: max_pd(f, 0) and min_pd(f, top) are exactly the
// ternaries f > 0 ? f : 0 and f < top ? f : top (they return their second operand for NaN and
// for equal zeros), truncation is truncation, and the sums and products come in the same
// order, with no fused multiply-add; so each lane gives velocity()'s bits.

PLUMETRACE_AVX2_TARGET void advect_avx2(const CellView& g, double* x, double* y, double* z,
                                        std::int64_t first, std::int64_t n, double dt, double dz) {
  const __m256d x0 = _mm256_set1_pd(g.x0), y0 = _mm256_set1_pd(g.y0);
  const __m256d inv_dx = _mm256_set1_pd(g.inv_dx), inv_dy = _mm256_set1_pd(g.inv_dy);
  const __m256d top_x = _mm256_set1_pd(g.top_x), top_y = _mm256_set1_pd(g.top_y);
  const __m256d zero = _mm256_setzero_pd(), step = _mm256_set1_pd(dt), rise = _mm256_set1_pd(dz);
  const __m128i last_x = _mm_set1_epi32(g.last_x), last_y = _mm_set1_epi32(g.last_y);
  const __m128i cells_x = _mm_set1_epi32(g.cells_x);
  std::int64_t s = first;
  for (; s + 4 <= n; s += 4) {
    // locate
    const __m256d px = _mm256_loadu_pd(x + s), py = _mm256_loadu_pd(y + s);
    __m256d fx = _mm256_mul_pd(_mm256_sub_pd(px, x0), inv_dx);
    __m256d fy = _mm256_mul_pd(_mm256_sub_pd(py, y0), inv_dy);
    fx = _mm256_min_pd(_mm256_max_pd(fx, zero), top_x);
    fy = _mm256_min_pd(_mm256_max_pd(fy, zero), top_y);
    const __m128i i = _mm_min_epi32(_mm256_cvttpd_epi32(fx), last_x);
    const __m128i j = _mm_min_epi32(_mm256_cvttpd_epi32(fy), last_y);
    const __m256d tx = _mm256_sub_pd(fx, _mm256_cvtepi32_pd(i));
    const __m256d ty = _mm256_sub_pd(fy, _mm256_cvtepi32_pd(j));
    const __m128i k = _mm_add_epi32(i, _mm_mullo_epi32(cells_x, j));
    // the lowest and the highest cell of the four
    __m128i lo = _mm_min_epi32(k, _mm_shuffle_epi32(k, _MM_SHUFFLE(1, 0, 3, 2)));
    __m128i hi = _mm_max_epi32(k, _mm_shuffle_epi32(k, _MM_SHUFFLE(1, 0, 3, 2)));
    lo = _mm_min_epi32(lo, _mm_shuffle_epi32(lo, _MM_SHUFFLE(2, 3, 0, 1)));
    hi = _mm_max_epi32(hi, _mm_shuffle_epi32(hi, _MM_SHUFFLE(2, 3, 0, 1)));
    const __m128i in_hi = _mm_cmpeq_epi32(k, hi);
    if (_mm_movemask_epi8(_mm_or_si128(_mm_cmpeq_epi32(k, lo), in_hi)) != 0xffff) {
      advect_points(g, x, y, z, s, s + 4, dt, dz);
      continue;
    }
    // evaluate, each lane with its cell's coefficients
    const __m256d second = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(in_hi));
    const double* ca = cell_coef(g, _mm_cvtsi128_si32(lo));
    const double* cb = cell_coef(g, _mm_cvtsi128_si32(hi));
    __m256d c[8];  // why: a loop here, not a lambda, which would not share this target
    for (int m = 0; m < 8; ++m) {
      c[m] = _mm256_blendv_pd(_mm256_broadcast_sd(ca + m), _mm256_broadcast_sd(cb + m), second);
    }
    const __m256d u =
        _mm256_add_pd(_mm256_add_pd(c[0], _mm256_mul_pd(c[1], tx)),
                      _mm256_mul_pd(ty, _mm256_add_pd(c[2], _mm256_mul_pd(c[3], tx))));
    const __m256d v =
        _mm256_add_pd(_mm256_add_pd(c[4], _mm256_mul_pd(c[5], tx)),
                      _mm256_mul_pd(ty, _mm256_add_pd(c[6], _mm256_mul_pd(c[7], tx))));
    _mm256_storeu_pd(x + s, _mm256_add_pd(px, _mm256_mul_pd(u, step)));
    _mm256_storeu_pd(y + s, _mm256_add_pd(py, _mm256_mul_pd(v, step)));
    _mm256_storeu_pd(z + s, _mm256_add_pd(_mm256_loadu_pd(z + s), rise));
  }
  advect_points(g, x, y, z, s, n, dt, dz);
}

// why: GCC 12's AVX-512 headers trip its own uninitialised-value warning
#if defined(PLUMETRACE_SIMD_AVX512)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

PLUMETRACE_AVX512_TARGET void advect_avx512(const CellView& g, double* x, double* y, double* z,
                                            std::int64_t first, std::int64_t n, double dt,
                                            double dz) {
  const __m512d x0 = _mm512_set1_pd(g.x0), y0 = _mm512_set1_pd(g.y0);
  const __m512d inv_dx = _mm512_set1_pd(g.inv_dx), inv_dy = _mm512_set1_pd(g.inv_dy);
  const __m512d top_x = _mm512_set1_pd(g.top_x), top_y = _mm512_set1_pd(g.top_y);
  const __m512d zero = _mm512_setzero_pd(), step = _mm512_set1_pd(dt), rise = _mm512_set1_pd(dz);
  const __m256i last_x = _mm256_set1_epi32(g.last_x), last_y = _mm256_set1_epi32(g.last_y);
  const __m256i cells_x = _mm256_set1_epi32(g.cells_x);
  std::int64_t s = first;
  for (; s + 8 <= n; s += 8) {
    // locate
    const __m512d px = _mm512_loadu_pd(x + s), py = _mm512_loadu_pd(y + s);
    __m512d fx = _mm512_mul_pd(_mm512_sub_pd(px, x0), inv_dx);
    __m512d fy = _mm512_mul_pd(_mm512_sub_pd(py, y0), inv_dy);
    fx = _mm512_min_pd(_mm512_max_pd(fx, zero), top_x);
    fy = _mm512_min_pd(_mm512_max_pd(fy, zero), top_y);
    const __m256i i = _mm256_min_epi32(_mm512_cvttpd_epi32(fx), last_x);
    const __m256i j = _mm256_min_epi32(_mm512_cvttpd_epi32(fy), last_y);
    const __m512d tx = _mm512_sub_pd(fx, _mm512_cvtepi32_pd(i));
    const __m512d ty = _mm512_sub_pd(fy, _mm512_cvtepi32_pd(j));
    const __m256i k = _mm256_add_epi32(i, _mm256_mullo_epi32(cells_x, j));
    // the lowest and the highest cell of the eight
    __m256i lo = _mm256_min_epi32(k, _mm256_permute2x128_si256(k, k, 1));
    __m256i hi = _mm256_max_epi32(k, _mm256_permute2x128_si256(k, k, 1));
    lo = _mm256_min_epi32(lo, _mm256_shuffle_epi32(lo, _MM_SHUFFLE(1, 0, 3, 2)));
    hi = _mm256_max_epi32(hi, _mm256_shuffle_epi32(hi, _MM_SHUFFLE(1, 0, 3, 2)));
    lo = _mm256_min_epi32(lo, _mm256_shuffle_epi32(lo, _MM_SHUFFLE(2, 3, 0, 1)));
    hi = _mm256_max_epi32(hi, _mm256_shuffle_epi32(hi, _MM_SHUFFLE(2, 3, 0, 1)));
    const __mmask8 in_hi = _mm256_cmpeq_epi32_mask(k, hi);
    if (static_cast<__mmask8>(_mm256_cmpeq_epi32_mask(k, lo) | in_hi) != 0xff) {
      advect_points(g, x, y, z, s, s + 8, dt, dz);
      continue;
    }
    // evaluate, each lane with its cell's coefficients
    const double* ca = cell_coef(g, _mm256_cvtsi256_si32(lo));
    const double* cb = cell_coef(g, _mm256_cvtsi256_si32(hi));
    __m512d c[8];
    for (int m = 0; m < 8; ++m) {
      c[m] = _mm512_mask_mov_pd(_mm512_set1_pd(ca[m]), in_hi, _mm512_set1_pd(cb[m]));
    }
    const __m512d u =
        _mm512_add_pd(_mm512_add_pd(c[0], _mm512_mul_pd(c[1], tx)),
                      _mm512_mul_pd(ty, _mm512_add_pd(c[2], _mm512_mul_pd(c[3], tx))));
    const __m512d v =
        _mm512_add_pd(_mm512_add_pd(c[4], _mm512_mul_pd(c[5], tx)),
                      _mm512_mul_pd(ty, _mm512_add_pd(c[6], _mm512_mul_pd(c[7], tx))));
    _mm512_storeu_pd(x + s, _mm512_add_pd(px, _mm512_mul_pd(u, step)));
    _mm512_storeu_pd(y + s, _mm512_add_pd(py, _mm512_mul_pd(v, step)));
    _mm512_storeu_pd(z + s, _mm512_add_pd(_mm512_loadu_pd(z + s), rise));
  }
  advect_points(g, x, y, z, s, n, dt, dz);
}

#pragma GCC diagnostic pop
#endif

#endif

}  // namespace

void advect(simd::Path path, const CellView& g, double* x, double* y, double* z, std::int64_t first,
            std::int64_t n, double dt, double dz) {
  switch (path) {
    case simd::Path::kScalar:
      return advect_scalar(g, x, y, z, first, n, dt, dz);
#if defined(PLUMETRACE_SIMD_AVX2)
    case simd::Path::kAvx2:
      return advect_avx2(g, x, y, z, first, n, dt, dz);
#endif
#if defined(PLUMETRACE_SIMD_AVX512)
    case simd::Path::kAvx512:
      return advect_avx512(g, x, y, z, first, n, dt, dz);
#endif
    default:
      return advect_baseline(g, x, y, z, first, n, dt, dz);
  }
}

}  // namespace plumetrace::wind_loops

#pragma once
// The half-list pair pass of dem_engine.cpp (no tangential contact, no
// rotation) eight pairs a vector on AVX-512, for a normal law linear in the
// overlap and its rate with the same coefficients for every pair
// (f_n = Kn delta_n + Cn delta_n_dot, Eq. 6 with Cn given): the plume's,
// scenes P and B; and the near-pair filter that feeds it (near_filter). Two steps a block of pairs:
//  1. test: gather both centres and diameters, keep the touching pairs
//     (dist^2 < (r_i + r_j)^2) compressed into lanes with dx and dist^2, in
//     pair order;
//  2. law: gather the velocities of the kept pairs, form the force on i.
// The caller adds the forces in lane order, i.e. pair order, so each grain
// sums its contacts in the order of the scalar pass and the bits do not
// depend on the thread count. The arithmetic differs from the scalar law's
// (Eigen's expressions, contracted by the compiler) in where the fused
// multiply-adds fall, so results differ from the scalar pass in the last
// bits; every lane is computed alike, full vector or tail.
#include "dem/avx512_lanes.hpp"
#ifdef FDEM_DEM_AVX512
#include <cstddef>

#include "core/types.hpp"
#include "dem/touching_lanes.hpp"

namespace fdem::touching_pairs_avx512 {

using avx512_lanes::first_lanes;
using avx512_lanes::gathered_difference;

template <int Block>
using Lanes = TouchingLanes<Block, 8>;

/// Step 1 over pairs [begin, end) (at most Block): returns how many touch.
template <int Block>
int test(const Index* pi, const Index* pj, Index begin, Index end, const double* x, const double* y, const double* z,
         const double* d, Lanes<Block>& out) {
  int found = 0;
  const __m512d half = _mm512_set1_pd(0.5);
  for (Index k = begin; k < end; k += 8) {
    const __mmask8 lanes = first_lanes(end - k);
    const __m256i i = _mm256_maskz_loadu_epi32(lanes, pi + k);
    const __m256i j = _mm256_maskz_loadu_epi32(lanes, pj + k);
    const __m512d zero = _mm512_setzero_pd();
    const __m512d dx = gathered_difference(lanes, j, i, x);
    const __m512d dy = gathered_difference(lanes, j, i, y);
    const __m512d dz = gathered_difference(lanes, j, i, z);
    const __m512d ri = _mm512_mul_pd(half, _mm512_mask_i32gather_pd(zero, lanes, i, d, 8));
    const __m512d rj = _mm512_mul_pd(half, _mm512_mask_i32gather_pd(zero, lanes, j, d, 8));
    const __m512d dist2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
    const __m512d sum_r = _mm512_add_pd(ri, rj);
    const __mmask8 hit = _mm512_mask_cmp_pd_mask(lanes, dist2, _mm512_mul_pd(sum_r, sum_r), _CMP_LT_OQ);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.i + found), _mm256_maskz_compress_epi32(hit, i));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.j + found), _mm256_maskz_compress_epi32(hit, j));
    _mm512_storeu_pd(out.dx + found, _mm512_maskz_compress_pd(hit, dx));
    _mm512_storeu_pd(out.dy + found, _mm512_maskz_compress_pd(hit, dy));
    _mm512_storeu_pd(out.dz + found, _mm512_maskz_compress_pd(hit, dz));
    _mm512_storeu_pd(out.dist2 + found, _mm512_maskz_compress_pd(hit, dist2));
    _mm512_storeu_pd(out.ri + found, _mm512_maskz_compress_pd(hit, ri));
    _mm512_storeu_pd(out.rj + found, _mm512_maskz_compress_pd(hit, rj));
    found += __builtin_popcount(hit);
  }
  return found;
}

/// The near set's filter (dem_engine.cpp, filter_near_pairs) over the half
/// pairs [0, count): keeps those with |x_j - x_i|^2 < (r_i + r_j + margin)^2,
/// compressed in pair order into near_i, near_j (room for count + 8: whole
/// vectors are stored); returns how many. Any rounding of the test is
/// inside the margin's allowance, so a pair that can touch is kept.
inline std::size_t near_filter(const Index* pi, const Index* pj, std::size_t count, const double* x, const double* y,
                               const double* z, const double* d, double margin, Index* near_i, Index* near_j) {
  std::size_t kept = 0;
  const __m512d half = _mm512_set1_pd(0.5), extra = _mm512_set1_pd(margin);
  for (std::size_t k = 0; k < count; k += 8) {
    const __mmask8 lanes = first_lanes(static_cast<std::ptrdiff_t>(count - k));
    const __m256i i = _mm256_maskz_loadu_epi32(lanes, pi + k);
    const __m256i j = _mm256_maskz_loadu_epi32(lanes, pj + k);
    const __m512d dx = gathered_difference(lanes, j, i, x);
    const __m512d dy = gathered_difference(lanes, j, i, y);
    const __m512d dz = gathered_difference(lanes, j, i, z);
    const __m512d zero = _mm512_setzero_pd();
    const __m512d sum_d = _mm512_add_pd(_mm512_mask_i32gather_pd(zero, lanes, i, d, 8),
                                        _mm512_mask_i32gather_pd(zero, lanes, j, d, 8));
    const __m512d reach = _mm512_fmadd_pd(half, sum_d, extra);
    const __m512d dist2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
    const __mmask8 near = _mm512_mask_cmp_pd_mask(lanes, dist2, _mm512_mul_pd(reach, reach), _CMP_LT_OQ);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(near_i + kept), _mm256_maskz_compress_epi32(near, i));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(near_j + kept), _mm256_maskz_compress_epi32(near, j));
    kept += static_cast<std::size_t>(__builtin_popcount(near));
  }
  return kept;
}

/// Step 2 for the `found` touching pairs: the force on i into out.f*, and
/// whether an overlap exceeded the smaller radius (a blow-up).
template <int Block>
bool law(Lanes<Block>& lanes_of, int found, const double* vx, const double* vy, const double* vz, double stiffness,
         double damping) {
  const __m512d kn = _mm512_set1_pd(stiffness), cn = _mm512_set1_pd(damping), one = _mm512_set1_pd(1.0);
  __mmask8 blown = 0;
  for (int q = 0; q < found; q += 8) {
    const __mmask8 lanes = first_lanes(found - q);
    const __m256i i = _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes_of.i + q));
    const __m256i j = _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes_of.j + q));
    const __m512d dist = _mm512_maskz_sqrt_pd(lanes, _mm512_load_pd(lanes_of.dist2 + q));
    const __m512d ri = _mm512_load_pd(lanes_of.ri + q), rj = _mm512_load_pd(lanes_of.rj + q);
    const __m512d overlap = _mm512_sub_pd(_mm512_add_pd(ri, rj), dist);
    blown |= _mm512_mask_cmp_pd_mask(lanes, overlap, _mm512_maskz_min_pd(lanes, ri, rj), _CMP_GT_OQ);
    const __m512d inv = _mm512_div_pd(one, dist);  // from i towards j: one division, not three
    const __m512d nx = _mm512_mul_pd(_mm512_load_pd(lanes_of.dx + q), inv);
    const __m512d ny = _mm512_mul_pd(_mm512_load_pd(lanes_of.dy + q), inv);
    const __m512d nz = _mm512_mul_pd(_mm512_load_pd(lanes_of.dz + q), inv);
    const __m512d wx = gathered_difference(lanes, i, j, vx);
    const __m512d wy = gathered_difference(lanes, i, j, vy);
    const __m512d wz = gathered_difference(lanes, i, j, vz);
    const __m512d closing = _mm512_fmadd_pd(wz, nz, _mm512_fmadd_pd(wy, ny, _mm512_mul_pd(wx, nx)));
    const __m512d push = _mm512_fmadd_pd(cn, closing, _mm512_mul_pd(kn, overlap));  // Eq. 6: f_n
    const __m512d minus_push = _mm512_sub_pd(_mm512_setzero_pd(), push);
    _mm512_store_pd(lanes_of.fx + q, _mm512_mul_pd(minus_push, nx));
    _mm512_store_pd(lanes_of.fy + q, _mm512_mul_pd(minus_push, ny));
    _mm512_store_pd(lanes_of.fz + q, _mm512_mul_pd(minus_push, nz));
  }
  return blown != 0;
}

}  // namespace fdem::touching_pairs_avx512
#endif

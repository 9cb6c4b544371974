#pragma once
// touching_pairs_avx512.hpp's pair pass for hosts with AVX2 and FMA but no
// AVX-512 (avx2_lanes.hpp): the same two steps (that file explains them and
// why the caller adds the forces in lane order) with the same operations in
// the same order, fused where that file fuses, so both give the same bits
// (dem_steps' hash of scene B), and its near-pair filter. Step 1 is scalar
// here: without AVX-512's compress a vector test, which keeps eight values a
// pair, lost to it (AMD Zen 3, plume at 0.2 s: pair pass 189 against 135 us
// a step; benchmarks/README.md); step 2, the law, runs four pairs a vector.
#include "dem/avx2_lanes.hpp"
#ifdef FDEM_DEM_AVX2
#include <cmath>
#include <cstddef>

#include "core/types.hpp"
#include "dem/touching_lanes.hpp"

namespace fdem::touching_pairs_avx2 {

using avx2_lanes::gathered_difference;

template <int Block>
using Lanes = TouchingLanes<Block, 4>;

/// Step 1 over pairs [begin, end) (at most Block): returns how many touch.
/// Every pair is written at the end of the kept ones, which advance only if
/// it touches: which do is random, and a branch would mispredict.
template <int Block>
int test(const Index* pi, const Index* pj, Index begin, Index end, const double* x, const double* y, const double* z,
         const double* d, Lanes<Block>& out) {
  int found = 0;
  for (Index k = begin; k < end; ++k) {
    const Index i = pi[k], j = pj[k];
    const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
    const double ri = 0.5 * d[i], rj = 0.5 * d[j];
    const double dist2 = std::fma(dz, dz, std::fma(dy, dy, dx * dx));
    const double sum_r = ri + rj;
    out.i[found] = i;
    out.j[found] = j;
    out.dx[found] = dx;
    out.dy[found] = dy;
    out.dz[found] = dz;
    out.dist2[found] = dist2;
    out.ri[found] = ri;
    out.rj[found] = rj;
    found += dist2 < sum_r * sum_r ? 1 : 0;
  }
  return found;
}

/// The near set's filter, as touching_pairs_avx512::near_filter, four half
/// pairs a vector (room for count + 4 in near_i, near_j: whole vectors are
/// stored). A tail vector loads its missing indices as grain 0 (maskload
/// zeroes them), masked out of the kept set. Unlike step 1 this is faster
/// as vectors (plume at 0.5 s: pair pass 88 against 109 us a step with the
/// scalar filter), as it keeps only indices.
inline std::size_t near_filter(const Index* pi, const Index* pj, std::size_t count, const double* x, const double* y,
                               const double* z, const double* d, double margin, Index* near_i, Index* near_j) {
  std::size_t kept = 0;
  const __m256d half = _mm256_set1_pd(0.5), extra = _mm256_set1_pd(margin);
  for (std::size_t k = 0; k < count; k += 4) {
    const auto left = static_cast<std::ptrdiff_t>(count - k);
    const __m128i lanes = avx2_lanes::first_lanes(left);
    const __m128i i = _mm_maskload_epi32(pi + k, lanes);
    const __m128i j = _mm_maskload_epi32(pj + k, lanes);
    const __m256d dx = gathered_difference(j, i, x);
    const __m256d dy = gathered_difference(j, i, y);
    const __m256d dz = gathered_difference(j, i, z);
    const __m256d sum_d = _mm256_add_pd(avx2_lanes::gather(d, i), avx2_lanes::gather(d, j));
    const __m256d reach = _mm256_fmadd_pd(half, sum_d, extra);
    const __m256d dist2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
    const int near = _mm256_movemask_pd(_mm256_cmp_pd(dist2, _mm256_mul_pd(reach, reach), _CMP_LT_OQ)) &
                     avx2_lanes::lane_bits(lanes);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(near_i + kept), avx2_lanes::compress(near, i));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(near_j + kept), avx2_lanes::compress(near, j));
    kept += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(near)));
  }
  return kept;
}

/// Step 2 for the `found` touching pairs: the force on i into out.f*, and
/// whether an overlap exceeded the smaller radius (a blow-up). Lanes past
/// `found` hold grain indices too (step 1 writes every pair it tests, and the
/// block starts zeroed), so their loads are in bounds.
template <int Block>
bool law(Lanes<Block>& lanes_of, int found, const double* vx, const double* vy, const double* vz, double stiffness,
         double damping) {
  const __m256d kn = _mm256_set1_pd(stiffness), cn = _mm256_set1_pd(damping), one = _mm256_set1_pd(1.0);
  int blown = 0;
  for (int q = 0; q < found; q += 4) {
    const int lanes = found - q >= 4 ? 0xF : (1 << (found - q)) - 1;
    const __m128i i = _mm_load_si128(reinterpret_cast<const __m128i*>(lanes_of.i + q));
    const __m128i j = _mm_load_si128(reinterpret_cast<const __m128i*>(lanes_of.j + q));
    const __m256d dist = _mm256_sqrt_pd(_mm256_load_pd(lanes_of.dist2 + q));
    const __m256d ri = _mm256_load_pd(lanes_of.ri + q), rj = _mm256_load_pd(lanes_of.rj + q);
    const __m256d overlap = _mm256_sub_pd(_mm256_add_pd(ri, rj), dist);
    blown |= _mm256_movemask_pd(_mm256_cmp_pd(overlap, _mm256_min_pd(ri, rj), _CMP_GT_OQ)) & lanes;
    const __m256d inv = _mm256_div_pd(one, dist);  // from i towards j: one division, not three
    const __m256d nx = _mm256_mul_pd(_mm256_load_pd(lanes_of.dx + q), inv);
    const __m256d ny = _mm256_mul_pd(_mm256_load_pd(lanes_of.dy + q), inv);
    const __m256d nz = _mm256_mul_pd(_mm256_load_pd(lanes_of.dz + q), inv);
    const __m256d wx = gathered_difference(i, j, vx);
    const __m256d wy = gathered_difference(i, j, vy);
    const __m256d wz = gathered_difference(i, j, vz);
    const __m256d closing = _mm256_fmadd_pd(wz, nz, _mm256_fmadd_pd(wy, ny, _mm256_mul_pd(wx, nx)));
    const __m256d push = _mm256_fmadd_pd(cn, closing, _mm256_mul_pd(kn, overlap));  // Eq. 6: f_n
    const __m256d minus_push = _mm256_sub_pd(_mm256_setzero_pd(), push);
    _mm256_store_pd(lanes_of.fx + q, _mm256_mul_pd(minus_push, nx));
    _mm256_store_pd(lanes_of.fy + q, _mm256_mul_pd(minus_push, ny));
    _mm256_store_pd(lanes_of.fz + q, _mm256_mul_pd(minus_push, nz));
  }
  return blown != 0;
}

}  // namespace fdem::touching_pairs_avx2
#endif

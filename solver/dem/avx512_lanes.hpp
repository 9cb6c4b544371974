#pragma once
// What the DEM's AVX-512 loops share (the list build, neighbour_list.cpp;
// the pair pass and near-pair filter, touching_pairs_avx512.hpp): whether
// the build has them (FDEM_DEM_AVX512; scalar code is compiled otherwise),
// the mask of a vector's first lanes and a gathered difference.
#if defined(__AVX512F__) && defined(__AVX512VL__)
#define FDEM_DEM_AVX512 1
#include <immintrin.h>

#include <cstddef>

namespace fdem::avx512_lanes {

/// The first min(count, 8) lanes.
inline __mmask8 first_lanes(std::ptrdiff_t count) {
  return static_cast<__mmask8>(count >= 8 ? 0xFFu : (1u << count) - 1u);
}

/// v[a] - v[b] in the given lanes (zero in the others).
inline __m512d gathered_difference(__mmask8 lanes, __m256i a, __m256i b, const double* v) {
  const __m512d zero = _mm512_setzero_pd();
  return _mm512_sub_pd(_mm512_mask_i32gather_pd(zero, lanes, a, v, 8), _mm512_mask_i32gather_pd(zero, lanes, b, v, 8));
}

}  // namespace fdem::avx512_lanes
#endif

#pragma once
// What the DEM's AVX2 loops share (the list build, neighbour_list.cpp; the
// pair law, touching_pairs_avx2.hpp), for hosts with AVX2 and FMA and no
// AVX-512 (FDEM_DEM_AVX2; an AMD Zen 3 host of this project's machine kind):
// the mask of a vector's first lanes, a compress of four indices (the kept
// lanes moved to the front, in order; AVX-512 has it as an instruction) and
// a gathered difference.
#if defined(__AVX2__) && defined(__FMA__) && !(defined(__AVX512F__) && defined(__AVX512VL__))
#define FDEM_DEM_AVX2 1
#include <immintrin.h>

#include <cstddef>
#include <cstdint>

namespace fdem::avx2_lanes {

struct LaneTables {
  alignas(16) std::int32_t compress[16][4];  // vpermilps indices: the set lanes of a 4-bit mask first
  alignas(16) std::int32_t first[5][4];      // the first 0..4 lanes set (maskload's sign bits)
};

constexpr LaneTables make_lane_tables() {
  LaneTables t{};
  for (int mask = 0; mask < 16; ++mask) {
    int out = 0;
    for (int lane = 0; lane < 4; ++lane)
      if (mask >> lane & 1) t.compress[mask][out++] = lane;
  }
  for (int count = 0; count <= 4; ++count)
    for (int lane = 0; lane < count; ++lane) t.first[count][lane] = -1;
  return t;
}
inline constexpr LaneTables kLaneTables = make_lane_tables();

/// Sign-bit mask of the first min(count, 4) 32-bit lanes, for _mm_maskload_epi32.
inline __m128i first_lanes(std::ptrdiff_t count) {
  return _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneTables.first[count >= 4 ? 4 : count]));
}

/// Those lanes as sign-bit masks of four doubles, for _mm256_maskload_pd.
inline __m256i double_lanes(__m128i lanes) { return _mm256_cvtepi32_epi64(lanes); }

/// Those lanes as 4 bits, to mask a movemask's.
inline int lane_bits(__m128i lanes) { return _mm_movemask_ps(_mm_castsi128_ps(lanes)); }

/// The lanes of `keep` (4 bits) of v moved to the front, in lane order.
inline __m128i compress(int keep, __m128i v) {
  const __m128i order = _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneTables.compress[keep]));
  return _mm_castps_si128(_mm_permutevar_ps(_mm_castsi128_ps(v), order));
}

/// v[a] in every lane (a valid in all four), as four loads: vgatherdpd is
/// microcoded on Zen 3 and lost to them (scene B's pair pass, 2026-12-06).
inline __m256d gather(const double* v, __m128i a) {
  return _mm256_set_pd(v[_mm_extract_epi32(a, 3)], v[_mm_extract_epi32(a, 2)], v[_mm_extract_epi32(a, 1)],
                       v[_mm_cvtsi128_si32(a)]);
}

/// v[a] - v[b] in every lane (a, b valid indices in all four).
inline __m256d gathered_difference(__m128i a, __m128i b, const double* v) {
  return _mm256_sub_pd(gather(v, a), gather(v, b));
}

}  // namespace fdem::avx2_lanes
#endif

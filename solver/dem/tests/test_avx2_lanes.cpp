// The AVX2 lane helpers (dem/avx2_lanes.hpp) the list build and the pair
// pass rely on: a wrong table entry drops or repeats a neighbour. On a build
// without them (AVX-512 or no AVX2) the tests skip.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

#include "dem/avx2_lanes.hpp"

namespace fdem {
namespace {

TEST(Avx2Lanes, CompressPutsTheKeptLanesFirstInOrder) {
#ifdef FDEM_DEM_AVX2
  const __m128i v = _mm_setr_epi32(10, 11, 12, 13);
  for (int keep = 0; keep < 16; ++keep) {
    alignas(16) std::array<std::int32_t, 4> out{};
    _mm_store_si128(reinterpret_cast<__m128i*>(out.data()), avx2_lanes::compress(keep, v));
    int at = 0;
    for (int lane = 0; lane < 4; ++lane) {
      if (keep >> lane & 1) {
        EXPECT_EQ(out[static_cast<std::size_t>(at++)], 10 + lane) << "mask " << keep;
      }
    }
    EXPECT_EQ(at, std::popcount(static_cast<unsigned>(keep)));
  }
#else
  GTEST_SKIP() << "built without the AVX2 paths";
#endif
}

TEST(Avx2Lanes, MaskedLoadsReadOnlyTheFirstLanes) {
#ifdef FDEM_DEM_AVX2
  const std::array<std::int32_t, 4> indices{7, 8, 9, 10};
  const std::array<double, 4> values{1.5, 2.5, 3.5, 4.5};
  for (int count = 0; count <= 6; ++count) {
    alignas(16) std::array<std::int32_t, 4> got_i{};
    alignas(32) std::array<double, 4> got_v{};
    const __m128i lanes = avx2_lanes::first_lanes(count);
    _mm_store_si128(reinterpret_cast<__m128i*>(got_i.data()), _mm_maskload_epi32(indices.data(), lanes));
    _mm256_store_pd(got_v.data(), _mm256_maskload_pd(values.data(), avx2_lanes::double_lanes(lanes)));
    EXPECT_EQ(avx2_lanes::lane_bits(lanes), (1 << std::min(count, 4)) - 1) << "count " << count;
    for (std::size_t lane = 0; lane < 4; ++lane) {
      const bool loaded = static_cast<int>(lane) < count;
      EXPECT_EQ(got_i[lane], loaded ? indices[lane] : 0) << "count " << count << " lane " << lane;
      EXPECT_EQ(got_v[lane], loaded ? values[lane] : 0.0) << "count " << count << " lane " << lane;
    }
  }
#else
  GTEST_SKIP() << "built without the AVX2 paths";
#endif
}

TEST(Avx2Lanes, GatheredDifferenceReadsEachLanesOwnIndex) {
#ifdef FDEM_DEM_AVX2
  const std::array<double, 6> v{0.0, 1.0, 4.0, 9.0, 16.0, 25.0};
  alignas(32) std::array<double, 4> out{};
  _mm256_store_pd(out.data(), avx2_lanes::gathered_difference(_mm_setr_epi32(5, 4, 3, 2), _mm_setr_epi32(0, 1, 2, 5),
                                                              v.data()));
  EXPECT_EQ(out[0], 25.0);
  EXPECT_EQ(out[1], 15.0);
  EXPECT_EQ(out[2], 5.0);
  EXPECT_EQ(out[3], -21.0);
#else
  GTEST_SKIP() << "built without the AVX2 paths";
#endif
}

}  // namespace
}  // namespace fdem

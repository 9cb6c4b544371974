#pragma once
// glibc declares the vector variants of its libm functions (libmvec,
// _ZGV<isa>N<lanes>v_log, ...) to GCC only under -ffast-math
// (bits/math-vector.h). We want them without fast-math's other licences
// (reassociation, finite-only arithmetic, flush to zero), so we make the
// same declarations glibc makes: `omp simd` loops calling pow, exp or log
// then call the 2/4/8-wide libmvec variant of the target (AVX-512:
// _ZGVeN8v_log, _ZGVeN8v_exp, _ZGVeN8vv_pow; <= 4 ulp by glibc's tables,
// measured <= 3 ulp for exp(0.3435 log x)); libm.so links libmvec as
// needed. Elsewhere (clang, other libcs) they stay the scalar libm calls.
// Every drag law includes this first, so its inline block functions are
// compiled alike in every translation unit.
#include <cmath>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__) && !defined(__FAST_MATH__)
extern "C" {
__attribute__((__simd__("notinbranch"))) double pow(double, double) noexcept;
__attribute__((__simd__("notinbranch"))) double exp(double) noexcept;
__attribute__((__simd__("notinbranch"))) double log(double) noexcept;
}
#endif

#include <bit>
#include <cstdint>

namespace fdem {

/// The relative error single_precision_power stays within (measured in its test).
inline constexpr double single_precision_power_error = 2e-7;

/// x^y in single precision, written out with no branch, table or call so
/// that an `omp simd` loop inlines it eight lanes an AVX2 vector (twice a
/// double's four, with shorter polynomials): for Wen & Yu's Reynolds-number
/// correction s^0.687, whose exponent is itself a three-digit fit. With
/// x = 2^k m (m in [sqrt(1/2), sqrt(2)), f = m - 1):
///   log2 m = 2 atanh(f / (2 + f)) / ln 2   (series to the 9th power; next term < 4e-10)
///   t = y log2 x = y k + y log2 m, y k exact as a float sum (y split in two
///       floats, the product's rounding error by an FMA), so t's rounding
///       does not grow with |t|
///   x^y = 2^n 2^r, n = round(t), r = t - n   (Taylor in r ln 2 to the 7th; next < 5e-9)
/// Within 2e-7 of x^y (relative; 1.4e-7 the worst of 6e6 samples) for x
/// in [1e-30, 1e30], |y| <= 1 (drag_laws/tests/test_drag_laws.cpp). x is rounded to
/// float: below its smallest normal (1.2e-38) the result is 0, exact at 0;
/// x must stay below its largest (3.4e38).
inline double single_precision_power(double x_double, double y_double) {
  const float x = static_cast<float>(x_double);
  const float y = static_cast<float>(y_double), y_low = static_cast<float>(y_double - static_cast<double>(y));
  // 1. log2 x: the float's exponent field and mantissa. Every select on
  //    integers: GCC if-converts no floating-point compare under
  //    -ftrapping-math for AVX2, which has no masked operations.
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
  const std::uint32_t mantissa = bits & 0x007fffffU;
  const std::uint32_t upper = mantissa > 0x3504f3U ? 1U : 0U;  // the mantissa of sqrt(2)
  const std::uint32_t field = bits >> 23;
  const float k = static_cast<float>(static_cast<std::int32_t>(field + upper) - 127);
  const float m = std::bit_cast<float>(mantissa | ((127U - upper) << 23));  // 1.m, or 1.m / 2 above sqrt(2)
  const float f = m - 1.0f;                                                 // exact (Sterbenz)
  const float s = f / (2.0f + f), z = s * s;
  constexpr float two_log2e = 2.88539008177792681f;  // 2 / ln 2
  const float log2_m =
      two_log2e * s * (1.0f + z * (1.0f / 3.0f + z * (1.0f / 5.0f + z * (1.0f / 7.0f + z * (1.0f / 9.0f)))));
  // 2. t = whole + part, whole = y k rounded, part small: n = round(t) by
  //    the 1.5 * 2^23 trick, r = (whole - n) + part (whole - n exact).
  const float whole = y * k;
  const float part = std::fma(y, k, -whole) + std::fma(y_low, k, y * log2_m);
  constexpr float shifter = 12582912.0f;
  const float shifted = (whole + part) + shifter;
  const float n = shifted - shifter;
  const float r = ((whole - n) + part) * 0.693147180559945309f;  // 2^r = exp(r ln 2)
  const float e =
      1.0f + r * (1.0f + r * (1.0f / 2.0f + r * (1.0f / 6.0f + r * (1.0f / 24.0f + r * (1.0f / 120.0f +
                                                                         r * (1.0f / 720.0f + r * (1.0f / 5040.0f)))))));
  const std::uint32_t scale = (std::bit_cast<std::uint32_t>(shifted) - std::bit_cast<std::uint32_t>(shifter)) << 23;
  const std::uint32_t normal = field != 0 ? ~0U : 0U;  // 0 and subnormals give 0
  return static_cast<double>(std::bit_cast<float>((std::bit_cast<std::uint32_t>(e) + scale) & normal));
}

}  // namespace fdem

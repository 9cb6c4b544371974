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

/// x^y for the subcycle's slip powers: exp(y log x) written out (fdlibm's
/// e_log.c and e_exp.c reductions and minimax polynomials, each < 1 ulp)
/// with no branch, table or call, so an `omp simd` loop inlines it eight
/// lanes wide: no libmvec call, and no spill of the loop's live vectors
/// around one (the vector ABI saves no register). For finite x >= 0 and
/// |y| <= 1; x below the smallest normal double (0, subnormals) gives 0,
/// exact at 0. Within 2 ulp of glibc's scalar exp(y log x) for x in
/// [1e-20, 1e4] (drag_laws/tests/test_drag_laws.cpp; libmvec's vector
/// exp(y log x) is within 4 ulp of it); like any exp(y log x), off the
/// exact x^y by up to |y log x| ulp from the rounding of y log x.
inline double power_of_positive(double x, double y) {
  // 1. log x = k ln 2 + log m, m in [sqrt(1/2), sqrt(2)): the exponent field
  //    as a double through the 2^52 trick (exact; AVX2 has no int64 -> double).
  //    Every select on integers: GCC if-converts no floating-point compare
  //    under -ftrapping-math for AVX2, which has no masked operations.
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  const std::uint64_t mantissa = bits & 0x000fffffffffffffULL;
  const std::uint64_t upper = mantissa > 0x6a09e667f3bcdULL ? 1 : 0;  // the mantissa of sqrt(2)
  const std::uint64_t field = bits >> 52;
  const double two52 = 4503599627370496.0;
  const double k = std::bit_cast<double>((field + upper) | std::bit_cast<std::uint64_t>(two52)) - two52 - 1023.0;
  const double m = std::bit_cast<double>(mantissa | ((0x3ffULL - upper) << 52));  // 1.m, or 1.m / 2 above sqrt(2)
  const double f = m - 1.0;  // exact (Sterbenz)
  constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
  constexpr double lg1 = 6.666666666666735130e-01, lg2 = 3.999999999940941908e-01,
                   lg3 = 2.857142874366239149e-01, lg4 = 2.222219843214978396e-01,
                   lg5 = 1.818357216161805012e-01, lg6 = 1.531383769920937332e-01,
                   lg7 = 1.479819860511658591e-01;
  const double s = f / (2.0 + f), z = s * s, w = z * z;
  const double t1 = w * (lg2 + w * (lg4 + w * lg6)), t2 = z * (lg1 + w * (lg3 + w * (lg5 + w * lg7)));
  const double r = t2 + t1, hfsq = 0.5 * f * f;
  const double log_x = k * ln2_hi - ((hfsq - (s * (hfsq + r) + k * ln2_lo)) - f);
  // 2. exp(t), t = y log x: t = n ln 2 + q, |q| <= ln 2 / 2, n by the
  //    1.5 * 2^52 rounding trick (|t| <= 745 here), then 2^n into the exponent.
  const double t = y * log_x;
  constexpr double inv_ln2 = 1.44269504088896338700e+00, shifter = 6755399441055744.0;
  constexpr double p1 = 1.66666666666666019037e-01, p2 = -2.77777777770155933842e-03,
                   p3 = 6.61375632143793436117e-05, p4 = -1.65339022054652515390e-06,
                   p5 = 4.13813679705723846039e-08;
  const double shifted = t * inv_ln2 + shifter;
  const double n = shifted - shifter;
  const double hi = t - n * ln2_hi, lo = n * ln2_lo, q = hi - lo;
  const double qq = q * q;
  const double c = q - qq * (p1 + qq * (p2 + qq * (p3 + qq * (p4 + qq * p5))));
  const double e = 1.0 - ((lo - (q * c) / (2.0 - c)) - hi);
  const std::uint64_t scale = (std::bit_cast<std::uint64_t>(shifted) - std::bit_cast<std::uint64_t>(shifter)) << 52;
  const std::uint64_t normal = field != 0 ? ~0ULL : 0ULL;  // 0 and subnormals give 0
  return std::bit_cast<double>((std::bit_cast<std::uint64_t>(e) + scale) & normal);
}

}  // namespace fdem

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

#pragma once
// The vector pair pass and near-pair filter of the host's widest ISA (the
// same bits on both, see touching_pairs_avx2.hpp), as `pair_lanes`, with
// FDEM_DEM_PAIR_LANES defined; a build without either has neither, and
// its callers use scalar code.
#include "dem/touching_pairs_avx2.hpp"
#include "dem/touching_pairs_avx512.hpp"

namespace fdem {
#if defined(FDEM_DEM_AVX512)
#define FDEM_DEM_PAIR_LANES 1
namespace pair_lanes = touching_pairs_avx512;
#elif defined(FDEM_DEM_AVX2)
#define FDEM_DEM_PAIR_LANES 1
namespace pair_lanes = touching_pairs_avx2;
#endif
}  // namespace fdem

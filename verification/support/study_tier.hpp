#pragma once
// Which tier a study's program runs, fixed when it is built: a study's fast
// program (ctest label verification) and its full one (nightly) compile the
// same sources, the full one with FDEM_FULL_TIER=1 (the study's CMakeLists.txt).
#ifndef FDEM_FULL_TIER
#define FDEM_FULL_TIER 0
#endif

namespace fdem::verification {

inline constexpr bool full_tier = FDEM_FULL_TIER != 0;
/// The tier's name in result ids and rows: "full" or "fast".
inline constexpr const char* tier_name = full_tier ? "full" : "fast";

}  // namespace fdem::verification

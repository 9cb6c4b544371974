#pragma once
// The paper's channel-flow contact (Sect. 4.3, Table 3): Kn 1e5 N/m and
// Cn 0.026 N s/m for grains of d 0.2-0.3 mm, rho 2170 kg/m^3. At the paper's
// DEM step of 1e-5 s that is 14.9 contact times of the smallest pair, a step
// the engine must refuse (verification/hard_cases/README.md). Shared by the stability unit
// tests (solver/scene/tests) and the engine's refusal (verification/dem).
// Test code only.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace fdem::scene_test {

inline ContactSpec paper_channel_contact() {
  ContactSpec contact;
  contact.normal_stiffness = 1e5;  // Kn [N/m]
  contact.normal_damping = 0.026;  // Cn [N s/m]
  return contact;
}

/// The refusal of the paper's 1e-5 s step names the key and its value, the
/// stable bound (the dashpot binds: 0.5 * 2 m_eff / Cn = 4.54e-9 / 0.026 =
/// 1.75e-7 s), the step in contact times, and the way to run anyway.
inline void expect_paper_channel_step_refused(const InputError& e) {
  EXPECT_EQ(e.key(), "time.dem_step");
  EXPECT_EQ(e.value(), "1e-05");
  const std::string what = e.what();
  EXPECT_NE(what.find("stable bound 1.75e-07 s"), std::string::npos) << what;
  EXPECT_NE(what.find("14.9 t_c"), std::string::npos) << what;
  EXPECT_NE(what.find("allow_unstable_step"), std::string::npos) << what;
}

}  // namespace fdem::scene_test

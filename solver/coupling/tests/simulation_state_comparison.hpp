#pragma once
// Two runs compared state for state (checkpoint and restart): every
// particle array, the fluid fields, the porosity, the source term and the
// diagnostics counters, bit for bit; a mismatch prints the relative
// difference, to tell round-off from a real divergence. Shared by
// solver/coupling/tests/test_checkpoint.cpp and verification/restart.
// Test code only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "coupling/simulation.hpp"

namespace fdem::checkpoint_test {

inline bool bitwise_equal(std::span<const double> a, std::span<const double> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}

/// Largest difference relative to the largest magnitude of `a` (infinite when the sizes differ).
inline double relative_difference(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return scale > 0.0 ? diff / scale : diff;
}

/// Every piece of state a reader of the run sees, and what the next step
/// starts from (forces, torques), the same bit for bit.
inline void expect_bitwise_same_state(const Simulation& a, const Simulation& b) {
  EXPECT_EQ(a.step_index(), b.step_index());
  EXPECT_EQ(a.time(), b.time());
  const Particles &p = a.particles(), &q = b.particles();
  ASSERT_EQ(p.size(), q.size());
  EXPECT_EQ(p.id, q.id);
  using Field = GrainArray Particles::*;
  const std::pair<Field, const char*> fields[] = {
      {&Particles::x, "x"},   {&Particles::y, "y"},   {&Particles::z, "z"},         {&Particles::vx, "vx"},
      {&Particles::vy, "vy"}, {&Particles::vz, "vz"}, {&Particles::fx, "fx"},       {&Particles::fy, "fy"},
      {&Particles::fz, "fz"}, {&Particles::wx, "wx"}, {&Particles::wy, "wy"},       {&Particles::wz, "wz"},
      {&Particles::tx, "tx"}, {&Particles::ty, "ty"}, {&Particles::tz, "tz"},       {&Particles::inertia, "inertia"},
      {&Particles::diameter, "diameter"},             {&Particles::mass, "mass"}};
  for (const auto& [field, name] : fields)
    EXPECT_TRUE(bitwise_equal(p.*field, q.*field))
        << "particle " << name << ": relative difference " << relative_difference(p.*field, q.*field);
  struct MeshField {
    std::span<const double> a, b;
    const char* name;
  };
  const MeshField mesh_fields[] = {{a.fluid_velocity(), b.fluid_velocity(), "fluid velocity"},
                                   {a.fluid_pressure(), b.fluid_pressure(), "fluid pressure"},
                                   {a.porosity(), b.porosity(), "porosity"},
                                   {a.source_term(), b.source_term(), "source term"}};
  for (const auto& [u, v, name] : mesh_fields)
    EXPECT_TRUE(bitwise_equal(u, v)) << name << ": relative difference " << relative_difference(u, v);
  EXPECT_EQ(a.diagnostics().floored_element_updates, b.diagnostics().floored_element_updates);
  EXPECT_EQ(a.diagnostics().dem.contacts, b.diagnostics().dem.contacts);
}

}  // namespace fdem::checkpoint_test

// Hard case: drag at the ends of its range. A 5 mm grain of 20000 kg/m^3 in
// water settles at Re ~ 8400, where Eq. 14 makes Cd constant (0.44) and the
// terminal velocity has a closed form; a 2 mm grain of 500 kg/m^3 rises at
// Re ~ 280, against a GSL root of the force balance with Eq. 14. One-way
// coupling (fluid_to_particle), so the water stays at rest and the reference
// is exact; the element porosity differs from 1 by V_p / V_e < 1e-3.
#include <gtest/gtest.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include <cmath>
#include <cstdio>

#include "coupling/simulation.hpp"
#include "hard_scenes.hpp"

namespace fdem {
namespace {

constexpr double kG = 9.81, kRhoF = 1000.0, kMu = 1.0e-3;

// Eq. 14 (Rowe & Henwood), the isolated sphere, written out here as the reference.
double reference_cd(double re) { return re > 1000.0 ? 0.44 : 24.0 / re * (1.0 + 0.15 * std::pow(re, 0.687)); }

struct Balance {
  double d, rho_p;
};
// Net force per unit of pi d^2 / 4 on a sphere moving at v through still water:
// |rho_p - rho_f| g d * 2/3 - 1/2 Cd rho_f v^2 (weight minus buoyancy minus drag).
double force_balance(double v, void* params) {
  const auto* b = static_cast<const Balance*>(params);
  const double re = kRhoF * v * b->d / kMu;
  return 2.0 / 3.0 * std::abs(b->rho_p - kRhoF) * kG * b->d - 0.5 * reference_cd(re) * kRhoF * v * v;
}

double gsl_terminal_velocity(double d, double rho_p) {
  Balance b{d, rho_p};
  gsl_function f{&force_balance, &b};
  gsl_root_fsolver* s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(s, &f, 1e-6, 10.0);
  double v = 0.0;
  for (int it = 0; it < 200; ++it) {
    gsl_root_fsolver_iterate(s);
    v = gsl_root_fsolver_root(s);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s), 0.0, 1e-12) == GSL_SUCCESS)
      break;
  }
  gsl_root_fsolver_free(s);
  return v;
}

// A still-water column 5 x 5 cm wide, one-way coupled, one grain.
Scene column(double height_m, int cells_z, const ParticleSet& grain, double end_s) {
  Scene s = hard::water_box(1, 1, cells_z, 0.05);
  s.domain.upper.z() = height_m;
  s.effects.coupling = CouplingMode::fluid_to_particle;
  s.particles.push_back(grain);
  s.contact = hard::soft_contact();
  s.time.fluid_step = 1e-2;
  s.time.dem_step = 1e-4;
  s.time.subcycles = 100;
  s.time.end_time = end_s;
  return s;
}

TEST(TerminalVelocity, DenseGrainAboveRe1000MatchesTheClosedFormWithCdConstant) {
  // Shows: d 5 mm, rho 20000 settles at sqrt(4 g d (rho_p - rho_f) / (3 * 0.44 rho_f)) = 1.680 m/s within 0.1 %, Re > 1000.
  const double d = 5e-3, rho_p = 20000.0;
  const double closed_form = std::sqrt(4.0 * kG * d * (rho_p - kRhoF) / (3.0 * 0.44 * kRhoF));
  EXPECT_NEAR(gsl_terminal_velocity(d, rho_p), closed_form, 1e-9);  // the two references agree
  Simulation sim(column(2.0, 8, hard::single_particle(Vec3(0.025, 0.025, 1.95), d, rho_p), 1.0));
  while (!sim.finished()) sim.step();
  const double v = -sim.particles().vz[0];
  EXPECT_GT(kRhoF * v * d / kMu, 1000.0) << "the case must sit in the constant-Cd branch";
  // 0.1 %: porosity 1 - 3e-4 in its element (Wen & Yu's eps^-1.65 raises drag by 5e-4, so v_t
  // falls by 2.5e-4; measured -2.9e-4), the approach tanh(g' t / v_t) = 1 - 3e-5 at 1 s, and the
  // O(dt) DEM error at dt = 1e-4 s.
  std::printf("dense grain: v %.6g m/s, closed form %.6g m/s (%+.3g %%), Re %.0f\n", v, closed_form,
              100.0 * (v / closed_form - 1.0), kRhoF * v * d / kMu);
  EXPECT_NEAR(v, closed_form, 0.001 * closed_form);
  for (double u : sim.fluid_velocity()) EXPECT_EQ(u, 0.0) << "one-way: the water stays at rest";
}

TEST(TerminalVelocity, GrainLighterThanWaterRisesAtTheGslTerminalVelocity) {
  // Shows: d 2 mm, rho 500 rises (vz > 0) at the GSL root of the Eq. 14 force balance (~0.14 m/s) within 0.1 %.
  const double d = 2e-3, rho_p = 500.0;
  const double reference = gsl_terminal_velocity(d, rho_p);
  Simulation sim(column(0.5, 4, hard::single_particle(Vec3(0.025, 0.025, 0.05), d, rho_p), 0.5));
  const double z0 = sim.particles().z[0];
  while (!sim.finished()) sim.step();
  const double v = sim.particles().vz[0];
  EXPECT_GT(sim.particles().z[0], z0) << "lighter than water: it rises";
  // 0.1 %: eps = 1 - 8e-5 in its element (v_t lower by ~7e-5; measured -5e-5), the approach
  // (response time ~ 20 ms, run 0.5 s), and the O(dt) DEM error.
  std::printf("light grain: v %.6g m/s, GSL root %.6g m/s (%+.3g %%), Re %.0f\n", v, reference,
              100.0 * (v / reference - 1.0), kRhoF * v * d / kMu);
  EXPECT_NEAR(v, reference, 0.001 * reference);
  const double re = kRhoF * v * d / kMu;
  EXPECT_GT(re, 100.0);
  EXPECT_LT(re, 1000.0);
}

}  // namespace
}  // namespace fdem

// GSL reference solutions of single-particle settling.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference/settling_reference.hpp"

namespace fdem {
namespace {

SettlingModel water_model(double d, const char* law = "ergun_wen_yu") {
  SettlingModel m;
  m.diameter_m = d;
  m.particle_density = 2650.0;
  m.fluid = {1000.0, 1.0e-3};
  m.drag = law;
  return m;
}

TEST(SettlingReference, StokesOdeMatchesExponentialApproach) {
  // With Stokes drag the ODE is linear: w(t) = -v_s (1 - exp(-t / tau)),
  // tau = rho_p d^2 / (18 mu). rk8pd at rel_tol 1e-12 is good to ~1e-11 relative.
  const SettlingModel m = water_model(0.2e-3, "stokes");
  const double vs = stokes_terminal_velocity(m);
  const double tau = m.particle_density * m.diameter_m * m.diameter_m / (18.0 * m.fluid.viscosity);
  const std::vector<double> times{0.0, 1e-3, 5e-3, 0.01, 0.05, 0.2};
  const auto states = integrate_settling(m, Vec3(0, 0, 0.07), 0.0, times);
  for (const auto& s : states) {
    const double exact = -vs * (1.0 - std::exp(-s.time_s / tau));
    EXPECT_NEAR(s.w_m_s, exact, 1e-11 * vs) << s.time_s;
    // z(t) = z0 - vs (t - tau (1 - exp(-t/tau)))
    EXPECT_NEAR(s.z_m, 0.07 - vs * (s.time_s - tau * (1.0 - std::exp(-s.time_s / tau))), 1e-11 * 0.07);
  }
}

TEST(SettlingReference, RootWithStokesDragIsStokesLaw) {
  const SettlingModel m = water_model(0.3e-3, "stokes");
  // Brent to rel_tol 1e-13.
  EXPECT_NEAR(terminal_velocity(m, 1.0), stokes_terminal_velocity(m), 1e-12 * stokes_terminal_velocity(m));
}

TEST(SettlingReference, PaperClosureTendsToStokesAtLowReynolds) {
  // Eq. 14 at Re -> 0 is 24/Re (1 + 0.15 Re^0.687): for d = 20 um, v ~ 0.36 mm/s,
  // Re ~ 0.007, so the terminal speed is Stokes' divided by (1 + 0.15 Re^0.687) ~ 1.005.
  const SettlingModel m = water_model(20e-6);
  const double v = terminal_velocity(m, 1.0), vs = stokes_terminal_velocity(m);
  const double re = 1000.0 * v * 20e-6 / 1e-3;
  EXPECT_NEAR(v, vs / (1.0 + 0.15 * std::pow(re, 0.687)), 1e-10 * vs);
  EXPECT_LT(std::abs(v / vs - 1.0), 0.01);
}

TEST(SettlingReference, OdeTerminalValueEqualsRoot) {
  // Constant porosity 0.99 (a grain in a 4 mm cell's central tetrahedron is
  // 0.989 for d = 0.76 mm). After 1 s (> 30 response times) the ODE speed
  // equals the root to the integrator's tolerance (1e-10 relative).
  for (double d : {0.208e-3, 0.76e-3}) {
    SettlingModel m = water_model(d);
    m.porosity = [](const Vec3&) { return 0.99; };
    const std::vector<double> times{1.0};
    const auto s = integrate_settling(m, Vec3(0, 0, 1.0), 0.0, times);
    const double vt = terminal_velocity(m, 0.99);
    EXPECT_NEAR(-s[0].w_m_s, vt, 1e-10 * vt) << d;
  }
}

TEST(SettlingReference, DesignTableOfTerminalVelocitiesInWater) {
  // reference_data/settling.csv (vt_ode_design): the ODE with the paper's drag law, eps = 1, mu = 1e-3 gives
  // 0.0263, 0.0340, 0.0414, 0.0647, 0.0933, 0.1199 m/s (3-4 digits: +-5e-5).
  const std::vector<double> d{0.208e-3, 0.25e-3, 0.29e-3, 0.42e-3, 0.59e-3, 0.76e-3};
  const std::vector<double> v{0.0263, 0.0340, 0.0414, 0.0647, 0.0933, 0.1199};
  for (std::size_t i = 0; i < d.size(); ++i) EXPECT_NEAR(terminal_velocity(water_model(d[i]), 1.0), v[i], 5e-5) << d[i];
}

TEST(SettlingReference, PorosityJumpAlongThePathIsIntegrated) {
  // Porosity 0.98 above z = 0.05 m and 0.96 below, start at z = 0.2 m: the speed relaxes from one
  // root to the other; the ODE follows the callable (checks the position is passed).
  SettlingModel m = water_model(0.76e-3);
  m.porosity = [](const Vec3& x) { return x.z() > 0.05 ? 0.98 : 0.96; };
  const std::vector<double> times{0.8, 2.5};  // crossing near t = 1.3 s; each time > 15 relaxation times after the start or the crossing
  const auto s = integrate_settling(m, Vec3(0.01, 0.02, 0.2), 0.0, times);
  ASSERT_GT(s[0].z_m, 0.05);
  ASSERT_LT(s[1].z_m, 0.05);
  EXPECT_NEAR(-s[0].w_m_s, terminal_velocity(m, 0.98), 1e-6);
  EXPECT_NEAR(-s[1].w_m_s, terminal_velocity(m, 0.96), 1e-6);
  EXPECT_GT(terminal_velocity(m, 0.98), terminal_velocity(m, 0.96));  // denser surroundings, more drag
}

}  // namespace
}  // namespace fdem

// A sphere launched sliding (no spin) on a plane with Coulomb friction mu:
// friction mu m g decelerates it and spins it up (torque mu m g r, I = m d^2/10)
// until the contact point stops slipping, at t* = 2 v0 / (7 mu g), after which
// it rolls at 5/7 v0.
#include <gtest/gtest.h>

#include <cmath>

#include "dem/dem_engine.hpp"
#include "dem_scene.hpp"
#include "../support/study_results.hpp"

namespace fdem {
namespace {

TEST(SlidingToRolling, RollsAtFiveSeventhsOfV0AfterTwoV0OverSevenMuG) {
  constexpr double d = 1e-3, rho = 2500.0, kn = 1e3, mu = 0.3, v0 = 0.1, g = 9.81;
  const double m = rho * sphere_volume(d);
  const double tc0 = pi * std::sqrt(m / kn);
  Scene s = verification::dry_scene(1.0, kn, tc0 / 100.0, true, true);
  s.effects.tangential_contact = true;
  s.effects.rotation = true;
  s.contact.restitution = 0.5;
  s.contact.tangential_stiffness = 2.0 / 7.0 * kn;
  s.contact.tangential_damping = 0.0;
  s.contact.friction = mu;
  Particles p;
  const double rest = m * g / kn;  // static overlap
  p.add(0.01, 0.5, 0.5 * d - rest, d, rho, v0);
  DemEngine dem(std::move(p), s);
  const double t_star = 2.0 * v0 / (7.0 * mu * g);
  double t_roll = -1.0;
  const double r = 0.5 * d;
  while (dem.time() < 2.0 * t_star) {
    dem.step();
    const Particles& q = dem.particles();
    const double slip = q.vx[0] - r * q.wy[0];  // contact-point velocity
    if (t_roll < 0.0 && slip <= 0.0) t_roll = dem.time();
  }
  const Particles& q = dem.particles();
  // t*: the slip reaches zero within one step; the tangential spring adds a
  // lag of order its period 2 pi sqrt(m_t/Kt) (~1.4e-4 s, 1.5 % of t* = 9.7 ms),
  // so 3 % of t*.
  verification::record_value("dem.rolling.t_star_s", t_roll);
  verification::record_value("dem.rolling.v_final_mps", q.vx[0]);
  verification::record_value("dem.rolling.r_omega_final_mps", r * q.wy[0]);
  EXPECT_NEAR(t_roll, t_star, 0.03 * t_star);
  // After t*, stick: the spring stores mu m g / Kt of slip and oscillates
  // about rolling with velocity amplitude mu g / omega_t ~ 2e-4 m/s = 0.3 % of
  // 5/7 v0; 1 % covers it.
  EXPECT_NEAR(q.vx[0], 5.0 / 7.0 * v0, 0.01 * 5.0 / 7.0 * v0);
  EXPECT_NEAR(r * q.wy[0], 5.0 / 7.0 * v0, 0.01 * 5.0 / 7.0 * v0);
  EXPECT_EQ(dem.diagnostics().particles_removed, 0u);
}

// Without friction the same sphere keeps sliding at v0 and never spins:
// rotation and tangential contact off cost nothing and change nothing.
TEST(SlidingToRolling, FrictionlessSphereKeepsSlidingAtV0) {
  constexpr double d = 1e-3, rho = 2500.0, kn = 1e3, v0 = 0.1;
  const double m = rho * sphere_volume(d);
  Scene s = verification::dry_scene(1.0, kn, pi * std::sqrt(m / kn) / 100.0, true, true);
  s.contact.restitution = 0.5;
  Particles p;
  p.add(0.01, 0.5, 0.5 * d - m * 9.81 / kn, d, rho, v0);
  DemEngine dem(std::move(p), s);
  dem.run(5000);
  verification::record_value("dem.rolling.frictionless_v_mps", dem.particles().vx[0]);
  EXPECT_EQ(dem.particles().vx[0], v0);  // exact: no tangential force exists
  EXPECT_TRUE(dem.particles().wy.empty());  // no rotation storage
}

}  // namespace
}  // namespace fdem

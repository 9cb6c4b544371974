// Unit tests of the contact laws (Eq. 6-8) for one contact, no integration.
#include <gtest/gtest.h>

#include <cmath>

#include "dem/contact_law.hpp"
#include "scene/stability.hpp"

namespace fdem {
namespace {

ContactLaw law() {
  ContactLaw c;
  c.linear.stiffness = 1000.0;
  c.linear.damping = 0.5;
  c.tangential_stiffness = 800.0;
  c.tangential_damping = 0.1;
  c.friction = 0.3;
  return c;
}

TEST(ContactLaw, NormalForceIsSpringPlusDashpotAlongMinusNormal) {
  const Vec3 n(0.0, 0.0, 1.0);
  const Vec3 v(0.0, 0.0, 0.2);  // closing at 0.2 m/s
  const ContactForce f = contact_force<false, LinearSpringDashpotForce<false>>(law(), 1e-3, 1e-4, n, v, 1e-6, nullptr);
  // Eq. 6: 1000 * 1e-4 + 0.5 * 0.2 = 0.2 N, pushing i away (-z). Exact to rounding.
  EXPECT_NEAR(f.normal_magnitude, 0.2, 1e-15);
  EXPECT_NEAR(f.normal.z(), -0.2, 1e-15);
  EXPECT_EQ(f.tangential.norm(), 0.0);
}

TEST(ContactLaw, TangentialSpringStaysBelowCoulombCapAndAccumulatesSlip) {
  const Vec3 n(0.0, 0.0, 1.0);
  const Vec3 v(1e-3, 0.0, 0.0);  // pure slip, no closing
  Vec3 slip = Vec3::Zero();
  const double dt = 1e-5;
  const ContactForce f = contact_force<true, LinearSpringDashpotForce<false>>(law(), 1e-3, 1e-3, n, v, dt, &slip);
  // slip = v dt = 1e-8 m; f_t = -(800 * 1e-8 + 0.1 * 1e-3) = -1.0008e-4 N << mu f_n = 0.3 N.
  EXPECT_NEAR(slip.x(), 1e-8, 1e-22);
  EXPECT_NEAR(f.tangential.x(), -(800.0 * 1e-8 + 0.1 * 1e-3), 1e-18);
}

TEST(ContactLaw, TangentialForceCappedByCoulombAndHistoryRescaled) {
  const Vec3 n(0.0, 0.0, 1.0);
  const Vec3 v(0.0, 2.0, 0.0);
  Vec3 slip(0.0, 1e-2, 0.0);  // spring would give 8 N >> mu f_n
  const ContactForce f = contact_force<true, LinearSpringDashpotForce<false>>(law(), 1e-3, 1e-3, n, v, 1e-6, &slip);
  const double cap = 0.3 * 1.0;  // mu * Kn delta = 0.3 N
  EXPECT_NEAR(f.tangential.norm(), cap, 1e-14);
  EXPECT_LT(f.tangential.y(), 0.0);  // opposes the slip
  // History reset so the spring-dashpot gives exactly the capped force.
  EXPECT_NEAR(-(800.0 * slip.y() + 0.1 * 2.0), f.tangential.y(), 1e-14);
}

TEST(ContactLaw, SlipHistoryIsProjectedIntoTheContactPlane) {
  const Vec3 n(0.0, 0.0, 1.0);
  Vec3 slip(1e-6, 0.0, 5e-7);  // out-of-plane part from a rotated normal
  contact_force<true, LinearSpringDashpotForce<false>>(law(), 1e-3, 1e-4, n, Vec3::Zero(), 1e-6, &slip);
  EXPECT_EQ(slip.z(), 0.0);
  EXPECT_NEAR(slip.x(), 1e-6, 1e-20);
}

TEST(ContactLaw, DampingFromRestitutionInvertsTheAnalyticRestitution) {
  for (double e : {0.1, 0.5, 0.9, 0.99}) {
    const double k = 1e5, m = 1e-8;
    const double c = damping_from_restitution(e, k, m);
    const double zeta = c / (2.0 * std::sqrt(k * m));
    // e = exp(-pi zeta / sqrt(1 - zeta^2)) back to rounding.
    EXPECT_NEAR(std::exp(-pi * zeta / std::sqrt(1.0 - zeta * zeta)), e, 1e-12);
    LinearSpringDashpot l;
    l.stiffness = k;
    l.damping_ratio = damping_ratio_from_restitution(e);
    EXPECT_NEAR(LinearSpringDashpotForce<true>::damping(l, m), c, 1e-15 * c + 1e-300);
  }
}

}  // namespace
}  // namespace fdem

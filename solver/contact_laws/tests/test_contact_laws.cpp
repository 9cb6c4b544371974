// The contact-law table (contact_law_table.cpp) and each law against a
// closed form: a binary collision integrated with the law's own normal force.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "contact_laws/contact_law.hpp"
#include "contact_laws/linear_spring_dashpot.hpp"
#include "scene/scene.hpp"

namespace fdem {
namespace {

TEST(ContactLawTable, RowsAreInCodeOrderWithUniqueNamesAndDocs) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < contact_laws().size(); ++i) {
    const ContactLawEntry& law = contact_laws()[i];
    EXPECT_EQ(static_cast<std::size_t>(law.code), i);
    EXPECT_TRUE(names.insert(std::string(law.name)).second) << law.name;
    EXPECT_FALSE(law.doc.empty() || law.summary.empty() || law.keys.empty()) << law.name;
    EXPECT_EQ(&contact_law_entry(law.code), &law);
    EXPECT_EQ(find_named_row(contact_laws(), law.name), &law);
  }
  EXPECT_EQ(find_named_row(contact_laws(), std::string_view("hertz_mindlin")), nullptr);
  // A scene that names no law keeps today's.
  EXPECT_EQ(contact_law_entry(ContactSpec{}.law).name, "linear_spring_dashpot");
}

// One head-on collision of a pair of effective mass m_eff closing at v0,
// integrated with velocity Verlet on the law's force until the overlap is
// gone (where the DEM pair loop ends a contact): the contact time and the
// restitution -v_out / v0.
struct Collision {
  double contact_time_s = 0.0;
  double restitution = 0.0;
};
template <class Law>
Collision collide(const typename Law::Coefficients& law, double m_eff, double v0, double dt) {
  double x = 0.0, v = v0, t = 0.0;  // x: overlap, v: closing rate
  double a = -Law::normal_force(law, m_eff, x, v) / m_eff;
  do {
    v += 0.5 * dt * a;
    x += dt * v;
    t += dt;
    a = -Law::normal_force(law, m_eff, x, v) / m_eff;
    v += 0.5 * dt * a;
  } while (x > 0.0);
  return {t, -v / v0};
}

TEST(LinearSpringDashpot, BinaryCollisionGivesTheRestitutionAndContactTimeAskedFor) {
  // Kn 1e3 N/m, m_eff 1e-5 kg (two 2.1 mm glass beads): omega0 = 1e4 rad/s.
  const double kn = 1e3, m_eff = 1e-5, omega0 = std::sqrt(kn / m_eff);
  for (const double e : {0.3, 0.7, 0.95, 1.0}) {
    SCOPED_TRACE(e);
    LinearSpringDashpot law;
    law.stiffness = kn;
    law.damping_ratio = damping_ratio_from_restitution(e);
    // Closed form, the free damped oscillator m x'' + Cn x' + Kn x = 0 from
    // x = 0, x' = v0: x is back to 0 after half a damped period,
    // t_c = pi / (omega0 sqrt(1 - zeta^2)), with x' = -v0 exp(-pi zeta / sqrt(1 - zeta^2)) = -e v0.
    const double zeta = law.damping_ratio;
    const double t_c = pi / (omega0 * std::sqrt(1.0 - zeta * zeta));
    // 2e4 steps a contact: the end is found to within one step, so t_c to
    // dt, and e to the velocity the dashpot changes over one step at the
    // end, 2 zeta omega0 dt e <= 2 x 0.36 x pi / 2e4 = 1.1e-4 (Verlet's own
    // error, O((omega0 dt)^2) = 2.5e-8, is below it).
    const double dt = (pi / omega0) / 2e4;
    const Collision c = collide<LinearSpringDashpotForce<true>>(law, m_eff, 0.1, dt);
    EXPECT_NEAR(c.contact_time_s, t_c, 1.01 * dt);
    EXPECT_NEAR(c.restitution, e, 2e-4);
    // The same law with that Cn given as contact.cn: the same collision to the bit.
    LinearSpringDashpot given = law;
    given.damping = LinearSpringDashpotForce<true>::damping(law, m_eff);
    const Collision g = collide<LinearSpringDashpotForce<false>>(given, m_eff, 0.1, dt);
    EXPECT_EQ(g.contact_time_s, c.contact_time_s);
    EXPECT_EQ(g.restitution, c.restitution);
  }
}

}  // namespace
}  // namespace fdem

// Unit tests of the stability analysis and the refusal of an unstable step.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "scene/stability.hpp"
#include "scene/tests/paper_channel_contact.hpp"

namespace fdem {
namespace {

using scene_test::paper_channel_contact;

TEST(Stability, ChannelPairContactTimeMatchesHandValue) {
  const MassRange r = mass_range(0.2e-3, 0.3e-3, 2170.0);
  const StabilityReport rep = analyse_stability(paper_channel_contact(), Effects{}, r, 1e-5, true);
  const ContactTimescale& c = rep.contacts[0];
  // t_c0 = pi sqrt(m/2 / Kn), m = 2170 pi/6 (2e-4)^3 = 9.09e-9 kg -> 6.70e-7 s (anchors/results.md).
  EXPECT_NEAR(c.contact_time_undamped_s, 6.70e-7, 0.005e-7);
  EXPECT_NEAR(c.damping_ratio, 0.61, 0.005);
  EXPECT_NEAR(rep.dem_step_s / c.contact_time_undamped_s, 14.9, 0.05);
  EXPECT_EQ(rep.contacts[rep.binding].label, "smallest pair");
  EXPECT_FALSE(rep.stable());
}

TEST(Stability, PaperChannelStepIsRefusedNamingKeyValueAndBound) {
  const MassRange r = mass_range(0.2e-3, 0.3e-3, 2170.0);
  const StabilityReport rep = analyse_stability(paper_channel_contact(), Effects{}, r, 1e-5, true);
  try {
    require_stable_step(rep, paper_channel_contact(), "channel.yaml");
    FAIL() << "dt = 15 t_c must be refused";
  } catch (const InputError& e) {
    scene_test::expect_paper_channel_step_refused(e);
  }
}

TEST(Stability, AllowUnstableStepRunsAnyway) {
  ContactSpec c = paper_channel_contact();
  c.allow_unstable_step = true;
  const StabilityReport rep = analyse_stability(c, Effects{}, mass_range(0.2e-3, 0.3e-3, 2170.0), 1e-5, true);
  EXPECT_NO_THROW(require_stable_step(rep, c, "channel.yaml"));
}

TEST(Stability, SettledBedStepIsAccepted) {
  const StabilityReport rep =
      analyse_stability(paper_channel_contact(), Effects{}, mass_range(0.2e-3, 0.3e-3, 2170.0), 1e-7, true);
  EXPECT_TRUE(rep.stable()) << rep.table();
  EXPECT_NO_THROW(require_stable_step(rep, paper_channel_contact(), "b.yaml"));
}

TEST(Stability, DampingLimitBindsForHeavilyDampedContact) {
  ContactSpec c;
  c.normal_stiffness = 1.0;
  c.normal_damping = 1.0;  // m = 1e-3: C dt / m limit 1e-3 s << spring limit sqrt(1e-3/2)
  const StabilityReport rep = analyse_stability(c, Effects{}, {1e-3, 1e-3, 1e-3, 1e-3}, 1e-4, false);
  EXPECT_NEAR(rep.stable_step_s(), 0.5 * 2.0 * 0.5e-3 / 1.0, 1e-15);
  EXPECT_GT(rep.contacts[0].damping_ratio, 1.0);
  EXPECT_EQ(rep.contacts[0].restitution, 0.0);
  EXPECT_TRUE(std::isinf(rep.contacts[0].contact_time_s));
}

TEST(Stability, WallContactUsesParticleMass) {
  const StabilityReport rep =
      analyse_stability(paper_channel_contact(), Effects{}, mass_range(0.2e-3, 0.3e-3, 2170.0), 1e-7, true);
  ASSERT_EQ(rep.contacts.size(), 5u);
  EXPECT_NEAR(rep.contacts[3].effective_mass_kg, 2170.0 * sphere_volume(0.2e-3), 1e-20);
  // 0.2 mm on a wall: t_c0 = 9.47e-7 s (anchors/results.md).
  EXPECT_NEAR(rep.contacts[3].contact_time_undamped_s, 9.47e-7, 0.005e-7);
}

}  // namespace
}  // namespace fdem

// The time-step rules (scene/time_steps.hpp): what is derived, exactly, and
// which key each broken rule names.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"
#include "scene/stability.hpp"
#include "scene/time_steps.hpp"

namespace fdem {
namespace {

struct Refusal {
  std::string key, reason;
};

[[noreturn]] void throw_refusal(const std::string& key, const std::string& reason) { throw Refusal{key, reason}; }

Scene water_scene_with_a_grain(double fluid_step, double dem_step, int subcycles) {
  Scene s;
  s.domain.upper = Vec3(0.01, 0.01, 0.01);
  ParticleSet grain;
  grain.size.diameter = 0.2e-3;
  s.particles.push_back(grain);
  // Kn 20 N/m: the pair's spring bound sqrt(m_eff / Kn) = 1.7e-5 s (m_eff = 5.5e-9 kg), so 1e-5 s is stable.
  s.contact.normal_stiffness = 20.0;
  s.contact.restitution = 0.5;
  s.time = TimeSpec{fluid_step, dem_step, 0.1, subcycles};
  return s;
}

const MassRange kGrains = mass_range(0.2e-3, 0.2e-3, 2650.0);

// The key a scene's time steps are refused with ("" when accepted).
std::string refused_key(const Scene& s, const std::optional<MassRange>& masses = kGrains) {
  try {
    resolve_time_steps(s, masses, throw_refusal);
  } catch (const Refusal& r) {
    return r.key;
  }
  return "";
}

TEST(TimeSteps, SubcyclesFromTheStepRatioAndTheDemStepFromSubcycles) {
  const TimeSpec a = resolve_time_steps(water_scene_with_a_grain(0.01, 1e-5, 0), kGrains, throw_refusal);
  EXPECT_EQ(a.subcycles, 1000);
  EXPECT_EQ(a.dem_step, 1e-5);  // as given
  const TimeSpec b = resolve_time_steps(water_scene_with_a_grain(0.01, 0.0, 2000), kGrains, throw_refusal);
  EXPECT_EQ(b.subcycles, 2000);
  EXPECT_EQ(b.dem_step, 0.01 / 2000);
}

TEST(TimeSteps, NeitherGivenTakesTheLargestStableStepThatDividesTheFluidStep) {
  const Scene s = water_scene_with_a_grain(0.01, 0.0, 0);
  const TimeSpec t = resolve_time_steps(s, kGrains, throw_refusal);
  const double stable = analyse_stability(s.contact, s.effects, kGrains, t.dem_step, true).stable_step_s();
  EXPECT_EQ(t.dem_step, 0.01 / t.subcycles);
  EXPECT_LE(t.dem_step, stable);
  EXPECT_GT(0.01 / (t.subcycles - 1), stable);  // one subcycle fewer would be unstable
  EXPECT_EQ(refused_key(s, std::nullopt), "dem_step");  // without the particles' masses it cannot be chosen
}

TEST(TimeSteps, DrySceneStepsSubcyclesDemStepsPerStep) {
  Scene s = water_scene_with_a_grain(0.0, 1e-6, 10);
  s.effects.fluid = false;
  const TimeSpec t = resolve_time_steps(s, kGrains, throw_refusal);
  EXPECT_DOUBLE_EQ(t.fluid_step, 1e-5);
  EXPECT_EQ(t.subcycles, 10);
}

TEST(TimeSteps, EachBrokenRuleNamesItsKey) {
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.01, 1e-5, 50)), "subcycles");  // 50 x 1e-5 != 0.01
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.01, 3e-3, 0)), "dem_step");    // 3.33 subcycles
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.01, 0.02, 0)), "dem_step");    // above the fluid step
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.0, 1e-5, 0)), "fluid_step");
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.01, -1e-5, 0)), "dem_step");
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.01, 1e-5, -1)), "subcycles");
  EXPECT_EQ(refused_key(water_scene_with_a_grain(0.01, 1e-5, 0)), "");
}

TEST(TimeSteps, AStepAboveTheStabilityBoundIsRefusedUnlessAllowed) {
  // Kn 1e3 N/m: the pair's spring bound sqrt(m_eff / Kn) = 2.4e-6 s, so 1e-5 s is unstable.
  Scene s = water_scene_with_a_grain(0.01, 1e-5, 0);
  const MassRange grains = kGrains;
  s.contact.normal_stiffness = 1e3;
  EXPECT_THROW(resolve_time_steps(s, grains, throw_refusal), InputError);
  s.contact.allow_unstable_step = true;
  EXPECT_NO_THROW(resolve_time_steps(s, grains, throw_refusal));
  s.contact.allow_unstable_step = false;
  EXPECT_NO_THROW(resolve_time_steps(s, std::nullopt, throw_refusal));  // masses unknown: the bound is Simulation's
}

TEST(TimeSteps, ASceneFileIsResolvedOnceByTheLoader) {
  // The settling study's scene: the loader derives 1000 subcycles; what
  // Simulation does with it, given its grain's mass, changes nothing.
  const Scene s = load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml");
  EXPECT_EQ(s.time.subcycles, 1000);
  const TimeSpec again = resolve_time_steps(s, mass_range(generate_particles(s)), throw_refusal);
  EXPECT_EQ(again.fluid_step, s.time.fluid_step);
  EXPECT_EQ(again.dem_step, s.time.dem_step);
  EXPECT_EQ(again.subcycles, s.time.subcycles);
}

}  // namespace
}  // namespace fdem

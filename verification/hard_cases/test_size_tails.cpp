// Hard case: the tails of a normal size distribution (salt plume, Sect. 4.4:
// mean 309 um, sd 114 um, Kn 100 N/m, Cn 8.5e-4 N s/m, DEM step 1e-5 s).
// Small grains have contact and dashpot times below the DEM step: the run is
// refused before the first step naming the smallest grain and the bound, and
// taking the advised step makes it run. A distribution that could produce a
// diameter <= 0 is refused by the scene loader.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "core/error.hpp"
#include "coupling/simulation.hpp"
#include "dem/dem_engine.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"
#include "scene/stability.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

using hard::contains;

// The plume's grains and contact in a small column; `min` is the lower
// truncation bound of the normal distribution [m].
std::string plume_yaml(const std::string& min, const std::string& dem_step = "1.0e-5",
                       const std::string& fluid_step = "1.0e-3") {
  return fmt::format(R"(title: plume size tails (hard case)
effects: {{fluid: true, coupling: two_way}}
domain: {{lower: [0, 0, 0], upper: [0.02, 0.02, 0.04]}}
mesh: {{cells: [2, 2, 4]}}
fluid: {{density: 1000, viscosity: 1.0e-3}}
particles:
  - name: salt
    placement: lattice
    region: {{lower: [0.005, 0.005, 0.02], upper: [0.015, 0.015, 0.03]}}
    lattice: [10, 10, 10]
    size: {{distribution: normal, mean: 309.0e-6, sd: 114.0e-6, min: {}, max: 600.0e-6}}
    density: 2170
    seed: 20240601
contact: {{kn: 100, cn: 8.5e-4}}
time: {{fluid_step: {}, dem_step: {}, end: {}}}
output: {{directory: out}}
)",
                     min, fluid_step, dem_step, fluid_step);
}

TEST(SizeTails, TinyGrainsBelowTheDemStepAreRefusedNamingTheSmallestGrain) {
  // Shows: 1000 plume grains (tail down to 50 um) at dt 1e-5 s are refused; the message names the smallest grain's d.
  const Scene scene = load_scene_from_string(plume_yaml("50.0e-6"), "plume_tails.yaml");
  const Particles grains = generate_particles(scene);
  const MassRange range = mass_range(grains);
  // The sample reaches into the tail: at least one grain under 120 um (P = 4.5 % per grain).
  ASSERT_LT(range.small_diameter_m, 120e-6);
  const StabilityReport report =
      analyse_stability(scene.contact, scene.effects, range, scene.time.dem_step, scene.effects.walls);
  ASSERT_FALSE(report.stable());
  try {
    Simulation sim(scene);
    FAIL() << "grains whose dashpot time is below the DEM step must be refused";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.key(), "time.dem_step");
    EXPECT_TRUE(contains(what, "smallest")) << what;
    EXPECT_TRUE(contains(what, fmt::format("{:.3g}", range.small_diameter_m))) << "the grain's diameter: " << what;
    EXPECT_TRUE(contains(what, fmt::format("at most {:.3g} s", report.stable_step_s()))) << what;
  }
}

TEST(SizeTails, TheAdvisedStepMakesTheSameGrainsRunFiniteWithSmallOverlap) {
  // Shows: the step the refusal advises (<= bound, dividing the fluid step) runs the same tail grains finite.
  const Scene refused = load_scene_from_string(plume_yaml("50.0e-6"), "plume_tails.yaml");
  const StabilityReport report = analyse_stability(refused.contact, refused.effects,
                                                   mass_range(generate_particles(refused)), 1e-5, true);
  const double fluid_step = 1.0e-4;
  const double subcycles = std::ceil(fluid_step / report.stable_step_s());
  const Scene scene = load_scene_from_string(
      plume_yaml("50.0e-6", fmt::format("{:.17g}", fluid_step / subcycles), fmt::format("{:.17g}", fluid_step)),
      "plume_tails.yaml");
  Simulation sim(scene);
  sim.step();
  const CouplingDiagnostics d = sim.diagnostics();
  EXPECT_TRUE(std::isfinite(d.dem.kinetic_energy_j));
  EXPECT_EQ(d.dem.particles_removed, 0u);
  // Grains start 1 mm apart at rest and fall 0.1 ms: no contact can have formed.
  EXPECT_EQ(d.dem.max_overlap_over_diameter, 0.0);
  for (double v : sim.particles().vz) EXPECT_LT(std::abs(v), 9.81 * fluid_step * 1.0001);  // at most free fall
}

TEST(SizeTails, FdemRunRefusesTheTailWithExitCode2) {
  // Shows: the command line turns the refusal into exit code 2 with the bound, before any output.
  const auto dir = hard::scratch_dir("size_tails");
  hard::write_text(dir / "plume.yaml", plume_yaml("50.0e-6"));
  hard::FdemProcess run({"run", (dir / "plume.yaml").string(), "-o", (dir / "out").string(), "-q", "-t", "1"}, dir);
  EXPECT_EQ(run.wait(), 2);
  const std::string err = run.stderr_text();
  EXPECT_TRUE(contains(err, "time.dem_step")) << err;
  EXPECT_TRUE(contains(err, "smallest")) << err;
  EXPECT_FALSE(hard::fs::exists(dir / "out" / "probes.csv"));
}

TEST(SizeTails, NormalDistributionWithoutAPositiveLowerBoundIsRefusedByTheLoader) {
  // Shows: min <= 0 or a missing min (mean - 2.7 sd < 0 is possible) is refused, key size.min, with the reason.
  for (const std::string min : {"0", "-1.0e-6"}) {
    try {
      load_scene_from_string(plume_yaml(min), "plume_tails.yaml");
      FAIL() << "min = " << min << " allows diameters <= 0";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "particles[0].size.min") << e.what();
      EXPECT_TRUE(contains(e.what(), "> 0")) << e.what();
    }
  }
  std::string no_min = plume_yaml("50.0e-6");
  no_min.replace(no_min.find(" min: 50.0e-6,"), std::string(" min: 50.0e-6,").size(), "");
  try {
    load_scene_from_string(no_min, "plume_tails.yaml");
    FAIL() << "a normal distribution without a lower bound can draw diameters <= 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "particles[0].size.min") << e.what();
  }
}

TEST(SizeTails, FixedAndUniformNonPositiveDiametersAreRefused) {
  // Shows: size 0, size -1e-4 and uniform min 0 are refused by the loader with the key named.
  const std::string base = plume_yaml("50.0e-6");
  const std::string normal = "{distribution: normal, mean: 309.0e-6, sd: 114.0e-6, min: 50.0e-6, max: 600.0e-6}";
  const std::pair<std::string, std::string> cases[] = {
      {"0", "particles[0].size"},
      {"-1.0e-4", "particles[0].size"},
      {"{distribution: uniform, min: 0, max: 3.0e-4}", "particles[0].size.min"},
      {"{distribution: fixed, diameter: 0}", "particles[0].size.diameter"}};
  for (const auto& [size, key] : cases) {
    std::string text = base;
    text.replace(text.find(normal), normal.size(), size);
    try {
      load_scene_from_string(text, "plume_tails.yaml");
      FAIL() << "size " << size << " must be refused";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  }
}

TEST(SizeTails, TruncatedNormalDrawsStayInsideTheirBoundsFarInTheTail) {
  // Shows: 1e5 draws with the plume's mean/sd truncated at [1 um, 600 um] are all in bounds, hence > 0.
  SizeDistribution size;
  size.kind = SizeKind::normal;
  size.mean = 309e-6;
  size.sd = 114e-6;
  size.minimum = 1e-6;
  size.maximum = 600e-6;
  std::mt19937_64 rng(7);
  double smallest = 1.0;
  for (int i = 0; i < 100000; ++i) {
    const double d = draw_diameter(size, rng);
    ASSERT_GE(d, size.minimum);
    ASSERT_LE(d, size.maximum);
    smallest = std::min(smallest, d);
  }
  // 0.4 % of the untruncated normal lies below 0 (mean / sd = 2.7): the tail was sampled.
  EXPECT_LT(smallest, 30e-6);
}

TEST(SizeTails, EngineRefusesNonPositiveDiametersGivenInCode) {
  // Shows: particles built in code with d = 0 or d < 0 are refused by the DEM engine (InputError "particles").
  Scene s;
  s.source_file = "hard_cases/in_code";
  s.domain.upper = Vec3::Constant(0.01);
  s.effects.fluid = false;
  s.effects.buoyancy = false;
  s.contact.normal_stiffness = 100.0;
  s.time.dem_step = 1e-6;
  for (double d : {0.0, -1e-4}) {
    Particles p;
    p.add(0.005, 0.005, 0.005, 1e-4, 2170.0);
    p.add(0.007, 0.005, 0.005, d, 2170.0);
    try {
      DemEngine dem(p, s);
      FAIL() << "d = " << d << " must be refused";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "particles") << e.what();
    }
  }
}

}  // namespace
}  // namespace fdem

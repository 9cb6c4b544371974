// Hard case: the paper's channel-flow contact (Kn 1e5 N/m, Cn 0.026 N s/m,
// d 0.2-0.3 mm, rho 2170) at its DEM step 1e-5 s, 15 contact times of a
// 0.2 mm pair. No explicit DEM can take that step: it is refused before the
// first step with the stable bound in the message; run anyway on request
// (contact.allow_unstable_step), the blow-up must be detected and stop the run
// with a SolverError naming the step, the particle and the quantity, keeping
// the output written before it.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "coupling/simulation.hpp"
#include "hard_scenes.hpp"
#include "scene/particle_generator.hpp"
#include "scene/stability.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

using hard::contains;

// The stable bound the solver must quote, from the grains actually generated.
double expected_bound(const Scene& s) {
  const Particles p = generate_particles(s);
  return analyse_stability(s.contact, s.effects, mass_range(p), s.time.dem_step, s.effects.walls).stable_step_s();
}

TEST(ChannelContact, PaperStepIsRefusedBeforeTheFirstStepWithTheStableBound) {
  // Shows: dt = 15 t_c is refused at construction (no step taken), key time.dem_step, bound quoted.
  const Scene s = hard::paper_channel_contact_bed();
  const double bound = expected_bound(s);
  // The dashpot limit 0.5 * 2 m_eff / Cn binds: 1.75e-7 s for two 0.2 mm grains, 5.9e-7 s for two
  // 0.3 mm grains (m_eff ~ d^3); the smallest drawn grain sets it in between.
  EXPECT_GE(bound, 1.749e-7);
  EXPECT_LE(bound, 5.9e-7);
  try {
    Simulation sim(s);
    FAIL() << "a DEM step 57 times the stable bound must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "time.dem_step");
    const std::string what = e.what();
    EXPECT_TRUE(contains(what, fmt::format("stable bound {:.3g} s", bound))) << what;
    EXPECT_TRUE(contains(what, "allow_unstable_step")) << "the message must say how to run anyway: " << what;
  }
}

TEST(ChannelContact, StableStepOfTheSameBedRunsWithSmallOverlap) {
  // Shows: the same bed at the advised step runs 2000 steps finite, overlap < 2 % d (no false alarm).
  Scene s = hard::paper_channel_contact_bed();
  s.time.dem_step = expected_bound(s);
  Simulation sim(s);
  for (int k = 0; k < 2000; ++k) sim.step();
  const CouplingDiagnostics d = sim.diagnostics();
  // Falling at 5 cm/s onto the floor: overlap v sqrt(m/Kn) = 0.05 * sqrt(9.1e-9 / 1e5) = 1.5e-5 mm,
  // 0.01 % of d; 2 % leaves room for the lattice's touching pairs loaded by the layers above.
  EXPECT_LT(d.dem.max_overlap_over_diameter, 0.02);
  EXPECT_EQ(d.dem.particles_removed, 0u);
  EXPECT_TRUE(std::isfinite(d.dem.kinetic_energy_j));
  // Kinetic energy cannot exceed the initial 1/2 m v^2 plus the potential energy released
  // over 2000 steps (0.05 m/s + g t for t = 3.5e-4 s: v < 0.054 m/s for every grain).
  double bound_j = 0.0;
  for (double m : sim.particles().mass) bound_j += 0.5 * m * 0.054 * 0.054;
  EXPECT_LE(d.dem.kinetic_energy_j, bound_j);
}

TEST(ChannelContact, RunAnywayStopsWithSolverErrorNamingStepParticleAndQuantity) {
  // Shows: allow_unstable_step runs, and the blow-up (15 t_c per step) stops the run with a
  // SolverError naming step, particle and quantity, before any grain escapes the walled box.
  Scene s = hard::paper_channel_contact_bed();
  s.contact.allow_unstable_step = true;
  Simulation sim(s);
  std::string message;
  long failed_at = -1;
  try {
    // With omega0 dt = 15 pi the spring amplifies an overlap ~ (omega0 dt)^2 = 2200 times per
    // step: a 1 nm overlap reaches the diameter in 3 steps. 200 steps is far beyond that.
    for (int k = 0; k < 200; ++k) {
      sim.step();
      failed_at = sim.step_index();
    }
  } catch (const SolverError& e) {
    message = e.what();
  }
  ASSERT_FALSE(message.empty()) << "200 steps at 15 t_c ran without a SolverError; removed grains: "
                                << sim.diagnostics().dem.particles_removed
                                << ", kinetic energy: " << sim.diagnostics().dem.kinetic_energy_j << " J";
  EXPECT_TRUE(contains(message, "step")) << message;
  EXPECT_TRUE(contains(message, "particle")) << message;
  EXPECT_TRUE(contains(message, "overlap") || contains(message, "energy") || contains(message, "non-finite") ||
              contains(message, "NaN"))
      << "the message must name the quantity that failed: " << message;
  EXPECT_LT(failed_at, 200);
  // With the six walls on, a grain can leave the box only by blowing up: none may be
  // removed silently before the detector fires.
  EXPECT_EQ(sim.diagnostics().dem.particles_removed, 0u) << message;
}

std::string channel_yaml(bool allow_unstable) {
  return fmt::format(R"(title: paper channel contact at its DEM step (hard case)
effects: {{fluid: true, coupling: two_way}}
domain: {{lower: [0, 0, 0], upper: [0.003, 0.0018, 0.003]}}
mesh: {{cells: [5, 3, 5]}}
fluid:
  density: 1000
  viscosity: 1.0e-3
  boundaries:
    x_min: {{type: inlet, velocity: [0.03, 0, 0], above: 0.0015}}
    x_max: outlet
    y_min: free_slip
    y_max: free_slip
    z_min: no_slip
    z_max: free_slip
particles:
  - name: bed
    placement: lattice
    region: {{lower: [0, 0, 0], upper: [0.003, 0.0018, 0.0015]}}
    lattice: [10, 6, 5]
    size: {{distribution: uniform, min: 0.2e-3, max: 0.3e-3}}
    density: 2170
    seed: 20240602
contact: {{kn: 1.0e5, cn: 0.026, allow_unstable_step: {}}}
time: {{fluid_step: 5.0e-3, dem_step: 1.0e-5, end: 0.05}}
coupling: {{porosity: centre, porosity_floor: 0.1}}
output: {{directory: out, csv_interval: 0}}
)",
                     allow_unstable ? "true" : "false");
}

TEST(ChannelContact, FdemRunRefusesWithExitCode2AndWritesNothing) {
  // Shows: `fdem run` on the paper's channel contact exits 2 with key, bound and remedy, no output.
  const auto dir = hard::scratch_dir("channel_refused");
  hard::write_text(dir / "scene.yaml", channel_yaml(false));
  hard::FdemProcess run({"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q", "-t", "1"}, dir);
  EXPECT_EQ(run.wait(), 2);
  const std::string err = run.stderr_text();
  EXPECT_TRUE(contains(err, "time.dem_step")) << err;
  EXPECT_TRUE(contains(err, "stable bound")) << err;
  EXPECT_TRUE(contains(err, "allow_unstable_step")) << err;
  EXPECT_FALSE(hard::fs::exists(dir / "out" / "probes.csv")) << "refused before the first step: no output";
}

TEST(ChannelContact, FdemRunAnywayExitsWithSolverFailureAndKeepsValidOutput) {
  // Shows: run anyway, `fdem run` exits 3 naming step and particle; probes.csv stays valid and finite.
  const auto dir = hard::scratch_dir("channel_run_anyway");
  hard::write_text(dir / "scene.yaml", channel_yaml(true));
  hard::FdemProcess run({"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q", "-t", "1"}, dir);
  const int code = run.wait();
  const std::string err = run.stderr_text();
  EXPECT_EQ(code, 3) << err;
  // The failure line itself must name the DEM blow-up (a fluid solve that diverges later,
  // driven by grains at hundreds of m/s, is the symptom, not the diagnosis).
  const std::size_t at = err.find("solver failure");
  ASSERT_NE(at, std::string::npos) << err;
  const std::string failure = err.substr(at);
  EXPECT_TRUE(contains(failure, "particle")) << failure;
  EXPECT_TRUE(contains(failure, "overlap") || contains(failure, "energy") || contains(failure, "non-finite"))
      << failure;
  ASSERT_TRUE(hard::fs::exists(dir / "out" / "probes.csv")) << "the output written before the failure is kept";
  const hard::Csv csv = hard::read_csv(dir / "out" / "probes.csv");
  EXPECT_TRUE(csv.well_formed);
  ASSERT_GE(csv.rows.size(), 1u) << "at least the initial state";
  const int count = csv.column("count");
  for (const auto& row : csv.rows) {
    for (double v : row) EXPECT_TRUE(std::isfinite(v)) << "the kept output is the last good state";
    if (count >= 0) {
      EXPECT_EQ(row[static_cast<std::size_t>(count)], 300.0) << "no grain lost silently in the kept output";
    }
  }
}

}  // namespace
}  // namespace fdem

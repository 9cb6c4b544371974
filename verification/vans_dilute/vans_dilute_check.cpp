// The dilute limit of the volume-averaged equations (paper Eq. 18-19): a
// single grain settling in a closed box (verification/settling/settling.yaml,
// d = 0.76 mm, the largest two-way effect of Table 1) with fluid.model
// vans_a and vans_b against the simplified model (Eq. 21-22). Where the grain
// is, eps = 1 - V_p / V_e = 0.989 (centre scheme; the grain falls through the
// central tetrahedra of 4 mm cells), elsewhere 1: the volume-averaged terms are O(1 - eps) locally
// and the fluid's effect on the grain is itself 0.18 % of its terminal
// velocity (verification/settling), so the models must agree to well
// within 0.1 %; model B's grain feels f_d / eps (Zhou et al. 2010, model B),
// 1.1 % more than the simplified model's here, and is held to that shifted
// limit instead (test body). Source forms: the simplified model uses the
// paper's -F / eps (Eq. 22); the volume-averaged models take exactly minus the
// grains' force (coupling/source_term.hpp).
// The d(eps)/dt switch (fluid.porosity_time_derivative) is measured here
// too: with the centre scheme the porosity of the element the grain leaves
// jumps from 0.989 to 1 and that of the one it enters back, a mass sink and
// source of the grain's volume in one step (V_p / dt).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <omp.h>

#include "coupling/drag.hpp"
#include "coupling/simulation.hpp"
#include "scene/scene_loader.hpp"
#include "../support/study_results.hpp"

namespace fdem {
namespace {

[[maybe_unused]] const ::testing::Environment* const kResults =
    fdem::verification::register_study_results("vans_dilute");
using fdem::verification::record_value;

constexpr double stop_height_m = 0.012;  // verification/settling: 3 cells above the floor

struct Settled {
  double terminal = 0.0;  // settling speed at the last sample [m/s]
  double porosity = 1.0;  // of the grain's element at the end
  double max_fluid_speed = 0.0;
  double wall_s = 0.0;
};

Settled settle(FluidModel model, SourceForm source, bool rate_term) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene scene = load_scene(FDEM_SOURCE_DIR "/verification/settling/settling.yaml");
  scene.particles.at(0).size.diameter = 0.76e-3;
  scene.fluid.model = model;
  scene.fluid.porosity_time_derivative = rate_term;
  scene.coupling.source_form = source;
  // 0.3 s: about 15 response times of the 0.76 mm grain (v_t / g' = 0.118 /
  // 6.1 = 0.019 s), a third of the settling study's run; all models compared
  // at the same time.
  scene.time.end_time = 0.3;
  Simulation sim(scene);
  while (!sim.finished() && sim.particles().z[0] > stop_height_m) sim.step();
  Settled s;
  s.terminal = -sim.particles().vz[0];
  s.porosity = sim.porosity()[static_cast<std::size_t>(sim.particle_elements()[0])];
  const auto u = sim.fluid_velocity();
  for (std::size_t i = 0; i < u.size() / 3; ++i)
    s.max_fluid_speed = std::max(s.max_fluid_speed, std::hypot(u[3 * i], u[3 * i + 1], u[3 * i + 2]));
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

// Model B's grain feels f_d / eps (Zhou et al. 2010; coupling/drag_coupling.hpp),
// where the simplified model's feels f_d: with the same weight its terminal
// speed v_B solves K(eps, v_B) v_B = eps K(eps, v_s) v_s, v_s the simplified
// model's measured one. f = K(eps, v) v grows with v: bisection.
double model_b_terminal(double simplified_terminal, double eps) {
  const Scene scene = load_scene(FDEM_SOURCE_DIR "/verification/settling/settling.yaml");
  const DragLawEntry& law = drag_law(scene.effects.drag);
  const FluidProperties fluid{scene.fluid.density, scene.fluid.viscosity};
  const double d = 0.76e-3;
  auto force = [&](double v) { return force_coefficient(law, eps, v, d, fluid) * v; };
  const double target = eps * force(simplified_terminal);
  double lo = 0.0, hi = simplified_terminal;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (force(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST(VansDilute, SingleGrainSettlesWithinOnePerMilleOfTheSimplifiedModel) {
  omp_set_num_threads(1);  // one grain: an OpenMP team per DEM step costs more than the step
  const Settled simplified = settle(FluidModel::simplified, SourceForm::paper, false);
  fmt::print("simplified (paper source): terminal {:.6f} m/s, max fluid speed {:.3e} m/s, wall {:.1f} s\n",
             simplified.terminal, simplified.max_fluid_speed, simplified.wall_s);
  struct Case {
    const char* name;
    FluidModel model;
    SourceForm source;
    bool rate;
  };
  for (const Case& c : {Case{"vans_a", FluidModel::vans_a, SourceForm::conservative, false},
                        Case{"vans_b", FluidModel::vans_b, SourceForm::conservative, false},
                        Case{"vans_a_rate", FluidModel::vans_a, SourceForm::conservative, true}}) {
    const Settled s = settle(c.model, c.source, c.rate);
    const double deviation = s.terminal / simplified.terminal - 1.0;
    fmt::print("{}: terminal {:.6f} m/s ({:+.4f} % of the simplified model's), max fluid speed {:.3e} m/s, wall {:.1f} s\n",
               c.name, s.terminal, 100.0 * deviation, s.max_fluid_speed, s.wall_s);
    record_value(fmt::format("vans_dilute.{}.terminal_deviation", c.name), deviation);
    if (c.model != FluidModel::vans_b) {
      EXPECT_LT(std::abs(deviation), 1e-3) << c.name;  // the project's 0.1 %
      continue;
    }
    // Model B's 1/eps folds in the pressure gradient of a uniform bed
    // (eps grad p = -n f_d), which one grain in still fluid does not raise: its
    // drag is 1/eps = 1 + V_p / V_e above the simplified model's, a real
    // departure of the model at this cell size. Gated against its own dilute
    // limit, the simplified run with the 1/eps, to the project's 0.1 %.
    const double predicted = model_b_terminal(simplified.terminal, s.porosity) / simplified.terminal - 1.0;
    fmt::print("vans_b: grain's element porosity {:.5f}, predicted {:+.4f} % from the 1/eps\n", s.porosity,
               100.0 * predicted);
    record_value("vans_dilute.vans_b.predicted_deviation", predicted);
    record_value("vans_dilute.vans_b.deviation_from_closed_form", deviation - predicted);
    EXPECT_LT(std::abs(deviation - predicted), 1e-3) << c.name;
  }
}

}  // namespace fdem

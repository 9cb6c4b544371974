// Hard case: a dense packing on a mesh finer than the grains (cell / d = 1.09,
// below the paper's own advice of 5 and the channel flow's 2.4). Each grain's
// centre lies in a central tetrahedron (h^3 / 3) smaller than the grain, so
// Eq. 32 gives porosity 1 - V_p / V_e = -0.21 there. The floor must hold, drag
// must stay finite and bounded, and the count of floored elements is reported
// (Simulation::diagnostics and the `fdem run` probes CSV).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "coupling/drag.hpp"
#include "coupling/simulation.hpp"
#include "scene/scene_loader.hpp"
#include "hard_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

constexpr double kCell = 1.2e-3;      // cell size h [m]
constexpr double kDiameter = 1.1e-3;  // grain diameter [m]: cell / d = 1.09
constexpr double kInlet = 0.05;       // inlet speed [m/s]
constexpr int kGrains = 32;           // 4 x 4 x 2 lattice, one grain per cell centre

// 4 x 4 x 4 cells of 1.2 mm; the lower two layers hold one 1.1 mm grain at each
// cell centre; water enters at x_min at 5 cm/s and leaves at x_max.
const std::string kDenseScene = R"(title: dense packing, cell / d = 1.09 (hard case)
effects: {fluid: true, coupling: two_way}
domain: {lower: [0, 0, 0], upper: [0.0048, 0.0048, 0.0048]}
mesh: {cells: [4, 4, 4]}
)" + hard::water_along_x_yaml("0.05") + R"(particles:
  - name: packing
    placement: lattice
    region: {lower: [0, 0, 0], upper: [0.0048, 0.0048, 0.0024]}
    lattice: [4, 4, 2]
    size: 1.1e-3
    density: 2650
contact: {kn: 100, restitution: 0.5}
time: {fluid_step: 1.0e-3, dem_step: 1.0e-5, end: 0.01}
coupling: {porosity: centre, porosity_floor: 0.1, source_form: paper}
output: {directory: out, csv_interval: 0}
)";

double max_norm3(std::span<const double> v) {
  double m = 0.0;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) m = std::max(m, std::hypot(v[i], v[i + 1], v[i + 2]));
  return m;
}

double max_particle_speed(const Particles& p) {
  double m = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) m = std::max(m, std::hypot(p.vx[i], p.vy[i], p.vz[i]));
  return m;
}

TEST(DensePacking, CentreSchemeGoesNegativeAndEveryGrainElementIsFloored) {
  // Shows: Eq. 32 gives 1 - V_p/(h^3/3) = -0.21 in all 32 grain-holding central tets; all 32 are floored at 0.1.
  const Scene scene = load_scene_from_string(kDenseScene, "dense.yaml");
  const Simulation sim(scene);
  const CouplingDiagnostics d = sim.diagnostics();
  const double expected_min = 1.0 - sphere_volume(kDiameter) / (kCell * kCell * kCell / 3.0);
  EXPECT_NEAR(d.min_porosity, expected_min, 1e-12);  // closed form; round-off only
  EXPECT_LT(d.min_porosity, 0.0);
  EXPECT_EQ(d.floored_elements, kGrains);
  long at_floor = 0;
  for (double eps : sim.porosity()) {
    EXPECT_GE(eps, 0.1);
    EXPECT_LE(eps, 1.0);
    at_floor += eps == 0.1 ? 1 : 0;
  }
  EXPECT_EQ(at_floor, kGrains);
}

TEST(DensePacking, FloorHoldsAndDragStaysFiniteAndBoundedOverTenSteps) {
  // Shows: 10 coupled steps keep porosity in [0.1, 1], drag finite and below the floor's Ergun bound, flow < 10 U.
  const Scene scene = load_scene_from_string(kDenseScene, "dense.yaml");
  Simulation sim(scene);
  const FluidProperties water{1000.0, 1.0e-3};
  long floored_sum = sim.diagnostics().floored_element_updates;
  double u_peak = 0.0, v_peak = 0.0, drag_peak = 0.0, drag_bound = 0.0;
  while (!sim.finished()) {
    sim.step();
    const CouplingDiagnostics d = sim.diagnostics();
    floored_sum += d.floored_elements;
    for (double eps : sim.porosity()) {
      ASSERT_GE(eps, 0.1) << "step " << sim.step_index();
      ASSERT_LE(eps, 1.0) << "step " << sim.step_index();
    }
    EXPECT_GT(d.floored_elements, 0) << "the packing stays denser than the mesh: the floor keeps biting";
    ASSERT_TRUE(d.drag_on_particles.allFinite()) << "step " << sim.step_index();
    ASSERT_TRUE(d.force_on_fluid.allFinite()) << "step " << sim.step_index();
    const double u_max = max_norm3(sim.fluid_velocity());
    const double v_max = max_particle_speed(sim.particles());
    // Fluid: 5 cm/s enter a 4.8 mm duct; even with the bed's half of the section blocked, the
    // mean above it is 2 U and a duct's peak/mean is 2.1, so 4.2 U; 10 U flags a blow-up.
    EXPECT_LT(u_max, 10.0 * kInlet) << "step " << sim.step_index();
    // Grains in walls, pushed by drag: no faster than the flow that pushes them.
    EXPECT_LT(v_max, 10.0 * kInlet) << "step " << sim.step_index();
    // Drag bound: Ergun's coefficient K = beta / (1 - eps) is largest at the floor (it falls
    // with eps, Eq. 12) and K s grows with the slip s <= u_max + v_max, so each grain's drag is
    // at most V_p K(0.1, s) s; the total at most N times that.
    const double s = 10.0 * kInlet + 10.0 * kInlet;
    const double bound =
        kGrains * sphere_volume(kDiameter) * force_coefficient(drag_law("ergun_wen_yu"), 0.1, s, kDiameter, water) * s;
    EXPECT_LE(d.drag_on_particles.norm(), bound) << "step " << sim.step_index();
    u_peak = std::max(u_peak, u_max);
    v_peak = std::max(v_peak, v_max);
    drag_peak = std::max(drag_peak, d.drag_on_particles.norm());
    drag_bound = bound;
    EXPECT_EQ(d.dem.particles_removed, 0u);
  }
  EXPECT_EQ(sim.diagnostics().floored_element_updates, floored_sum) << "the run total counts every update";
  std::printf("dense packing: max |u| %.4g m/s (%.3g U), max grain speed %.4g m/s, max |drag| %.4g N (bound %.4g N), "
              "floored element-updates %ld\n",
              u_peak, u_peak / kInlet, v_peak, drag_peak, drag_bound, floored_sum);
}

TEST(DensePacking, FdemRunReportsFlooredElementsInEveryRow) {
  // Shows: `fdem run` writes floored_elements (> 0) and min_porosity (< 0 at t = 0) in its probes CSV.
  const auto dir = hard::scratch_dir("dense_packing");
  hard::write_text(dir / "dense.yaml", kDenseScene);
  hard::FdemProcess run({"run", (dir / "dense.yaml").string(), "-o", (dir / "out").string(), "-q", "-t", "1"}, dir);
  ASSERT_EQ(run.wait(), 0) << run.stderr_text();
  const hard::Csv csv = hard::read_csv(dir / "out" / "probes.csv");
  ASSERT_TRUE(csv.well_formed);
  const int floored = csv.column("floored_elements");
  const int min_eps = csv.column("min_porosity");
  ASSERT_GE(floored, 0) << "probes.csv must report floored_elements";
  ASSERT_GE(min_eps, 0) << "probes.csv must report min_porosity";
  ASSERT_EQ(csv.rows.size(), 11u);  // t = 0 and 10 steps
  EXPECT_EQ(csv.rows.front()[static_cast<std::size_t>(floored)], kGrains);
  EXPECT_LT(csv.rows.front()[static_cast<std::size_t>(min_eps)], 0.0);
  for (const auto& row : csv.rows) {
    EXPECT_GT(row[static_cast<std::size_t>(floored)], 0.0);
    for (double v : row) EXPECT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace fdem

// The coupled step (Simulation): momentum exchange, coupling modes, freeze,
// subcycles, and what a scene without fluid builds. Small scenes (3 x 3 x 6
// cells of 4 mm, 270 tetrahedra) so each test takes well under a second.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "coupling/simulation.hpp"

namespace fdem {
namespace {

Scene small_scene(CouplingMode mode, SourceForm form = SourceForm::conservative) {
  Scene s;
  s.source_file = "test_simulation";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(0.012, 0.012, 0.024);
  s.cells = {3, 3, 6};
  s.effects.coupling = mode;
  s.fluid.density = 1000.0;
  s.fluid.viscosity = 1e-3;
  ParticleSet p;
  p.name = "grain";
  p.placement = PlacementKind::single;
  p.position = Vec3(0.006, 0.006, 0.018);  // centre of cell (1, 1, 4): central tetrahedron
  p.size.kind = SizeKind::fixed;
  p.size.diameter = 0.76e-3;
  p.density = 2650.0;
  s.particles.push_back(p);
  s.contact.normal_stiffness = 10.0;  // stable at 1e-4 s for this grain (bound 1.7e-4 s)
  s.contact.restitution = 0.5;
  s.time.fluid_step = 0.01;
  s.time.dem_step = 1e-4;  // 100 subcycles; response time of this grain ~ 40 ms
  s.time.end_time = 0.05;
  s.coupling.source_form = form;
  return s;
}

double free_fall_speed(const Scene& s, double t) {  // gravity and buoyancy only, Eq. 4-5
  const double rho_p = s.particles[0].density;
  return 9.81 * (1.0 - s.fluid.density / rho_p) * t;
}

double max_abs(std::span<const double> v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST(Simulation, ConservativeSourceBalancesMomentumInTheCoupledStep) {
  Simulation sim(small_scene(CouplingMode::two_way, SourceForm::conservative));
  for (int n = 0; n < 3; ++n) sim.step();
  const CouplingDiagnostics d = sim.diagnostics();
  ASSERT_GT(d.drag_on_particles.norm(), 1e-7);  // ~ m g: 6e-7 kg * 9.81 * 0.6 after 30 ms
  // The fluid receives exactly minus the mean drag of the step: sums of a few
  // terms, round-off 1e-15 relative.
  EXPECT_LT(d.momentum_imbalance, 1e-13);
  EXPECT_LT((d.drag_on_particles + d.force_on_fluid).norm(), 1e-13 * d.drag_on_particles.norm());
}

TEST(Simulation, ShapeFunctionPorosityConservesSolidAndMomentum) {
  Scene s = small_scene(CouplingMode::two_way, SourceForm::conservative);
  s.coupling.porosity = PorosityScheme::shape_function;
  Simulation sim(s);
  for (int n = 0; n < 3; ++n) sim.step();
  const BoxMesh& mesh = *sim.mesh();
  double solid = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) solid += mesh.element_volume(e) * (1.0 - sim.porosity()[static_cast<std::size_t>(e)]);
  // sum_e V_e (1 - eps_e) = V_p: sums of ~1e3 terms, 1e-12 relative.
  EXPECT_NEAR(solid, sphere_volume(0.76e-3), 1e-12 * sphere_volume(0.76e-3));
  EXPECT_LT(sim.diagnostics().momentum_imbalance, 1e-13);
}

TEST(Simulation, PaperSourceGivesFluidOneOverEpsTimesTheDrag) {
  Simulation sim(small_scene(CouplingMode::two_way, SourceForm::paper));
  for (int n = 0; n < 3; ++n) sim.step();
  const double eps = sim.porosity()[static_cast<std::size_t>(sim.particle_elements()[0])];
  EXPECT_NEAR(sim.diagnostics().momentum_imbalance, 1.0 / eps - 1.0, 1e-12);
  EXPECT_GT(1.0 / eps - 1.0, 0.01);  // 4 mm cell, 0.76 mm grain: eps = 0.9892
}

TEST(Simulation, CouplingOffIsFreeFallAndStillFluid) {
  const Scene s = small_scene(CouplingMode::off);
  Simulation sim(s);
  while (!sim.finished()) sim.step();
  EXPECT_EQ(sim.step_index(), 5);
  EXPECT_NEAR(sim.time(), 0.05, 1e-15);
  // Velocity Verlet is exact for a constant force: round-off only.
  EXPECT_NEAR(-sim.particles().vz[0], free_fall_speed(s, 0.05), 1e-12);
  EXPECT_EQ(max_abs(sim.fluid_velocity()), 0.0);
  EXPECT_EQ(max_abs(sim.source_term()), 0.0);
}

TEST(Simulation, FluidToParticleDragsTheGrainAndLeavesTheFluidAtRest) {
  const Scene s = small_scene(CouplingMode::fluid_to_particle);
  Simulation sim(s);
  while (!sim.finished()) sim.step();
  const double v = -sim.particles().vz[0];
  EXPECT_LT(v, 0.9 * free_fall_speed(s, 0.05));  // drag is felt (tau ~ 40 ms, so well below free fall)
  EXPECT_GT(v, 0.0);
  EXPECT_EQ(max_abs(sim.fluid_velocity()), 0.0);  // nothing reaches the fluid
  EXPECT_EQ(max_abs(sim.source_term()), 0.0);
}

TEST(Simulation, ParticleToFluidMovesTheFluidNotTheGrain) {
  const Scene s = small_scene(CouplingMode::particle_to_fluid);
  Simulation sim(s);
  while (!sim.finished()) sim.step();
  EXPECT_NEAR(-sim.particles().vz[0], free_fall_speed(s, 0.05), 1e-12);  // drag not felt
  EXPECT_GT(max_abs(sim.fluid_velocity()), 1e-6);                     // but the fluid is pushed
  EXPECT_GT(max_abs(sim.source_term()), 0.0);
}

TEST(Simulation, TwoWayGrainFallsFasterThanOneWay) {
  // The fluid dragged along reduces the slip: two-way speed >= one-way speed.
  Simulation one(small_scene(CouplingMode::fluid_to_particle));
  Simulation two(small_scene(CouplingMode::two_way));
  while (!one.finished()) one.step();
  while (!two.finished()) two.step();
  EXPECT_GT(-two.particles().vz[0], -one.particles().vz[0]);
}

TEST(Simulation, DragTimeIsPartOfTheDemTimeAndZeroWithoutCoupling) {
  Simulation coupled(small_scene(CouplingMode::two_way)), dry(small_scene(CouplingMode::off));
  coupled.step();
  dry.step();
  const CouplingDiagnostics c = coupled.diagnostics(), d = dry.diagnostics();
  EXPECT_GT(c.drag_seconds, 0.0);  // 100 drag evaluations were timed
  EXPECT_LE(c.drag_seconds, c.dem_seconds);
  EXPECT_EQ(d.drag_seconds, 0.0);  // no drag object exists
  EXPECT_EQ(coupled.steps_to_end(), 5);
}

TEST(Simulation, CouplingDiagnosticsAreTheDiagnosticsWithoutTheDemPass) {
  Simulation sim(small_scene(CouplingMode::two_way));
  for (int n = 0; n < 2; ++n) sim.step();
  const CouplingDiagnostics all = sim.diagnostics(), coupling = sim.coupling_diagnostics();
  ASSERT_EQ(all.dem.steps, 200u);
  EXPECT_GT(all.dem.kinetic_energy_j, 0.0);
  // The same step's numbers, bit for bit; the DEM's part not computed.
  EXPECT_EQ(coupling.fluid_seconds, all.fluid_seconds);
  EXPECT_EQ(coupling.dem_seconds, all.dem_seconds);
  EXPECT_EQ(coupling.drag_seconds, all.drag_seconds);
  EXPECT_EQ(coupling.coupling_seconds, all.coupling_seconds);
  EXPECT_EQ(coupling.drag_on_particles, all.drag_on_particles);
  EXPECT_EQ(coupling.momentum_imbalance, all.momentum_imbalance);
  EXPECT_EQ(coupling.dem.steps, 0u);
  EXPECT_EQ(coupling.dem.kinetic_energy_j, 0.0);
}

TEST(Simulation, FreezeHoldsGrainsAndSourceUntilReleased) {
  Scene s = small_scene(CouplingMode::two_way);
  s.coupling.freeze_until = 0.02;
  Simulation sim(s);
  sim.step();
  sim.step();
  EXPECT_EQ(sim.particles().z[0], 0.018);
  EXPECT_EQ(sim.particles().vz[0], 0.0);
  EXPECT_EQ(max_abs(sim.source_term()), 0.0);
  sim.step();
  EXPECT_LT(sim.particles().z[0], 0.018);
  EXPECT_GT(max_abs(sim.source_term()), 0.0);
}

TEST(Simulation, SubcyclesComeFromTheSceneOrTheStepRatio) {
  Scene s = small_scene(CouplingMode::two_way);
  EXPECT_EQ(Simulation(s).subcycles(), 100);  // fluid_step / dem_step
  s.time.subcycles = 200;
  s.time.dem_step = 0.0;  // derived: 0.01 / 200
  Simulation sim(s);
  EXPECT_EQ(sim.subcycles(), 200);
  sim.step();
  EXPECT_EQ(sim.diagnostics().dem.steps, 200u);
  s.time.dem_step = 1e-4;  // 200 x 1e-4 != 0.01
  EXPECT_THROW(Simulation bad(s), InputError);
}

TEST(Simulation, DrySceneBuildsNoMeshAndNoFluid) {
  Scene s = small_scene(CouplingMode::off);
  s.effects.fluid = false;
  s.effects.buoyancy = false;
  Simulation sim(s);
  EXPECT_EQ(sim.mesh(), nullptr);
  EXPECT_TRUE(sim.fluid_velocity().empty());
  EXPECT_TRUE(sim.porosity().empty());
  EXPECT_TRUE(sim.source_term().empty());
  sim.step();
  EXPECT_NEAR(-sim.particles().vz[0], 9.81 * 0.01, 1e-14);  // free fall without buoyancy
}

// A study's stages: the inlet raised between steps. A duct with free-slip
// sides, an inlet at z_min and an outlet at z_max carries the inlet's plug
// flow exactly (div u = 0, no shear), so after one step at the new value
// every node moves at it; the scene reports it; a face that is not an
// inlet is refused.
TEST(Simulation, InletVelocityChangedBetweenStepsIsTheFlowOfTheNextStep) {
  Scene s = small_scene(CouplingMode::off);
  for (int f = 0; f < 4; ++f) s.fluid.faces[static_cast<std::size_t>(f)].condition = FaceCondition::free_slip;
  s.fluid.faces[4].condition = FaceCondition::inlet;
  s.fluid.faces[4].velocity = Vec3(0, 0, 1e-3);
  s.fluid.faces[5].condition = FaceCondition::outlet;
  Simulation sim(s);
  sim.step();
  const auto max_deviation = [&](double w) {
    double dev = 0.0;
    const auto u = sim.fluid_velocity();
    for (std::size_t a = 0; a < u.size() / 3; ++a)
      dev = std::max({dev, std::abs(u[3 * a]), std::abs(u[3 * a + 1]), std::abs(u[3 * a + 2] - w)});
    return dev;
  };
  EXPECT_LT(max_deviation(1e-3), 1e-3 * 1e-6);  // linear tolerance 1e-8
  sim.set_inlet_velocity(BoxFace::z_min, Vec3(0, 0, 3e-3));
  EXPECT_EQ(sim.scene().fluid.faces[4].velocity.z(), 3e-3);
  sim.step();
  EXPECT_LT(max_deviation(3e-3), 3e-3 * 1e-6);
  EXPECT_THROW(sim.set_inlet_velocity(BoxFace::z_max, Vec3(0, 0, 1e-3)), SolverError);
}

// Starting from a zero inlet the fluid is at rest and its solve skipped;
// an inlet raised later must end that (the flow follows the new inlet).
TEST(Simulation, InletRaisedFromZeroEndsTheFluidAtRestShortcut) {
  Scene s = small_scene(CouplingMode::off);
  for (int f = 0; f < 4; ++f) s.fluid.faces[static_cast<std::size_t>(f)].condition = FaceCondition::free_slip;
  s.fluid.faces[4].condition = FaceCondition::inlet;
  s.fluid.faces[5].condition = FaceCondition::outlet;
  Simulation sim(s);
  sim.step();
  EXPECT_EQ(*std::max_element(sim.fluid_velocity().begin(), sim.fluid_velocity().end()), 0.0);
  sim.set_inlet_velocity(BoxFace::z_min, Vec3(0, 0, 2e-3));
  sim.step();
  EXPECT_NEAR(sim.fluid_velocity()[2], 2e-3, 2e-9);
}

}  // namespace
}  // namespace fdem

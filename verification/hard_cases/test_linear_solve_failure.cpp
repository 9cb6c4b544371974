// Hard case: a linear solve that does not converge. The fluid solver must
// throw SolverError naming the step, the iterations and the residual, leave
// its state at the last good step, and the coupled run must not continue
// silently (`fdem run` exits 3 with the message).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "coupling/simulation.hpp"
#include "fluid/fluid_solver.hpp"
#include "hard_scenes.hpp"
#include "mesh/box_mesh.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

using hard::contains;

// A duct driven by an inlet, with a linear tolerance no Krylov solver reaches in 2 iterations.
Scene starved_duct() {
  Scene s = hard::water_box(6, 3, 3, 1e-3);
  s.fluid.faces[0].condition = FaceCondition::inlet;
  s.fluid.faces[0].velocity = Vec3(0.05, 0.0, 0.0);
  s.fluid.faces[1].condition = FaceCondition::outlet;
  s.fluid.linear_tolerance = 1e-15;
  s.fluid.max_linear_iterations = 2;
  s.time.fluid_step = 1e-2;
  s.time.end_time = 0.1;
  return s;
}

TEST(LinearSolveFailure, FluidSolverThrowsNamingStepIterationsResidualAndKeepsItsState) {
  // Shows: BiCGSTAB, and PETSc's FGMRES, capped at 2 iterations at tolerance 1e-15 throw SolverError;
  // time, step count and velocity are unchanged.
  for (const FluidLinearSolverChoice choice :
       {FluidLinearSolverChoice::eigen_bicgstab_ilut, FluidLinearSolverChoice::petsc}) {
    Scene s = starved_duct();
    s.fluid.linear_solver = choice;
    const BoxMesh mesh(s.domain.lower, s.domain.upper, s.cells);
    FluidSolver fluid(mesh, s);
    const std::vector<double> before(fluid.velocity().begin(), fluid.velocity().end());
    try {
      fluid.step(1e-2);
      FAIL() << "a linear solve that cannot reach its tolerance must not pass";
    } catch (const SolverError& e) {
      const std::string what = e.what();
      EXPECT_TRUE(contains(what, "fluid step 1")) << what;
      EXPECT_TRUE(contains(what, "did not converge")) << what;
      EXPECT_TRUE(contains(what, "residual")) << what;
      EXPECT_TRUE(contains(what, "max_linear_iterations")) << "names the setting to change: " << what;
    }
    EXPECT_EQ(fluid.step_count(), 0);
    EXPECT_EQ(fluid.time(), 0.0);
    const std::vector<double> after(fluid.velocity().begin(), fluid.velocity().end());
    EXPECT_EQ(after, before) << "a failed step leaves the last good velocity";
  }
}

TEST(LinearSolveFailure, CoupledStepDoesNotAdvanceAfterTheFailure) {
  // Shows: Simulation::step rethrows the SolverError and its time and step index stay at the last good step.
  Scene s = starved_duct();
  s.particles.push_back(hard::single_particle(Vec3(3e-3, 1.5e-3, 1.5e-3), 0.2e-3, 2650.0));
  s.contact = hard::soft_contact();
  s.time.dem_step = 1e-5;
  s.time.subcycles = 1000;
  Simulation sim(s);
  const double z0 = sim.particles().z[0];
  EXPECT_THROW(sim.step(), SolverError);
  EXPECT_EQ(sim.step_index(), 0);
  EXPECT_EQ(sim.time(), 0.0);
  EXPECT_EQ(sim.particles().z[0], z0) << "no DEM subcycle ran after the failed fluid solve";
}

TEST(LinearSolveFailure, FdemRunExitsWithCode3AndTheSolverMessage) {
  // Shows: `fdem run` with fluid.solver {linear_tolerance 1e-15, max_linear_iterations 2} exits 3 naming the
  // failure and the residual, with either linear solver.
  for (const std::string solver : {"eigen_bicgstab_ilut", "petsc"}) {
    const auto dir = hard::scratch_dir("linear_failure_" + solver);
    hard::write_text(dir / "duct.yaml", R"(title: starved linear solver (hard case)
effects: {fluid: true}
domain: {lower: [0, 0, 0], upper: [0.006, 0.003, 0.003]}
mesh: {cells: [6, 3, 3]}
)" + hard::water_along_x_yaml("0.05") + "  solver: {linear_tolerance: 1.0e-15, max_linear_iterations: 2, linear_solver: " + solver + R"(}
time: {fluid_step: 1.0e-2, end: 0.1}
output: {directory: out}
)");
    hard::FdemProcess run({"run", (dir / "duct.yaml").string(), "-o", (dir / "out").string(), "-q", "-t", "1"}, dir);
    EXPECT_EQ(run.wait(), 3);
    const std::string err = run.stderr_text();
    EXPECT_TRUE(contains(err, "did not converge")) << err;
    EXPECT_TRUE(contains(err, "fluid step 1")) << err;
    EXPECT_TRUE(contains(err, "relative residual")) << err;
  }
}

}  // namespace
}  // namespace fdem

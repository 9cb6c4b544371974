// Inlet faces: a superficial inlet (fluid.boundaries.<face>.superficial)
// delivers the flux asked for into a porous region that touches it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "fluid/fluid_solver.hpp"

namespace fdem {
namespace {

// A duct along x, uniform porosity eps everywhere (also on the inlet nodes),
// free-slip sides, traction-free outlet. div(eps u) = 0 with uniform eps
// keeps u uniform, so u equals what the inlet nodes are given: U / eps for
// a superficial inlet with a volume-averaged model (the flux eps u = U),
// U otherwise (the simplified model has no eps in its continuity).
double duct_velocity(FluidModel model, bool superficial) {
  constexpr double U = 0.01, eps = 0.4;
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.02, 0.005, 0.005), {4, 1, 1});
  Scene scene;
  scene.fluid.model = model;
  scene.fluid.faces[0].condition = FaceCondition::inlet;
  scene.fluid.faces[0].velocity = Vec3(U, 0, 0);
  scene.fluid.faces[0].superficial = superficial;
  scene.fluid.faces[1].condition = FaceCondition::outlet;
  for (std::size_t f = 2; f < 6; ++f) scene.fluid.faces[f].condition = FaceCondition::free_slip;
  FluidSolver fluid(mesh, scene, {.linear_solver = FluidLinearSolver::sparse_lu});
  fluid.set_porosity(std::vector<double>(static_cast<std::size_t>(mesh.num_elements()), eps));
  fluid.step(std::numeric_limits<double>::infinity());
  double lo = 1e300, hi = -1e300;
  for (Index a = 0; a < mesh.num_nodes(); ++a) {
    lo = std::min(lo, fluid.velocity()[3 * static_cast<std::size_t>(a)]);
    hi = std::max(hi, fluid.velocity()[3 * static_cast<std::size_t>(a)]);
  }
  EXPECT_LT(hi - lo, 1e-10 * hi);  // uniform, to LU round-off
  return hi / U;
}

TEST(FluidInlet, SuperficialInletGivesVolumeAveragedFluidTheFluxAskedFor) {
  EXPECT_NEAR(duct_velocity(FluidModel::vans_a, true), 1.0 / 0.4, 1e-10);
  EXPECT_NEAR(duct_velocity(FluidModel::vans_b, true), 1.0 / 0.4, 1e-10);
  EXPECT_NEAR(duct_velocity(FluidModel::vans_a, false), 1.0, 1e-10);     // as given: flux eps U only
  EXPECT_NEAR(duct_velocity(FluidModel::simplified, true), 1.0, 1e-10);  // no eps in Eq. 21
}

}  // namespace
}  // namespace fdem

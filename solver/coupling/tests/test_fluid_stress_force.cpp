// Model A's pressure-gradient force on the grains (coupling/fluid_stress_force.hpp)
// against a pressure field the fluid solver holds exactly: the Darcy-like
// duct of a uniform bed (verification/fluid/test_fluid_vans.cpp), where
// eps dp/dx = -beta U and the force on a grain is -V_p grad p.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include "coupling/fluid_stress_force.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem {
namespace {

struct UnitForceX final : ExternalForce {
  void add(const Particles&, std::span<double> fx, std::span<double>, std::span<double>) override {
    for (double& f : fx) f += 1.0;
  }
};

TEST(FluidStressForce, GrainFeelsMinusItsVolumeTimesTheDynamicPressureGradient) {
  constexpr double U = 0.02, beta = 3.0e6, eps = 0.45, length = 0.04, d = 1.0e-3;
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(length, 0.01, 0.01), {8, 2, 2});
  Scene scene;
  scene.fluid.model = FluidModel::vans_a;
  scene.fluid.faces[0].condition = FaceCondition::inlet;
  scene.fluid.faces[0].velocity = Vec3(U, 0, 0);
  scene.fluid.faces[1].condition = FaceCondition::outlet;
  for (std::size_t f = 2; f < 6; ++f) scene.fluid.faces[f].condition = FaceCondition::free_slip;
  FluidSolver fluid(mesh, scene, {.linear_solver = FluidLinearSolver::sparse_lu});
  const auto elements = static_cast<std::size_t>(mesh.num_elements());
  fluid.set_porosity(std::vector<double>(elements, eps));
  fluid.set_momentum_exchange(std::vector<double>(elements, beta), std::vector<double>(3 * elements, 0.0));
  fluid.step(std::numeric_limits<double>::infinity());

  Particles particles;
  particles.add(0.013, 0.004, 0.006, d, 2500.0);
  particles.add(0.031, 0.007, 0.002, d, 2500.0);
  ParticleMapping mapping;
  mapping.update(mesh, particles);
  UnitForceX inner;
  FluidStressForce force(&inner);
  force.begin_step(mapping, particles, fluid);
  std::vector<double> fx(2, 0.0), fy(2, 0.0), fz(2, 0.0);
  force.add(particles, fx, fy, fz);
  // Model A: eps dp/dx = -beta U, so -V_p dp/dx = V_p beta U / eps, pushing downstream.
  const double expected = sphere_volume(d) * beta * U / eps;
  for (std::size_t i = 0; i < 2; ++i) {
    // LU round-off of the pressure (test_fluid_vans.cpp: 1e-9 of the slope).
    EXPECT_NEAR(fx[i], 1.0 + expected, 1e-8 * expected);
    EXPECT_NEAR(fy[i], 0.0, 1e-8 * expected);
    EXPECT_NEAR(fz[i], 0.0, 1e-8 * expected);
  }
}

}  // namespace
}  // namespace fdem

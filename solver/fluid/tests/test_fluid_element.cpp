// Unit tests of the P1/P1 SUPG/PSPG/LSIC element system (fluid/fluid_element.hpp).
// GCC 12 reports a false -Wmaybe-uninitialized inside its own AVX-512
// intrinsics (_mm512_extractf64x4_pd's __Y = __Y idiom) when Eigen's dynamic
// reductions are inlined with -march=native; the warning is about the
// compiler's header, not this file. It must precede the first Eigen include.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include "fluid/fluid_element.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

#include "mesh/box_mesh.hpp"

using fdem::BoxMesh;
using fdem::FluidElementInput;
using fdem::FluidElementSystem;
using fdem::Vec3;

namespace {

// A corner tetrahedron of a stretched cell: not regular, so symmetric
// mistakes do not cancel.
FluidElementInput sample_input(double dt, const Vec3& advecting) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.02, 0.03, 0.05), {1, 1, 1});
  FluidElementInput in;
  in.gradients = mesh.shape_gradients(2);
  in.volume = mesh.element_volume(2);
  in.h = std::cbrt(mesh.cell_size().prod());
  for (int a = 0; a < 4; ++a) in.advecting.row(a) = advecting.transpose();
  in.history.setZero();
  in.body_force.setZero();
  in.density = 1000.0;
  in.viscosity = 1e-3;
  in.dt = dt;
  in.alpha0 = 1.0;
  return in;
}

Eigen::Matrix<double, 16, 1> constant_velocity(const Vec3& u, double p) {
  Eigen::Matrix<double, 16, 1> x;
  for (int a = 0; a < 4; ++a) {
    x.segment<3>(4 * a) = u;
    x[4 * a + 3] = p;
  }
  return x;
}

constexpr double steady = std::numeric_limits<double>::infinity();

}  // namespace

TEST(FluidElement, SteadyOperatorAnnihilatesUniformFlowAndSeesConstantPressureOnlyThroughItsBoundary) {
  // A uniform velocity solves the steady equations with f = 0: every row of
  // K x vanishes (partition of unity: sum_b grad N_b = 0). A constant pressure
  // leaves the continuity rows (PSPG) at zero and gives the momentum rows only
  // -(div w, p) = -p V grad N_a, the element's share of a boundary integral
  // that cancels between neighbours.
  FluidElementSystem sys;
  const auto in = sample_input(steady, Vec3(0.3, -0.1, 0.2));
  fdem::fluid_element_system(in, sys);
  const double scale = sys.matrix.cwiseAbs().maxCoeff();
  const Eigen::Matrix<double, 16, 1> flow = sys.matrix * constant_velocity(Vec3(0.3, -0.1, 0.2), 0.0);
  // round-off relative to the largest entry times |u| ~ 0.4
  EXPECT_LT(flow.cwiseAbs().maxCoeff(), 1e-12 * scale);
  const Eigen::Matrix<double, 16, 1> level = sys.matrix * constant_velocity(Vec3::Zero(), 123.0);
  for (int a = 0; a < 4; ++a) {
    EXPECT_NEAR(level[4 * a + 3], 0.0, 1e-12 * scale * 123.0);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(level[4 * a + i], -123.0 * in.volume * in.gradients(a, i), 1e-12 * scale * 123.0);
  }
}

TEST(FluidElement, TransientMassRowsSumToRhoVolumeOverDt) {
  // With a = 0 there is no SUPG; the momentum rows applied to a uniform u hold
  // only the consistent mass: sum_ab M_ab = V, times rho alpha0 / dt.
  FluidElementSystem sys;
  auto in = sample_input(1e-3, Vec3::Zero());
  in.alpha0 = 1.5;
  fdem::fluid_element_system(in, sys);
  const Eigen::Matrix<double, 16, 1> r = sys.matrix * constant_velocity(Vec3(1.0, 0.0, 0.0), 0.0);
  double x_momentum = 0.0;
  for (int a = 0; a < 4; ++a) x_momentum += r[4 * a];
  EXPECT_NEAR(x_momentum, in.density * 1.5 / in.dt * in.volume, 1e-12 * in.density * 1.5 / in.dt * in.volume);
}

TEST(FluidElement, StokesGalerkinCouplingIsSkewAndViscousBlockIsSymmetric) {
  // a = 0 and dt = inf: the pressure-velocity coupling of momentum (-B^T) and
  // continuity (+B) are exact negatives (PSPG adds no velocity term: its
  // residual's velocity part vanishes), and the viscous + grad-div block is
  // symmetric positive semi-definite.
  FluidElementSystem sys;
  const auto in = sample_input(steady, Vec3::Zero());
  fdem::fluid_element_system(in, sys);
  Eigen::Matrix<double, 12, 12> velocity_block;
  const double scale = sys.matrix.cwiseAbs().maxCoeff();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(sys.matrix(4 * a + i, 4 * b + 3), -sys.matrix(4 * b + 3, 4 * a + i), 1e-14 * scale);
        EXPECT_NEAR(sys.matrix(4 * a + i, 4 * b + 3), -in.volume / 4.0 * in.gradients(a, i), 1e-14 * scale);
        for (int j = 0; j < 3; ++j) velocity_block(3 * a + i, 3 * b + j) = sys.matrix(4 * a + i, 4 * b + j);
      }
    }
  EXPECT_LT((velocity_block - velocity_block.transpose()).cwiseAbs().maxCoeff(), 1e-14 * scale);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> eig(velocity_block);
  EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-12 * scale);
  // The PSPG pressure block is tau/rho V grad N_a . grad N_b with tau = h^2/(4 nu).
  const auto stab = fdem::fluid_stabilization(in.h, Vec3::Zero(), in.density, in.viscosity, in.dt);
  const Eigen::Matrix4d expected = stab.tau_momentum / in.density * in.volume * in.gradients * in.gradients.transpose();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) EXPECT_NEAR(sys.matrix(4 * a + 3, 4 * b + 3), expected(a, b), 1e-12 * expected.norm());
}

TEST(FluidElement, ConvectionRowsMatchExactIntegralForLinearAdvectingVelocity) {
  // Column sums of the Galerkin convection: sum_a int N_a a.grad N_b = int a.grad N_b
  // = V mean(a).grad N_b exactly for P1 a; with mu -> 0, dt = inf, and the
  // skew term removed by a divergence-free a (a uniform field here is the
  // simplest such), K x for x = N_b e_x summed over the x-rows.
  FluidElementSystem sys;
  auto in = sample_input(steady, Vec3(0.2, 0.1, -0.3));
  in.viscosity = 1e-300;
  fdem::fluid_element_system(in, sys);
  const auto stab = fdem::fluid_stabilization(in.h, Vec3(0.2, 0.1, -0.3), in.density, in.viscosity, in.dt);
  for (int b = 0; b < 4; ++b) {
    double column = 0.0;
    for (int a = 0; a < 4; ++a) column += sys.matrix(4 * a, 4 * b);
    // LSIC adds rho tau_C V g_a,x g_b,x which sums to 0 over a; SUPG sums to 0 too.
    const double exact = in.density * in.volume * Vec3(0.2, 0.1, -0.3).dot(in.gradients.row(b).transpose());
    EXPECT_NEAR(column, exact, 1e-12 * std::abs(in.density * in.volume * 0.3 / stab.h));
  }
}

TEST(FluidElement, UniformBodyForceLoadsVolumeTimesForce) {
  // Consistent load of a uniform f: sum_a int N_a f = V f; PSPG load tau/rho V grad N_a . f.
  FluidElementSystem sys;
  auto in = sample_input(1e-2, Vec3::Zero());
  for (int a = 0; a < 4; ++a) in.body_force.row(a) = Eigen::RowVector3d(0.0, 0.0, -9810.0);
  fdem::fluid_element_system(in, sys);
  double fz = 0.0;
  for (int a = 0; a < 4; ++a) fz += sys.rhs[4 * a + 2];
  EXPECT_NEAR(fz, -9810.0 * in.volume, 1e-12 * 9810.0 * in.volume);
  const auto stab = fdem::fluid_stabilization(in.h, Vec3::Zero(), in.density, in.viscosity, in.dt);
  for (int a = 0; a < 4; ++a)
    EXPECT_NEAR(sys.rhs[4 * a + 3], stab.tau_momentum / in.density * in.volume * in.gradients(a, 2) * -9810.0,
                1e-12 * std::abs(stab.tau_momentum / in.density * in.volume * 9810.0 * in.gradients.norm()));
}

TEST(FluidElement, HydrostaticPressureBalancesGravityExactly) {
  // p = rho g.x with u = 0 under f = rho g: the element residual K x - r is the
  // boundary flux only; its sum over the four momentum rows (the element's net
  // force) is int grad p - f = 0, and the PSPG rows see R_M = grad p - f = 0.
  FluidElementSystem sys;
  auto in = sample_input(1e-2, Vec3::Zero());
  const Vec3 rho_g(0.0, 0.0, -9810.0);
  for (int a = 0; a < 4; ++a) in.body_force.row(a) = rho_g.transpose();
  fdem::fluid_element_system(in, sys);
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.02, 0.03, 0.05), {1, 1, 1});
  Eigen::Matrix<double, 16, 1> x = Eigen::Matrix<double, 16, 1>::Zero();
  for (int a = 0; a < 4; ++a) x[4 * a + 3] = rho_g.dot(mesh.node(mesh.element_nodes(2)[static_cast<std::size_t>(a)]));
  const auto r = (sys.matrix * x - sys.rhs).eval();
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(r[4 * a + 3], 0.0, 1e-12 * sys.rhs.cwiseAbs().maxCoeff());
}

TEST(FluidElement, StabilizationParameterHasItsThreeLimits) {
  const double h = 0.01, rho = 1000.0, mu = 1e-3;
  // transient limit: tau -> dt/2, tau_C -> h^2 / (6 dt)
  auto s = fdem::fluid_stabilization(h, Vec3::Zero(), rho, mu, 1e-9);
  EXPECT_NEAR(s.tau_momentum, 0.5e-9, 1e-6 * 0.5e-9);
  EXPECT_NEAR(s.tau_continuity, h * h / 6e-9, 1e-6 * h * h / 6e-9);
  // advective limit: tau -> h / (2|u|), tau_C -> h|u|/6
  s = fdem::fluid_stabilization(h, Vec3(1e3, 0, 0), rho, mu, steady);
  EXPECT_NEAR(s.tau_momentum, h / 2e3, 1e-6 * h / 2e3);
  EXPECT_NEAR(s.tau_continuity, h * 1e3 / 6.0, 1e-6 * h * 1e3 / 6.0);
  // diffusive limit: tau -> h^2 / (4 nu), tau_C -> nu / 3
  s = fdem::fluid_stabilization(h, Vec3::Zero(), rho, mu, steady);
  EXPECT_NEAR(s.tau_momentum, h * h / (4.0 * mu / rho), 1e-12);
  EXPECT_NEAR(s.tau_continuity, mu / rho / 3.0, 1e-15);
}

// Volume-averaged fluid models (fluid.model vans_a / vans_b, paper Eq. 18-19)
// and the semi-implicit momentum exchange against solutions that P1 holds
// exactly, and the promise that the simplified model (Eq. 21-22) is unchanged
// bit for bit by a porosity it is given.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "fluid_fixtures.hpp"
#include "one_openmp_thread.hpp"

using namespace fdem;
using namespace fdem::fluid_verification;
using FC = FaceCondition;

namespace {

constexpr double steady = std::numeric_limits<double>::infinity();

// A duct along x: uniform inlet U at x_min, traction-free outlet at x_max,
// free-slip side walls; a uniform porosity and a uniform exchange
// (beta, v) throughout. The exact solution is u = (U, 0, 0) (uniform: it
// satisfies div(eps u) = 0 and has no viscous or convective term) and the
// Darcy-like pressure s dp/dx = -beta (U - v_x), p = 0 at the outlet (the
// natural condition s (mu du/dn - p n) = 0): linear, so P1 holds it.
struct Duct {
  static constexpr double U = 0.02, length = 0.04, beta = 3.0e6, v_x = 0.005, eps = 0.45;
  BoxMesh mesh{Vec3(0, 0, 0), Vec3(length, 0.01, 0.01), {8, 2, 2}};
  Scene scene;
  explicit Duct(FluidModel model) {
    scene = scene_with({FC::inlet, FC::outlet, FC::free_slip, FC::free_slip, FC::free_slip, FC::free_slip}, 1000.0,
                       1e-3);
    scene.fluid.faces[0].velocity = Vec3(U, 0, 0);
    scene.fluid.model = model;
  }
  std::vector<double> betas() const { return std::vector<double>(static_cast<std::size_t>(mesh.num_elements()), beta); }
  std::vector<double> grain_velocities() const {
    std::vector<double> v(3 * static_cast<std::size_t>(mesh.num_elements()), 0.0);
    for (std::size_t e = 0; e < v.size() / 3; ++e) v[3 * e] = v_x;
    return v;
  }
};

double max_abs_difference(std::span<const double> a, std::span<const double> b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

}  // namespace

TEST(FluidVolumeAveraged, UniformBedDarcyPressureIsExactForEveryModel) {
  for (const FluidModel model : {FluidModel::simplified, FluidModel::vans_a, FluidModel::vans_b}) {
    Duct duct(model);
    // Direct solve: the claim is about the discretization, not the Krylov tolerance.
    FluidSolver solver(duct.mesh, duct.scene, {.linear_solver = FluidLinearSolver::sparse_lu});
    solver.set_porosity(std::vector<double>(static_cast<std::size_t>(duct.mesh.num_elements()), Duct::eps));
    solver.set_momentum_exchange(duct.betas(), duct.grain_velocities());
    solver.step(steady);
    for (int s = 0; s < 3; ++s) solver.step(0.005);  // beta dt / rho = 15: implicit, no step limit
    // The pressure gradient is carried by s: eps in model A, 1 in model B and the simplified model.
    const double s = model == FluidModel::vans_a ? Duct::eps : 1.0;
    const double slope = -Duct::beta * (Duct::U - Duct::v_x) / s;  // [Pa/m]
    double u_error = 0.0, p_error = 0.0;
    for (Index n = 0; n < duct.mesh.num_nodes(); ++n) {
      u_error = std::max(u_error, (nodal_velocity(solver.velocity(), n) - Vec3(Duct::U, 0, 0)).cwiseAbs().maxCoeff());
      const double p_exact = slope * (duct.mesh.node(n).x() - Duct::length);
      p_error = std::max(p_error, std::abs(solver.pressure()[static_cast<std::size_t>(n)] - p_exact));
    }
    double gradient_error = 0.0;
    for (Index e = 0; e < duct.mesh.num_elements(); ++e)
      gradient_error = std::max(gradient_error, (solver.pressure_gradient(e) - Vec3(slope, 0, 0)).norm());
    fmt::print("model {}: |u - U|max {:.2e} m/s, |p - p_exact|max {:.2e} Pa of {:.3e}, |grad p - exact|max {:.2e} Pa/m\n",
               static_cast<int>(model), u_error, p_error, -slope * Duct::length, gradient_error);
    // Round-off of an LU solve (a few hundred unknowns; the exchange makes the
    // momentum diagonal ~1e4 x the viscous one): relative 1e-10 is ample.
    EXPECT_LT(u_error, 1e-10 * Duct::U);
    EXPECT_LT(p_error, 1e-10 * std::abs(slope) * Duct::length);
    EXPECT_LT(gradient_error, 1e-9 * std::abs(slope));
  }
}

namespace {

// A flow with convection, viscosity and a transient: a body-force blob in a
// closed box, three BDF2 steps with Picard.
std::vector<double> blob_run(FluidModel model, const std::vector<double>* porosity, bool exchange = false) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(0.02, 0.02, 0.03), {4, 4, 6});
  Scene scene = scene_with({FC::no_slip, FC::no_slip, FC::no_slip, FC::no_slip, FC::no_slip, FC::no_slip}, 1000.0, 1e-3);
  scene.fluid.model = model;
  scene.fluid.linearization = FluidLinearization::picard;
  FluidSolver solver(mesh, scene);
  solver.set_body_force(nodal(mesh, [](const Vec3& x) {
    const double r2 = (x - Vec3(0.01, 0.01, 0.015)).squaredNorm();
    return Vec3(0.0, 0.0, 50.0 * std::exp(-r2 / 2.5e-5));
  }));
  if (porosity) solver.set_porosity(*porosity);
  if (exchange) {
    const auto elements = static_cast<std::size_t>(mesh.num_elements());
    solver.set_momentum_exchange(std::vector<double>(elements, 0.0), std::vector<double>(3 * elements, 0.0));
  }
  for (int s = 0; s < 3; ++s) solver.step(0.01);
  std::vector<double> out(solver.velocity().begin(), solver.velocity().end());
  out.insert(out.end(), solver.pressure().begin(), solver.pressure().end());
  return out;
}

}  // namespace

TEST(FluidVolumeAveraged, SimplifiedModelIgnoresPorosityBitForBitAndVansWithUnitPorosityIsIt) {
  const std::vector<double> reference = blob_run(FluidModel::simplified, nullptr);
  ASSERT_GT(*std::max_element(reference.begin(), reference.end()), 1e-6);  // the blob moves the fluid
  const auto elements = static_cast<std::size_t>(4 * 4 * 6 * 5);
  std::vector<double> bumpy(elements), ones(elements, 1.0);
  for (std::size_t e = 0; e < elements; ++e) bumpy[e] = 0.4 + 0.5 * static_cast<double>((e * 7) % 11) / 10.0;
  // Bitwise: the simplified model never reads the porosity, and a zero
  // exchange runs its kernel (fluid_element.cpp).
  EXPECT_EQ(blob_run(FluidModel::simplified, &bumpy), reference);
  EXPECT_EQ(blob_run(FluidModel::simplified, nullptr, true), reference);
  // The volume-averaged kernel with eps = 1 is the same equations: equal to
  // round-off (its FMA contractions differ; 1e-12 of the largest value).
  const double largest = std::abs(*std::max_element(reference.begin(), reference.end(),
                                                    [](double a, double b) { return std::abs(a) < std::abs(b); }));
  EXPECT_LT(max_abs_difference(blob_run(FluidModel::vans_a, &ones), reference), 1e-12 * largest);
  EXPECT_LT(max_abs_difference(blob_run(FluidModel::vans_b, nullptr), reference), 1e-12 * largest);
  // And the porosity matters to the volume-averaged models (the test can fail).
  EXPECT_GT(max_abs_difference(blob_run(FluidModel::vans_a, &bumpy), reference), 1e-3 * 1e-3);
}

TEST(FluidVolumeAveraged, RefusesBadPorosityAndExchangeInput) {
  Duct duct(FluidModel::vans_a);
  FluidSolver solver(duct.mesh, duct.scene);
  const auto elements = static_cast<std::size_t>(duct.mesh.num_elements());
  std::vector<double> eps(elements, 0.5);
  eps[3] = 0.0;
  EXPECT_THROW(solver.set_porosity(eps), SolverError);
  eps[3] = 1.2;
  EXPECT_THROW(solver.set_porosity(eps), SolverError);
  EXPECT_THROW(solver.set_porosity(std::vector<double>(elements - 1, 0.5)), SolverError);
  std::vector<double> beta = duct.betas();
  EXPECT_THROW(solver.set_momentum_exchange(beta, std::vector<double>(elements, 0.0)), SolverError);
  beta[0] = -1.0;
  EXPECT_THROW(solver.set_momentum_exchange(beta, duct.grain_velocities()), SolverError);
  beta[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(solver.set_momentum_exchange(beta, duct.grain_velocities()), SolverError);
  EXPECT_NO_THROW(solver.set_momentum_exchange({}, {}));
}

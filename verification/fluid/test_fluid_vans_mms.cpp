// Manufactured solutions of the volume-averaged equations (paper Eq. 18-19,
// fluid.model vans_a / vans_b; weak form in solver/fluid/fluid_element.hpp)
// with a prescribed smooth porosity eps(x, t) and a smooth momentum exchange
// beta(x) (u - v(x)): observed orders on three refinements of the unit cube.
//
//   eps(x, t) = 0.7 + 0.2 c(t) C(x),  C = cos(pi x) cos(pi y) cos(pi z)   (in [0.5, 0.9])
//   eps u = g(t) W(x) + grad phi,     W divergence-free (as in test_fluid_mms.cpp),
//   phi = 0.2 c'(t) C / (3 pi^2)      so lap phi = -d(eps)/dt and d(eps)/dt + div(eps u) = 0
//   (phi = 0 for the runs without the d(eps)/dt term: then div(eps u) = 0),
//   p = g(t) P0 cos(pi x) sin(pi y) sin(pi z),
//   f = rho eps (du/dt + u.grad u) + s grad p - div(s mu grad u) + beta (u - v),  s = eps (A), 1 (B).
// The porosity goes in as element values at the centroids through
// FluidSolver::set_porosity, like the coupling's: dC/dn = 0 on the box faces,
// so the solver's lumped projection to the nodes is second-order there too.
// f is built by central differences of the closed-form u, eps, p (steps 1e-4
// in space and 1e-5 in time: errors ~1e-8, far below the discretization's).
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "manufactured.hpp"
#include "one_openmp_thread.hpp"

using namespace fdem;
using namespace fdem::fluid_verification;
using fdem::verification::record_value;

namespace {

constexpr double rho = 1.0, mu = 0.05, P0 = 0.5;  // Re ~ 20, as test_fluid_mms.cpp
constexpr double eps0 = 0.7, eps1 = 0.2;
constexpr double end_time = 0.5;

struct Manufactured {
  FluidModel model = FluidModel::vans_a;
  bool unsteady = false;
  bool rate_term = false;  // the solution carries d(eps)/dt (phi != 0)

  double g(double t) const { return unsteady ? std::cos(2.0 * t) : 1.0; }
  double c(double t) const { return unsteady ? std::cos(3.0 * t) : 1.0; }
  double dc(double t) const { return unsteady ? -3.0 * std::sin(3.0 * t) : 0.0; }

  static double shape_c(const Vec3& x) { return std::cos(pi * x.x()) * std::cos(pi * x.y()) * std::cos(pi * x.z()); }
  double eps(const Vec3& x, double t) const { return eps0 + eps1 * c(t) * shape_c(x); }
  double stress_weight(const Vec3& x, double t) const { return model == FluidModel::vans_a ? eps(x, t) : 1.0; }

  static Vec3 shape_w(const Vec3& x) { return divergence_free_shape(x); }
  Vec3 grad_phi(const Vec3& x, double t) const {
    if (!rate_term) return Vec3::Zero();
    const double sx = std::sin(pi * x.x()), sy = std::sin(pi * x.y()), sz = std::sin(pi * x.z());
    const double cx = std::cos(pi * x.x()), cy = std::cos(pi * x.y()), cz = std::cos(pi * x.z());
    return eps1 * dc(t) / (3.0 * pi * pi) * -pi * Vec3(sx * cy * cz, cx * sy * cz, cx * cy * sz);
  }
  Vec3 u(const Vec3& x, double t) const { return (g(t) * shape_w(x) + grad_phi(x, t)) / eps(x, t); }
  double p(const Vec3& x, double t) const {
    return g(t) * P0 * std::cos(pi * x.x()) * std::sin(pi * x.y()) * std::sin(pi * x.z());
  }
  static double beta(const Vec3& x) { return 3.0 * (1.0 + 0.5 * x.x() * x.y()); }  // beta/rho ~ 3 1/s
  static Vec3 grain_velocity(const Vec3& x) {
    return 0.2 * Vec3(std::sin(pi * x.y()), 0.0, std::cos(pi * x.x()));
  }

  Vec3 forcing(const Vec3& x, double t) const {
    constexpr double hx = 1e-4, ht = 1e-5;
    const Vec3 ux = u(x, t);
    const Vec3 du_dt = unsteady ? Vec3((u(x, t + ht) - u(x, t - ht)) / (2.0 * ht)) : Vec3(Vec3::Zero());
    Vec3 convection = Vec3::Zero(), viscous = Vec3::Zero(), grad_p = Vec3::Zero();
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = hx * Vec3::Unit(j);
      convection += ux[j] * (u(x + e, t) - u(x - e, t)) / (2.0 * hx);
      grad_p[j] = (p(x + e, t) - p(x - e, t)) / (2.0 * hx);
      // d/dx_j (s d u / dx_j) in flux form.
      viscous += (stress_weight(x + 0.5 * e, t) * (u(x + e, t) - ux) - stress_weight(x - 0.5 * e, t) * (ux - u(x - e, t))) /
                 (hx * hx);
    }
    return rho * eps(x, t) * (du_dt + convection) + stress_weight(x, t) * grad_p - mu * viscous +
           beta(x) * (ux - grain_velocity(x));
  }
};

std::vector<double> element_values(const BoxMesh& mesh, const std::function<double(const Vec3&)>& field) {
  std::vector<double> out(static_cast<std::size_t>(mesh.num_elements()));
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    Vec3 centroid = Vec3::Zero();
    for (Index a : mesh.element_nodes(e)) centroid += mesh.node(a) / 4.0;
    out[static_cast<std::size_t>(e)] = field(centroid);
  }
  return out;
}

std::vector<double> element_grain_velocities(const BoxMesh& mesh) {
  std::vector<double> out(3 * static_cast<std::size_t>(mesh.num_elements()));
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    Vec3 centroid = Vec3::Zero();
    for (Index a : mesh.element_nodes(e)) centroid += mesh.node(a) / 4.0;
    const Vec3 v = Manufactured::grain_velocity(centroid);
    for (int d = 0; d < 3; ++d) out[3 * static_cast<std::size_t>(e) + static_cast<std::size_t>(d)] = v[d];
  }
  return out;
}

// n^3 cells; steady: one step of dt = infinity; unsteady: n steps (dt = h/2) of
// BDF2 with the extrapolated linearization to t = 0.5 from the exact field.
Level run(const Manufactured& m, int n, bool solver_rate_term) {
  const BoxMesh mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), {n, n, n});
  Scene scene = no_slip_box_scene(rho, mu);
  scene.fluid.model = m.model;
  scene.fluid.porosity_time_derivative = solver_rate_term;
  scene.fluid.linearization = FluidLinearization::extrapolated;
  FluidSolver solver(mesh, scene);
  solver.set_boundary_velocity([&m](const Vec3& x, double t) { return m.u(x, t); });
  solver.set_momentum_exchange(element_values(mesh, Manufactured::beta), element_grain_velocities(mesh));
  const double t_end = m.unsteady ? end_time : 0.0;
  if (!m.unsteady) {
    solver.set_porosity(element_values(mesh, [&m](const Vec3& x) { return m.eps(x, 0.0); }));
    solver.set_body_force(nodal(mesh, [&m](const Vec3& x) { return m.forcing(x, 0.0); }));
    solver.step(std::numeric_limits<double>::infinity());
  } else {
    solver.set_porosity(element_values(mesh, [&m](const Vec3& x) { return m.eps(x, 0.0); }));
    solver.set_velocity(nodal(mesh, [&m](const Vec3& x) { return m.u(x, 0.0); }));
    for (int s = 1; s <= n; ++s) {
      const double t = end_time * s / n;
      solver.set_porosity(element_values(mesh, [&m, t](const Vec3& x) { return m.eps(x, t); }));
      solver.set_body_force(nodal(mesh, [&m, t](const Vec3& x) { return m.forcing(x, t); }));
      solver.step(end_time / n);
    }
  }
  return {n, l2_errors(solver, [&m, t_end](const Vec3& x) { return m.u(x, t_end); },
                       [&m, t_end](const Vec3& x) { return m.p(x, t_end); })};
}

struct Orders {
  double velocity, pressure, velocity_error, pressure_error;  // 8 -> 12 orders; relative errors at 12^3
};

Orders convergence_study(const std::string& name, const Manufactured& m, bool solver_rate_term) {
  std::vector<Level> levels;
  for (int n : {4, 8, 12}) levels.push_back(run(m, n, solver_rate_term));
  report_convergence(name, name, levels);
  const auto& c = levels[1];
  const auto& f = levels[2];
  const Orders o{order(c, f, &L2Errors::velocity), order(c, f, &L2Errors::pressure),
                 f.error.velocity / f.error.velocity_norm, f.error.pressure / f.error.pressure_norm};
  record_value("fluid.mms." + name + ".velocity_order", o.velocity);
  record_value("fluid.mms." + name + ".pressure_order", o.pressure);
  return o;
}

}  // namespace

// Asymptotic P1 orders as for the simplified model (test_fluid_mms.cpp):
// velocity 2, pressure >= 1. 1.8 and 1.0 are that test's bounds (its measured
// 8 -> 12 orders 1.92-1.95 and 1.45-1.85). Measured here, 8 -> 12 (4 -> 8):
//   model A steady        velocity 1.86 (1.62), pressure 2.20 (1.50), errors at 12^3 2.4e-2, 1.6e-1
//   model B steady        velocity 1.83 (1.62), pressure 1.94 (1.52), 2.4e-2, 1.2e-1
//   model A, d(eps)/dt    velocity 1.86 (1.61), pressure 2.00 (1.55), 2.5e-2, 9.4e-2
//   model B, no d(eps)/dt velocity 1.87 (1.65), pressure 2.30 (1.91), 2.4e-2, 4.2e-2
// The velocity is still approaching 2 from below (4 -> 8 gives 1.6), as the
// simplified model's does (1.78 -> 1.95); the porosity's element means in the
// inertia and viscous terms are second-order (fluid_element.hpp).
TEST(FluidVolumeAveragedManufactured, SteadyModelA_VelocityOrderNearTwoPressureAtLeastOne) {
  const Orders o = convergence_study("vans_a_steady", {.model = FluidModel::vans_a}, false);
  EXPECT_GT(o.velocity, 1.8);
  EXPECT_GT(o.pressure, 1.0);
}

TEST(FluidVolumeAveragedManufactured, SteadyModelB_VelocityOrderNearTwoPressureAtLeastOne) {
  const Orders o = convergence_study("vans_b_steady", {.model = FluidModel::vans_b}, false);
  EXPECT_GT(o.velocity, 1.8);
  EXPECT_GT(o.pressure, 1.0);
}

// A porosity changing in time with the d(eps)/dt term on, in the solution and
// in the solver (BDF2 rate of the nodal porosity).
TEST(FluidVolumeAveragedManufactured, UnsteadyModelAWithPorosityRate_VelocityOrderNearTwoPressureAtLeastOne) {
  const Orders o = convergence_study("vans_a_bdf2_rate", {.model = FluidModel::vans_a, .unsteady = true, .rate_term = true}, true);
  EXPECT_GT(o.velocity, 1.8);
  EXPECT_GT(o.pressure, 1.0);
}

// Porosity changing in time, d(eps)/dt off in both (div(eps u) = 0).
TEST(FluidVolumeAveragedManufactured, UnsteadyModelBWithoutPorosityRate_VelocityOrderNearTwoPressureAtLeastOne) {
  const Orders o = convergence_study("vans_b_bdf2_norate", {.model = FluidModel::vans_b, .unsteady = true, .rate_term = false}, false);
  EXPECT_GT(o.velocity, 1.8);
  EXPECT_GT(o.pressure, 1.0);
}

// The switch matters: the same solution with d(eps)/dt, solved without the
// term, stops converging (its continuity equation is another one): the
// error without it falls much slower from 8^3 to 12^3 than with it.
TEST(FluidVolumeAveragedManufactured, DroppingThePorosityRateStallsTheConvergence) {
  const Manufactured m{.model = FluidModel::vans_a, .unsteady = true, .rate_term = true};
  const Level with8 = run(m, 8, true), with12 = run(m, 12, true);
  const Level without8 = run(m, 8, false), without12 = run(m, 12, false);
  const double order_with = order(with8, with12, &L2Errors::velocity);
  const double order_without = order(without8, without12, &L2Errors::velocity);
  const double ratio = without12.error.velocity / with12.error.velocity;
  fmt::print("d(eps)/dt in the solution, velocity error 8^3 -> 12^3: with the term {:.3e} -> {:.3e} (order {:.2f}), "
             "without {:.3e} -> {:.3e} (order {:.2f}); without / with at 12^3: {:.2f}\n",
             with8.error.velocity, with12.error.velocity, order_with, without8.error.velocity,
             without12.error.velocity, order_without, ratio);
  record_value("fluid.mms.vans_a_rate_dropped.velocity_order", order_without);
  record_value("fluid.mms.vans_a_rate_dropped.error_ratio_n12", ratio);
  // Measured: with 1.86, without 0.39 (error 7.1e-2 -> 6.0e-2), 2.5x the error at 12^3.
  EXPECT_LT(order_without, order_with - 0.5);
}

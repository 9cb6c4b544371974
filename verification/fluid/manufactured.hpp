#pragma once
// What the manufactured-solution studies share (test_fluid_mms.cpp for the
// simplified model, test_fluid_vans_mms.cpp for the volume-averaged ones): the
// divergence-free shape of the velocity and the simplified model's
// manufactured flow, the no-slip unit box, the observed
// order between two refinements, the table and convergence.csv rows of a
// refinement study, and the report to $FDEM_RESULTS_DIR/fluid/ (ids in
// reference_data/fluid.csv). Each test executable includes it once.
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "../support/study_results.hpp"
#include "fluid_fixtures.hpp"

namespace fdem::fluid_verification {

// The test process's values and series go to the fluid study's results
// (verify_fluid_exact registers the same study). The PETSc build of a study
// (verify_fluid_*_petsc) checks the same gates and writes no results: the
// report shows the default solver's numbers.
#ifndef FDEM_FLUID_TEST_PETSC
[[maybe_unused]] inline const ::testing::Environment* const kFluidResults =
    verification::register_study_results("fluid");
#endif

/// U(x) = ( sin(pi x) [cos(pi y) - cos(pi z)], sin(pi y) [cos(pi z) - cos(pi x)],
///          sin(pi z) [cos(pi x) - cos(pi y)] ): divergence-free by
/// construction, lap U = -2 pi^2 U.
inline Vec3 divergence_free_shape(const Vec3& x) {
  const double sx = std::sin(pi * x.x()), sy = std::sin(pi * x.y()), sz = std::sin(pi * x.z());
  const double cx = std::cos(pi * x.x()), cy = std::cos(pi * x.y()), cz = std::cos(pi * x.z());
  return Vec3(sx * (cy - cz), sy * (cz - cx), sz * (cx - cy));
}

/// (d U_i / d x_j) of divergence_free_shape.
inline Eigen::Matrix3d divergence_free_shape_gradient(const Vec3& x) {
  const double sx = std::sin(pi * x.x()), sy = std::sin(pi * x.y()), sz = std::sin(pi * x.z());
  const double cx = std::cos(pi * x.x()), cy = std::cos(pi * x.y()), cz = std::cos(pi * x.z());
  Eigen::Matrix3d g;
  g << pi * cx * (cy - cz), -pi * sx * sy, pi * sx * sz,   //
      pi * sy * sx, pi * cy * (cz - cx), -pi * sy * sz,    //
      -pi * sz * sx, pi * sz * sy, pi * cz * (cx - cy);
  return g;
}

/// The simplified model's manufactured flow u = g(t) U(x), p = g(t) P(x),
/// U = divergence_free_shape, P = P0 cos(pi x) sin(pi y) sin(pi z), in a
/// fluid of density rho and viscosity mu: the body force that makes it exact
/// (test_fluid_mms.cpp with g = 1 and g = cos t, test_fluid_projection.cpp
/// with g = sin t).
struct ManufacturedFlow {
  double rho, mu, P0;

  double shape_p(const Vec3& x) const { return P0 * std::cos(pi * x.x()) * std::sin(pi * x.y()) * std::sin(pi * x.z()); }
  Vec3 shape_grad_p(const Vec3& x) const {
    const double sx = std::sin(pi * x.x()), sy = std::sin(pi * x.y()), sz = std::sin(pi * x.z());
    const double cx = std::cos(pi * x.x()), cy = std::cos(pi * x.y()), cz = std::cos(pi * x.z());
    return P0 * pi * Vec3(-sx * sy * sz, cx * cy * sz, cx * sy * cz);
  }
  /// rho (du/dt + u . grad u) + grad p - mu lap u at x, for g = g(t), dg = g'(t).
  Vec3 forcing(const Vec3& x, double g, double dg) const {
    const Vec3 U = divergence_free_shape(x);
    return rho * (dg * U + g * g * divergence_free_shape_gradient(x) * U) + g * shape_grad_p(x) +
           2.0 * pi * pi * mu * g * U;
  }
};

/// The unit cube with the exact velocity imposed on all six faces.
inline Scene no_slip_box_scene(double density, double viscosity) {
  using FC = FaceCondition;
  return scene_with({FC::no_slip, FC::no_slip, FC::no_slip, FC::no_slip, FC::no_slip, FC::no_slip}, density,
                    viscosity);
}

/// Observed order between meshes of n_coarse and n_fine cells a side.
inline double observed_order(double e_coarse, double e_fine, int n_coarse, int n_fine) {
  return std::log(e_coarse / e_fine) / std::log(static_cast<double>(n_fine) / n_coarse);
}

/// One refinement: n^3 cells, the L2 errors, and |div u_h| / |grad u_h|
/// (negative: not measured).
struct Level {
  int cells;
  L2Errors error;
  double divergence_relative = -1.0;
};

inline double order(const Level& coarse, const Level& fine, double L2Errors::*field) {
  return observed_order(coarse.error.*field, fine.error.*field, coarse.cells, fine.cells);
}

/// Prints the refinement table (relative L2 errors, orders, the divergence
/// where measured) and writes one convergence.csv row per level and field
/// (h = 1/cells; expected orders: velocity 2, pressure 1).
inline void report_convergence(const std::string& title, const std::string& name, const std::vector<Level>& levels) {
  const bool divergence = !levels.empty() && levels.front().divergence_relative >= 0.0;
  fmt::print("{}\n  cells  |u-uh|/|u|   order   |p-ph|/|p|   order{}\n", title,
             divergence ? "   |div uh|/|grad uh|" : "");
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Level& l = levels[i];
    const double eu = l.error.velocity / l.error.velocity_norm, ep = l.error.pressure / l.error.pressure_norm;
    const std::string orders_u = i == 0 ? "     -" : fmt::format("{:6.2f}", order(levels[i - 1], l, &L2Errors::velocity));
    const std::string orders_p = i == 0 ? "     -" : fmt::format("{:6.2f}", order(levels[i - 1], l, &L2Errors::pressure));
    fmt::print("  {:5d}  {:.3e}  {}    {:.3e}  {}{}\n", l.cells, eu, orders_u, ep, orders_p,
               divergence ? fmt::format("    {:.3e}", l.divergence_relative) : "");
    for (const auto& [quantity, error, expected] :
         {std::tuple{"velocity", eu, 2.0}, std::tuple{"pressure", ep, 1.0}})
      verification::record_series_row("fluid", "convergence.csv", fmt::format("{}_{}_{:03d}", name, quantity, l.cells),
                                      {"case", "quantity", "h_m", "error", "expected_order"},
                                      {name, quantity, fmt::format("{}", 1.0 / l.cells), fmt::format("{}", error),
                                       fmt::format("{}", expected)});
  }
}

}  // namespace fdem::fluid_verification

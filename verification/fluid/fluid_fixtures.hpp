#pragma once
// Shared set-up for the fluid verification cases: scenes, exact solutions and
// error norms on the 5-tetrahedra box mesh.
// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's AVX-512 code
// (see fluid/fluid_solver.cpp); off from here to the end of the case's file,
// which reaches Eigen only through this header.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fluid/fluid_solver.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem::fluid_verification {

inline Scene scene_with(const std::array<FaceCondition, 6>& faces, double density, double viscosity,
                        TimeScheme scheme = TimeScheme::bdf2) {
  Scene scene;
  scene.fluid.density = density;
  scene.fluid.viscosity = viscosity;
  scene.fluid.time_scheme = scheme;
  for (std::size_t f = 0; f < 6; ++f) scene.fluid.faces[f].condition = faces[f];
  // Linear solves 100x tighter than the Picard test, so that Picard's change is
  // not Krylov noise; both far below the discretization errors measured here.
  scene.fluid.linear_tolerance = 1e-11;
  scene.fluid.max_linear_iterations = 2000;
  scene.fluid.max_picard_iterations = 30;
  scene.fluid.picard_tolerance = 1e-9;
  return scene;
}

// The linear solvers under test. Each case file is compiled twice: as itself
// (Eigen: BiCGSTAB + ILUT, or SparseLU where a case asks for a direct solve)
// and with FDEM_FLUID_TEST_PETSC (verify_fluid_*_petsc): PETSc's KSP with its
// default preconditioner (fluid/petsc_linear_solver.hpp), or PETSc's MUMPS LU
// for the direct solves, through the same MPIAIJ matrix path.
inline FluidSolver tested_solver(const BoxMesh& mesh, const Scene& scene) {
#ifdef FDEM_FLUID_TEST_PETSC
  return FluidSolver(mesh, scene, {.linear_solver = FluidLinearSolver::petsc});
#else
  return FluidSolver(mesh, scene, {.linear_solver = FluidLinearSolver::bicgstab_ilut});
#endif
}

inline FluidSolver direct_solver(const BoxMesh& mesh, Scene scene) {
#ifdef FDEM_FLUID_TEST_PETSC
  scene.fluid.petsc_options = "-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps";
  return FluidSolver(mesh, scene, {.linear_solver = FluidLinearSolver::petsc});
#else
  return FluidSolver(mesh, scene, {.linear_solver = FluidLinearSolver::sparse_lu});
#endif
}

/// Nodal values of a vector field, node-major.
inline std::vector<double> nodal(const BoxMesh& mesh, const std::function<Vec3(const Vec3&)>& field) {
  std::vector<double> out(3 * static_cast<std::size_t>(mesh.num_nodes()));
  for (Index n = 0; n < mesh.num_nodes(); ++n) {
    const Vec3 v = field(mesh.node(n));
    for (std::size_t d = 0; d < 3; ++d) out[3 * static_cast<std::size_t>(n) + d] = v[static_cast<Eigen::Index>(d)];
  }
  return out;
}

inline Vec3 nodal_velocity(std::span<const double> u, Index n) {
  const auto s = 3 * static_cast<std::size_t>(n);
  return Vec3(u[s], u[s + 1], u[s + 2]);
}

/// The largest nodal velocity component error against an exact field [m/s].
inline double max_velocity_error(const FluidSolver& solver, const std::function<Vec3(const Vec3&)>& exact) {
  double worst = 0.0;
  for (Index n = 0; n < solver.mesh().num_nodes(); ++n)
    worst = std::max(worst, (nodal_velocity(solver.velocity(), n) - exact(solver.mesh().node(n))).cwiseAbs().maxCoeff());
  return worst;
}

// Degree-2 four-point rule on a tetrahedron (volume coordinates, weights 1/4):
// exact for quadratics, so the squared error of a P1 field against a smooth
// one converges at the same order as the error itself.
inline constexpr double quad_a = 0.5854101966249685, quad_b = 0.1381966011250105;

struct L2Errors {
  double velocity = 0.0;   // ||u_h - u||_L2
  double pressure = 0.0;   // ||(p_h - mean) - (p - mean)||_L2
  double velocity_norm = 0.0, pressure_norm = 0.0;  // ||u||, ||p - mean|| of the exact solution
};

inline L2Errors l2_errors(const FluidSolver& solver, const std::function<Vec3(const Vec3&)>& u_exact,
                          const std::function<double(const Vec3&)>& p_exact) {
  const BoxMesh& mesh = solver.mesh();
  const auto u = solver.velocity();
  const auto p = solver.pressure();
  // Means of p_h and p over the domain, then the L2 norms of the differences.
  double volume = 0.0, mean_h = 0.0, mean_exact = 0.0;
  auto for_each_point = [&](auto&& visit) {
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto& nodes = mesh.element_nodes(e);
      const double w = mesh.element_volume(e) / 4.0;
      for (int q = 0; q < 4; ++q) {
        Eigen::Vector4d lambda = Eigen::Vector4d::Constant(quad_b);
        lambda[q] = quad_a;
        Vec3 x = Vec3::Zero(), uh = Vec3::Zero();
        double ph = 0.0;
        for (std::size_t a = 0; a < 4; ++a) {
          const double l = lambda[static_cast<Eigen::Index>(a)];
          x += l * mesh.node(nodes[a]);
          uh += l * nodal_velocity(u, nodes[a]);
          ph += l * p[static_cast<std::size_t>(nodes[a])];
        }
        visit(w, x, uh, ph);
      }
    }
  };
  for_each_point([&](double w, const Vec3& x, const Vec3&, double ph) {
    volume += w;
    mean_h += w * ph;
    mean_exact += w * p_exact(x);
  });
  mean_h /= volume;
  mean_exact /= volume;
  L2Errors err;
  for_each_point([&](double w, const Vec3& x, const Vec3& uh, double ph) {
    const Vec3 ue = u_exact(x);
    const double pe = p_exact(x) - mean_exact;
    err.velocity += w * (uh - ue).squaredNorm();
    err.pressure += w * (ph - mean_h - pe) * (ph - mean_h - pe);
    err.velocity_norm += w * ue.squaredNorm();
    err.pressure_norm += w * pe * pe;
  });
  err.velocity = std::sqrt(err.velocity);
  err.pressure = std::sqrt(err.pressure);
  err.velocity_norm = std::sqrt(err.velocity_norm);
  err.pressure_norm = std::sqrt(err.pressure_norm);
  return err;
}

}  // namespace fdem::fluid_verification

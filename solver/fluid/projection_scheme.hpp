#pragma once
// The segregated alternative to the monolithic SUPG/PSPG solve (scene
// fluid.scheme: projection): an incremental pressure-correction step in
// rotational form (Timmermans, Minev & van de Vosse 1996; Guermond, Minev &
// Shen 2006, Comput. Methods Appl. Mech. Engrg. 195, Sect. 3.3), BDF1/BDF2
// with the monolithic scheme's coefficients and extrapolated advection,
// P1 velocity and pressure on the same tetrahedra. Per step (u* the
// extrapolated advecting velocity, p^n the last pressure):
//
//   1. predictor, one scalar convection-diffusion matrix for the three components,
//        rho (alpha0 u~ - u_hist) / dt + rho u*.grad u~ + rho/2 (div u*) u~ - mu lap u~
//          + beta (u~ - v) = f - grad p^n,      u~ = g on prescribed components,
//      with SUPG on the convection (tau_M of fluid_element.hpp, h one per
//      cell) and the momentum exchange beta lumped as in the monolithic
//      scheme. No LSIC, no PSPG: the projection carries the continuity.
//   2. projection: (grad q, grad phi) = -(rho alpha0 / dt) (q, div u~), natural
//      (dphi/dn = 0) on walls and inlets, phi = 0 on outlet nodes; a closed
//      domain pins phi at the monolithic scheme's pressure node. The matrix is
//      the P1 Laplacian, constant: factored once (sparse Cholesky, Eigen's
//      SimplicialLDLT) and reused by every step.
//   3. correction: u^{n+1} = u~ - dt / (rho alpha0) grad phi, grad phi taken to
//      the nodes by the lumped L2 projection (volume-weighted mean of the
//      element gradients); prescribed components keep their values.
//      p^{n+1} = p^n + phi - mu div u~ (the rotational term, div u~ lumped the
//      same way); a closed domain's pressure is shifted back to 0 at its node.
//
// Splitting error: velocity O(dt^2), pressure O(dt^1.5) in L2 for BDF2
// (Guermond et al. 2006, Thm. 3.3); u^{n+1} is divergence-free only weakly
// (the nodal correction is an approximate projection). Only the simplified
// model (Eq. 21-22), only a time-dependent solve, only one MPI rank: the
// scene loader and FluidSolver refuse the rest.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "fluid/fluid_boundary.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct ProjectionStepInput {
  double dt = 0.0;      // [s], finite
  double alpha0 = 1.0;  // BDF leading coefficient
  std::span<const double> advecting;       // 3 * nodes: u* [m/s]
  std::span<const double> history;         // 3 * nodes: u_hist = -(alpha1 u^n + alpha2 u^{n-1}) [m/s]
  std::span<const double> body_force;      // 3 * nodes: f [N/m^3]
  std::span<const double> prescribed;      // 4 * nodes (u, v, w, p interleaved): prescribed values at the new level
  std::span<const double> exchange_beta;   // elements, or empty: beta [kg/(m^3 s)]
  std::span<const double> exchange_velocity;  // 3 * elements, or empty: v [m/s]
  double linear_tolerance = 1e-8;          // relative residual of each predictor solve
  int max_linear_iterations = 1000;
};

struct ProjectionStepResult {
  int predictor_iterations = 0;   // BiCGSTAB iterations, summed over the components
  double predictor_residual = 0.0;  // the largest relative residual of the component solves
  double assembly_seconds = 0.0;
  double solve_seconds = 0.0;     // predictor solves, the Poisson solve and the correction
};

class ProjectionScheme {
 public:
  /// Builds the predictor's pattern and factors the pressure Laplacian.
  /// Throws SolverError when the factorization fails.
  ProjectionScheme(const BoxMesh& mesh, const FluidSpec& spec, const FluidConstraints& constraints);

  /// One step: `velocity` (3 * nodes) receives u^{n+1}, `pressure` (nodes)
  /// holds p^n on entry and p^{n+1} on return. Throws SolverError (step
  /// number, component, iterations, residual) when a predictor solve does not
  /// reach the tolerance or the velocity is not finite.
  ProjectionStepResult step(const ProjectionStepInput& in, int step_number, std::span<double> velocity,
                            std::span<double> pressure);

 private:
  using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  void assemble(const ProjectionStepInput& in, std::span<const double> pressure);

  const BoxMesh& mesh_;
  double density_ = 0.0, viscosity_ = 0.0, h_ = 0.0;
  Index num_nodes_ = 0;
  std::vector<std::uint8_t> velocity_fixed_;  // 3 * nodes
  // Components with the same prescribed set share one matrix: matrix_of_[d].
  std::array<int, 3> matrix_of_{0, 0, 0};
  RowMatrix predictor_;                        // unconstrained, assembled each step
  std::array<RowMatrix, 3> constrained_;       // prescribed rows made identity rows
  std::vector<std::array<int, 16>> entry_;     // element -> positions of its 4x4 block in predictor_'s values
  Eigen::VectorXd rhs_[3];
  std::vector<double> node_volume_;            // sum of V_e / 4 around the node
  std::vector<std::uint8_t> phi_fixed_;        // nodes: phi = 0 (outlet nodes, or the pinned node)
  Index pressure_node_ = -1;                   // closed domain: the pressure gauge node
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> poisson_;
};

}  // namespace fdem

#pragma once
// Incompressible Navier-Stokes on the 5-tetrahedra box mesh (paper Sect. 2.2, Eq. 21-22):
// equal-order P1 velocity and pressure, SUPG/PSPG + LSIC (grad-div) stabilization,
// implicit BDF1/BDF2 in time, Picard or extrapolated (semi-implicit) linearization,
// one monolithic sparse system per Picard iteration (per step when extrapolated)
// solved with BiCGSTAB + ILUT (or a sparse LU for small meshes), or with PETSc
// (scene fluid.solver.linear_solver: petsc; fluid/petsc_linear_solver.hpp).
//
//   rho (du/dt + u.grad u) = -grad p + mu lap u + f,   div u = 0          (Eq. 21-22)
//
// p is the DYNAMIC pressure: gravity is not part of the fluid solve, because rho g
// is balanced by the hydrostatic pressure. f is the nodal body force density
// [N/m^3] given by set_body_force (the particle source term -F/eps of Eq. 22).
//
// scene fluid.model = vans_a / vans_b: the volume-averaged Eq. 18-19 (weak form
// and stabilization in fluid/fluid_element.hpp), with the porosity of
// set_porosity and an implicit momentum exchange set_momentum_exchange:
//   rho eps (du/dt + u.grad u) = -s grad p + div(s mu grad u) + f - beta (u - v),
//   [d(eps)/dt] + div(eps u) = 0,     s = eps (model A), 1 (model B).
// Gravity with the dynamic pressure: model A's -eps grad P + eps rho g =
// -eps grad p (P = p + rho g.x, the full pressure), so no gravity term is
// needed in the fluid; model B's -grad P + eps rho g = -grad p - (1 - eps) rho g,
// the -(1 - eps) rho g cancelling against the hydrostatic part of the grains'
// pressure-gradient reaction when the coupling leaves that part (the grains'
// buoyancy of Eq. 5) out of f: pass only the dynamic-pressure forces.
//
// Unknowns are interleaved per node (u, v, w, p), node-major; velocity() and
// pressure() expose them as 3*num_nodes and num_nodes arrays.
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>

#include <Eigen/Core>

#include "core/types.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// What one time step cost and how well it converged.
struct FluidStepReport {
  int picard_iterations = 0;       // nonlinear iterations taken (linear solves; 1 when extrapolated)
  int linear_iterations = 0;       // Krylov iterations summed over the Picard iterations
  double linear_residual = 0.0;    // relative residual |b - A x| / |b| of the last linear solve
                                   // (of the row/column-equilibrated system the Krylov solver sees)
  double picard_change = 0.0;      // last relative velocity update |du| / |u| (0 for a converged zero field)
  bool picard_converged = false;   // picard_change <= scene picard_tolerance within max_picard_iterations
                                   // (always true for the extrapolated linearization: nothing to converge)
  double divergence_l2 = 0.0;      // ||div u||_L2(domain) [m^1.5/s], sqrt(sum_e V_e (div u_e)^2)
  double divergence_relative = 0.0;  // ||div u||_L2 / ||grad u||_L2, dimensionless (0 when u = 0)
                                     // (both 0 unless FluidSolverOptions::report_divergence)
  int preconditioner_factorizations = 0;  // ILUT factorizations this step (0: reused the last one)
  double time_s = 0.0;             // simulated time after the step [s]
  double assembly_seconds = 0.0;   // wall time spent assembling (all Picard iterations)
  double solve_seconds = 0.0;      // wall time spent in preconditioner set-up and linear solves
};

enum class FluidLinearSolver {
  bicgstab_ilut,  // BiCGSTAB preconditioned by incomplete LU with threshold (Eigen)
  sparse_lu,      // direct Eigen::SparseLU: reference and fallback for small meshes
  petsc,          // PETSc KSP on an MPIAIJ matrix (fluid/petsc_linear_solver.hpp), scene petsc_options
};

/// Numerical settings that are not part of a scene (the scene holds tolerances).
struct FluidSolverOptions {
  // Unset: the scene's fluid.solver.linear_solver.
  std::optional<FluidLinearSolver> linear_solver = std::nullopt;
  // IncompleteLUT droptol and fillfactor. Measured (extrapolated, tolerance 1e-8,
  // median CPU per step, plume / settling / channel): 1e-2 x 4: 44 / 42 / 18 ms
  // (28 / 27 / 16 Krylov); 1e-2 x 2: 50 / 46 / 19 ms; 3e-2 x 2: 51 / 47 / 21 ms;
  // 1e-3 x 5: 87 / 55 / 21 ms (fewer iterations, dearer factors). A direct
  // SparseLU factored every step costs ~1.5 s on the plume mesh.
  double ilut_drop_tolerance = 1e-2;
  int ilut_fill_factor = 4;
  // Keep the ILUT factors between Picard iterations and time steps while the
  // Krylov solver converges in fewer than this many iterations; refactor after.
  int refactor_above_iterations = 40;
  // The same for the PETSc preconditioner (BoomerAMG set-up): rebuild once a
  // solve takes more than this many Krylov iterations.
  int petsc_rebuild_above_iterations = 40;
  // Fill FluidStepReport::divergence_l2 / divergence_relative (a pass over
  // the elements after every step: 0.6 ms of the settling scene's 19 ms
  // step, benchmarks/README.md). The coupled run reads neither and turns it off.
  bool report_divergence = true;
};

class FluidSolver {
 public:
  /// Boundary conditions, density, viscosity, time scheme and tolerances come
  /// from scene.fluid. The fluid starts at rest, time 0, zero body force.
  FluidSolver(const BoxMesh& mesh, const Scene& scene, FluidSolverOptions options = {});
  ~FluidSolver();
  FluidSolver(const FluidSolver&) = delete;
  FluidSolver& operator=(const FluidSolver&) = delete;
  FluidSolver(FluidSolver&&) noexcept;
  FluidSolver& operator=(FluidSolver&&) noexcept;

  /// 3*num_nodes, node-major (n*3+d): body force per unit volume [N/m^3] added
  /// to the momentum equation, held until changed; it acts at the new time level
  /// of the next step(). Interpolated with P1 shape functions (consistent load).
  void set_body_force(std::span<const double> nodal_force_density);

  /// num_elements values: the porosity eps_e (fluid volume fraction, in (0, 1])
  /// of each element at the NEW time level of the next step(); held until
  /// changed. The solver keeps the values of the last two steps for the
  /// d(eps)/dt of Eq. 18 (the first call starts that history at the given
  /// values, so the first rate is zero). Never set: eps = 1. The volume-averaged
  /// models use the P1 field whose nodal value is the volume-weighted mean of
  /// the elements around the node (the lumped L2 projection: it keeps
  /// sum_e V_e eps_e); the simplified model stores it and ignores it (its
  /// results are bitwise those of a solver that never got a porosity).
  /// Throws SolverError on a wrong size or a value outside (0, 1].
  void set_porosity(std::span<const double> element_porosity);

  /// Semi-implicit momentum exchange, any model: num_elements coefficients
  /// beta_e [kg/(m^3 s)] (force per unit TOTAL volume per unit velocity) and
  /// 3 * num_elements mean grain velocities v_e [m/s] (element-major, e*3+d).
  /// The momentum equation gets -beta_e (u^{n+1} - v_e): beta_e u^{n+1} in the
  /// matrix as a LUMPED mass-like term (beta_e V_e / 4 on each of the element's
  /// nodes: positive diagonal, so the system stays solvable for any beta dt /
  /// rho), beta_e v_e on the right-hand side; beta_e also enters tau_M. The
  /// force the fluid receives from element e over the step is therefore
  /// exactly -beta_e V_e (mean of its 4 nodal u^{n+1} - v_e). Held until changed;
  /// two empty spans switch it off. The coefficient is used as given (model A:
  /// the drag's beta; the simplified model's Eq. 22 and model B divide the
  /// grains' force by eps: the caller passes beta / eps). Throws SolverError
  /// on wrong sizes or a negative or non-finite beta.
  void set_momentum_exchange(std::span<const double> element_beta, std::span<const double> element_particle_velocity);

  /// Gradient of the P1 pressure in an element (constant there) [Pa/m]: the
  /// DYNAMIC pressure's (buoyancy of Eq. 5 stays as it is); model A's grains take it
  /// shared out as the porosity scheme shares their solid (coupling/fluid_stress_force.hpp).
  Vec3 pressure_gradient(Index element) const;

  /// One implicit step of dt [s]: BDF1 for the first step (and after
  /// set_velocity), then the scene's scheme (variable-step BDF2 coefficients if
  /// dt changes). dt = +infinity solves the steady equations (BDF1, no mass term).
  /// The advecting velocity is extrapolated from u^n, u^{n-1} (u^n for BDF1);
  /// it is also the initial guess of the Krylov solve (with p^n).
  /// scene fluid.linearization = extrapolated: ONE linear solve with it (the
  /// semi-implicit BDF scheme; report.picard_iterations = 1, picard_converged =
  /// true, picard_change = |u^{n+1} - u*| / |u^{n+1}|, the extrapolation defect).
  /// picard (and any steady solve): iterate until |du|/|u| <= scene
  /// picard_tolerance or max_picard_iterations (then report.picard_converged = false). Throws fdem::SolverError naming the
  /// step, the iteration count and the residual when a linear solve does not
  /// reach scene linear_tolerance in max_linear_iterations (after one retry
  /// with a fresh preconditioner), on a non-finite velocity, or when Picard
  /// diverges (relative update still > 1 after max_picard_iterations).
  FluidStepReport step(double dt);

  std::span<const double> velocity() const;  // 3*num_nodes, node-major [m/s]
  std::span<const double> pressure() const;  // num_nodes, dynamic pressure [Pa]

  /// P1 interpolation of the velocity in an element at volume coordinates
  /// (Eq. 28-31, e.g. BoxMesh::volume_coordinates).
  Vec3 velocity_at(Index element, const Eigen::Vector4d& volume_coordinates) const;

  double time() const;  // simulated time [s]
  int step_count() const;
  const BoxMesh& mesh() const;

  /// Initial condition: 3*num_nodes node-major velocity [m/s]. Resets the
  /// BDF history, so the next step is BDF1. Constrained components are
  /// overwritten by their boundary values at the next step.
  void set_velocity(std::span<const double> nodal_velocity);
  void set_time(double time_s);

  /// Replace the value prescribed on every node whose velocity is fully
  /// prescribed (no_slip faces; inlet faces) by field(x, t) evaluated at the new
  /// time level. Free-slip normal components stay zero. For manufactured
  /// solutions and moving walls (Couette); an empty function restores the scene's.
  /// Called from OpenMP threads: it must be thread-safe (pure functions are).
  using BoundaryVelocity = std::function<Vec3(const Vec3& x_m, double time_s)>;
  void set_boundary_velocity(BoundaryVelocity field);

  /// Sets the velocity of an inlet face (scene fluid.boundaries) from the
  /// next step on, as if the scene had said it: a study driver raises or
  /// lowers a fluidized bed's inflow between stages. The face's other data
  /// (inlet_above_m) and every other face stay. Not part of a checkpoint
  /// (save_state): a restart takes the scene's value. Throws SolverError
  /// when the face is not an inlet or the velocity is not finite.
  void set_inlet_velocity(BoxFace face, const Vec3& velocity_m_s);

  /// Node whose pressure is 0 when no face is an outlet (the level of a closed
  /// domain's pressure: pinned there, or for PETSc's Krylov solves the
  /// null-space solution shifted to it), else -1.
  Index pressure_reference_node() const;

  /// ||div u||_L2 of the current velocity [m^1.5/s].
  double divergence_l2() const;

  /// Assembles (without solving) the system step(dt) would assemble first, at
  /// the current state; returns the wall time [s]. For benchmarks.
  double assemble_only(double dt);

  /// Checkpoint: the exact state, binary doubles: u^n, u^{n-1},
  /// the pressure history, the last solution (the next solve's initial
  /// guess), the body force, time, step count, the BDF2 start state (steps
  /// since the last reset, previous dt), the porosity and its history, the
  /// momentum exchange (format version 2; version 1 loads with eps = 1 and no
  /// exchange). Not saved: options, the boundary
  /// field of set_boundary_velocity (set it again), the mesh (load_state
  /// refuses a state of another node count).
  /// A checkpoint is a refactor point: the ILUT preconditioner is reused
  /// across steps and refactored only when a solve gets slow, so save_state
  /// (const for the physical state) and load_state both mark it for
  /// refactoring at the next step. A run that wrote a checkpoint and a run
  /// restarted from it then use the same preconditioner from that step on:
  /// their results are equal bit for bit (same thread count); against a run
  /// that wrote no checkpoint they are equal to the linear solver tolerance.
  /// load_state throws SolverError on a short, corrupt or mismatched stream
  /// and then leaves the solver unchanged.
  void save_state(std::ostream& out) const;
  void load_state(std::istream& in);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fdem

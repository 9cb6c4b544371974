#pragma once
// A sparse linear solve with PETSc's KSP: the matrix is an MPIAIJ, the
// preconditioner and Krylov method come from PETSc's options database:
// petsc_default_options, then the caller's options string over them (PETSc's
// own syntax, for experts).
//
// On several MPI ranks every rank holds the whole system's pattern (the run
// is replicated, core/petsc_runtime.hpp) but fills and hands PETSc only its
// own block of rows: whole nodes, rank r owning nodes [r N / R, (r + 1) N / R)
// (owned_node_range). The solve is shared, and every rank gets the whole
// solution back. On one process the
// block is the whole system.
//
// The unknowns are interleaved per node in blocks of block_size, the last of
// each block a pressure: for PCFIELDSPLIT the solver defines the splits "u"
// (all but the last) and "p" (the last), so options address them as
// -fieldsplit_u_... and -fieldsplit_p_....
//
// Convergence: the Krylov residual norm (the true, unpreconditioned one for
// the default FGMRES: right preconditioning) below tolerance * |b|, the same
// test as Eigen's BiCGSTAB; the scene's tolerance and iteration cap override
// -ksp_rtol, -ksp_atol and -ksp_max_it.
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "core/types.hpp"

namespace fdem {

/// Defaults measured on the fluid's stabilized P1/P1 systems (benchmarks/README.md,
/// "Fluid linear solver"): FGMRES (right-preconditioned, so the tested residual
/// is the true one) with an upper block-triangular Schur complement
/// preconditioner: BoomerAMG on the velocity block; for the pressure,
/// KSPRICHARDSON with 2 iterations and BoomerAMG on A_pp ("a11": the PSPG
/// pressure Laplacian, a one-ring stencil), which PETSc runs as two BoomerAMG
/// V-cycles on A_pp (PCApplyRichardson: hypre's own iterations on the
/// preconditioning matrix), not as Richardson on the Schur complement: no S
/// product is made (-log_view, benchmarks/README.md, "Where the settling
/// scene's fluid step goes"; real Richardson on S, forced with a monitor,
/// cost 1.54x the run for 1 % fewer iterations). "selfp"
/// (A_pp - A_pu diag(A_uu)^-1 A_up, the former default) has a two-ring
/// stencil whose V-cycle cost twice as much per iteration (0.49-0.54x the
/// CPU a step at 4e4-1e5 tetrahedra, 15-18 Krylov iterations against 21-24).
/// BoomerAMG with the usual 3D settings (strong threshold 0.7, HMIS
/// coarsening, ext+i interpolation, P_max 4, one level of aggressive
/// coarsening): with hypre's defaults the coarse levels grow dense and a step
/// cost 1.6x more. The pressure block's strong threshold is 0.5, not 0.7:
/// 0.93-0.97x the CPU a step on the 8.6e3-1.03e6 tetrahedra cubes, Krylov
/// 12.0 / 12.6 / 16 / 17 against 12.4 / 13.6 / 17 / 19 at 8.6e3 / 9.8e4 /
/// 3.2e5 / 1.03e6 (2026-12-03, benchmarks/README.md, "Where the Krylov growth
/// with N comes from"; measured with the pressure block scaled node by node).
/// Since the fluid scales its pressure block as a whole (FluidSolver's
/// equilibration; "Pressure block scaled as a whole") the counts are 6.4 /
/// 6.6 / 7.0 / 7.0, and threshold 0.25 / 0.7, PMIS, no aggressive coarsening,
/// one V-cycle or SOR on the velocity block were no better in CPU a step
/// ("Pressure AMG options after the scaling fix").
inline constexpr std::string_view petsc_default_options =
    "-ksp_type fgmres -ksp_gmres_restart 100 "
    "-pc_type fieldsplit -pc_fieldsplit_type schur -pc_fieldsplit_schur_fact_type upper "
    "-pc_fieldsplit_schur_precondition a11 "
    "-fieldsplit_u_ksp_type preonly -fieldsplit_u_pc_type hypre -fieldsplit_u_pc_hypre_type boomeramg "
    "-fieldsplit_u_pc_hypre_boomeramg_strong_threshold 0.7 -fieldsplit_u_pc_hypre_boomeramg_coarsen_type HMIS "
    "-fieldsplit_u_pc_hypre_boomeramg_interp_type ext+i -fieldsplit_u_pc_hypre_boomeramg_P_max 4 "
    "-fieldsplit_u_pc_hypre_boomeramg_agg_nl 1 "
    "-fieldsplit_p_ksp_type richardson -fieldsplit_p_ksp_max_it 2 "
    "-fieldsplit_p_pc_type hypre -fieldsplit_p_pc_hypre_type boomeramg "
    "-fieldsplit_p_pc_hypre_boomeramg_strong_threshold 0.5 -fieldsplit_p_pc_hypre_boomeramg_coarsen_type HMIS "
    "-fieldsplit_p_pc_hypre_boomeramg_interp_type ext+i -fieldsplit_p_pc_hypre_boomeramg_P_max 4 "
    "-fieldsplit_p_pc_hypre_boomeramg_agg_nl 1";

struct PetscLinearSolveResult {
  int iterations = 0;
  double relative_residual = 0.0;  // |b - A x| / |b| after the solve (true residual, computed)
  bool converged = false;          // KSP reached tolerance * |b| in the cap, true residual within 2x that
  std::string reason;              // PETSc's KSPConvergedReason, e.g. CONVERGED_ATOL, DIVERGED_ITS
};

class PetscLinearSolver {
 public:
  /// options: extra PETSc options ("-pc_type fieldsplit ..."), parsed now;
  /// block_size: unknowns per node (interleaved). Initialises PETSc on first use.
  /// Throws SolverError on an unparsable options string.
  PetscLinearSolver(std::string_view options, int block_size);
  ~PetscLinearSolver();
  PetscLinearSolver(const PetscLinearSolver&) = delete;
  PetscLinearSolver& operator=(const PetscLinearSolver&) = delete;

  /// The whole square system as CSR, its pattern the same on every rank:
  /// row_start (rows + 1 offsets), columns (increasing in each row), values
  /// (read in this rank's rows only); this rank passes its own rows to PETSc. The first call fixes the pattern; later
  /// calls must pass the same pattern with new values.
  void set_matrix(std::span<const int> row_start, std::span<const int> columns, std::span<const double> values);

  /// The next solve rebuilds the preconditioner from the current matrix
  /// (otherwise it reuses the last one; the first solve always builds it).
  void request_preconditioner_setup();

  /// Solves A x = b; rhs and solution are whole vectors (rhs read in this
  /// rank's rows only), solution holds the initial guess on entry (the same
  /// on every rank) and the whole solution on every rank after. Never throws for non-convergence (see result.converged).
  PetscLinearSolveResult solve(std::span<const double> rhs, std::span<double> solution, double tolerance,
                               int max_iterations);

  /// Whether set_null_space may be used with these options: not for a direct
  /// solve (-ksp_type preonly: a factorisation, which needs a nonsingular
  /// matrix). PCFIELDSPLIT needs set_null_space's preconditioner_pin_row:
  /// with BoomerAMG on the singular pressure block itself, the steady
  /// manufactured solution (12^3 cells, tolerance 1e-11) stalled at a
  /// relative residual of 1.9e-5 for 2000 iterations where the pinned system
  /// converges (measured 2026-12-02, benchmarks/README.md, "Pressure level").
  bool solves_singular_systems() const;

  /// The matrix is singular with a one-dimensional null space: A right = 0
  /// and left^T A = 0 (whole vectors, this rank's rows read; need not be
  /// normalized). Held for the next solves, until set again. solve() then
  /// takes b's component along `left` out of b before it solves (the system
  /// is consistent up to round-off when the caller's null space is right;
  /// the residual and |b| are those of the projected b) and PETSc removes
  /// `right` where a method or preconditioner asks for it; the solution's
  /// component along `right` is arbitrary (the initial guess's, nearly).
  /// The fluid's closed box: the pressure level. Only where
  /// solves_singular_systems(). preconditioner_pin_row (>= 0; used with
  /// PCFIELDSPLIT only): the preconditioner is built from A with that row and
  /// column replaced by the identity's, a nonsingular matrix for the AMG on
  /// the pressure block, while the Krylov method solves the singular A.
  void set_null_space(std::span<const double> right, std::span<const double> left,
                      Index preconditioner_pin_row = -1);

  /// "fgmres + hypre" etc.: the KSP and PC types in use (after the first solve).
  std::string description() const;

  /// Rank `rank` of `ranks` owns nodes [first, end) of `nodes`: r N / R to
  /// (r + 1) N / R, whole nodes in order (the same split for every matrix).
  static std::pair<Index, Index> owned_node_range(Index nodes, int rank, int ranks);

  /// This rank's rows: [first, first + count).
  Index first_owned_row() const;
  Index owned_rows() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fdem

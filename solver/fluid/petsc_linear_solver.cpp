#include "fluid/petsc_linear_solver.hpp"

#include <petscksp.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/petsc_runtime.hpp"

namespace fdem {

namespace {

// PETSc reports failure through its return codes: turn one into a SolverError
// naming the call.
void check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw SolverError(fmt::format("PETSc: {} failed: {} (error {})", call, text ? text : "unknown error",
                                static_cast<int>(code)));
}

// Makes `options` the database PETSc objects read while it lives, so that two
// solvers with different options strings in one process do not see each
// other's (the fieldsplit and hypre sub-solvers read theirs at set-up).
class OptionsScope {
 public:
  explicit OptionsScope(PetscOptions options) { check(PetscOptionsPush(options), "PetscOptionsPush"); }
  ~OptionsScope() { PetscOptionsPop(); }
  OptionsScope(const OptionsScope&) = delete;
  OptionsScope& operator=(const OptionsScope&) = delete;
};

}  // namespace

struct PetscLinearSolver::Impl {
  int block_size = 4;
  std::string options_text;
  std::vector<std::string> caller_option_names;  // without the leading '-'
  PetscOptions options = nullptr;
  Mat matrix = nullptr;
  Vec rhs = nullptr, solution = nullptr, residual = nullptr;
  // On several ranks: the whole solution gathered onto every rank.
  Vec whole_solution = nullptr;
  VecScatter to_all = nullptr;
  KSP ksp = nullptr;
  IS velocity_rows = nullptr, pressure_rows = nullptr;
  // set_null_space: the right and left null vectors (normalized) and their MatNullSpaces.
  Vec right_null = nullptr, left_null = nullptr;
  MatNullSpace right_space = nullptr, left_space = nullptr;
  // set_null_space's preconditioner_pin_row (-1: none) and the matrix the
  // preconditioner is then built from: A with that row and column the identity's.
  PetscInt pin_row = -1;
  Mat pinned = nullptr;
  bool direct_solve = false, fieldsplit_preconditioner = false;  // from the options
  bool sequential = false;  // one process: the matrix is a SeqAIJ (create)
  PetscInt global_rows = 0, local_rows = 0, first_row = 0;
  int first_entry = 0;  // this rank's first CSR entry in the whole system
  int local_entries = 0;  // this rank's CSR entries
  bool configured = false;      // KSP options applied, splits defined
  bool setup_requested = true;  // rebuild the preconditioner at the next solve
  bool options_checked = false;

  Impl(std::string_view extra_options, int block) : block_size(block) {
    ensure_petsc_initialized();
    options_text = fmt::format("{} {}", petsc_default_options, extra_options);
    // Option names are the words starting with '-' and a letter (not "-1e-3").
    std::string_view rest = extra_options;
    while (!rest.empty()) {
      const auto start = rest.find_first_not_of(" \t\n");
      if (start == std::string_view::npos) break;
      rest.remove_prefix(start);
      const auto end = std::min(rest.find_first_of(" \t\n"), rest.size());
      const std::string_view word = rest.substr(0, end);
      if (word.size() > 1 && word[0] == '-' && std::isalpha(static_cast<unsigned char>(word[1])))
        caller_option_names.emplace_back(word.substr(1));
      rest.remove_prefix(end);
    }
    check(PetscOptionsCreate(&options), "PetscOptionsCreate");
    const PetscErrorCode code = PetscOptionsInsertString(options, options_text.c_str());
    if (code != 0) {
      PetscOptionsDestroy(&options);
      throw SolverError(fmt::format("PETSc: cannot parse the options \"{}\"", extra_options));
    }
    char ksp_type[64] = "";
    PetscBool given = PETSC_FALSE;
    check(PetscOptionsGetString(options, nullptr, "-ksp_type", ksp_type, sizeof ksp_type, &given),
          "PetscOptionsGetString");
    direct_solve = given && std::string_view(ksp_type) == KSPPREONLY;
    char pc_type[64] = "";
    check(PetscOptionsGetString(options, nullptr, "-pc_type", pc_type, sizeof pc_type, &given),
          "PetscOptionsGetString");
    fieldsplit_preconditioner = given && std::string_view(pc_type) == PCFIELDSPLIT;
  }

  ~Impl() {
    if (petsc_finalized()) return;  // PETSc already freed everything at exit
    KSPDestroy(&ksp);
    MatNullSpaceDestroy(&right_space);
    MatNullSpaceDestroy(&left_space);
    VecDestroy(&right_null);
    VecDestroy(&left_null);
    MatDestroy(&pinned);
    VecScatterDestroy(&to_all);
    VecDestroy(&whole_solution);
    ISDestroy(&velocity_rows);
    ISDestroy(&pressure_rows);
    VecDestroy(&rhs);
    VecDestroy(&solution);
    VecDestroy(&residual);
    MatDestroy(&matrix);
    PetscOptionsDestroy(&options);
  }

  void create(std::span<const int> row_start, std::span<const int> columns, std::span<const double> values) {
    global_rows = static_cast<PetscInt>(row_start.size()) - 1;
    if (global_rows % block_size != 0)
      throw SolverError(fmt::format("PETSc: {} rows are not whole blocks of {}", global_rows, block_size));
    // Whole nodes per rank, in order: rank r owns nodes [r N / R, (r + 1) N / R).
    const auto ranks = static_cast<long long>(petsc_world_size());
    int rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    const auto [first_node, end_node] =
        owned_node_range(global_rows / block_size, rank, static_cast<int>(ranks));
    first_row = static_cast<PetscInt>(first_node * block_size);
    local_rows = static_cast<PetscInt>((end_node - first_node) * block_size);
    first_entry = row_start[static_cast<std::size_t>(first_row)];
    local_entries = row_start[static_cast<std::size_t>(first_row + local_rows)] - first_entry;
    std::vector<PetscInt> local_row_start(static_cast<std::size_t>(local_rows) + 1);
    for (std::size_t i = 0; i < local_row_start.size(); ++i)
      local_row_start[i] = row_start[static_cast<std::size_t>(first_row) + i] - first_entry;
    const auto first_entry_index = static_cast<std::size_t>(first_entry);
    check(MatCreate(PETSC_COMM_WORLD, &matrix), "MatCreate");
    check(MatSetSizes(matrix, local_rows, local_rows, global_rows, global_rows), "MatSetSizes");
    // One process: a SeqAIJ, whose sub-blocks (the fieldsplit's A_pp) PETSc's
    // own LU and the SuiteSparse factorisations accept (an MPIAIJ's only
    // MUMPS, whose solve phase cost 3x PETSc's on the settling scene's
    // pressure block, benchmarks/README.md, "A direct pressure block").
    sequential = ranks == 1;
    check(MatSetType(matrix, sequential ? MATSEQAIJ : MATMPIAIJ), "MatSetType");
    check(MatSetBlockSize(matrix, block_size), "MatSetBlockSize");
    // The CSR arrays are copied, and the pattern fixed: later value updates
    // overwrite the value array (MatUpdateMPIAIJWithArray) with no search.
    if (sequential)
      check(MatSeqAIJSetPreallocationCSR(matrix, local_row_start.data(), columns.data() + first_entry_index,
                                         values.data() + first_entry_index),
            "MatSeqAIJSetPreallocationCSR");
    else
      check(MatMPIAIJSetPreallocationCSR(matrix, local_row_start.data(), columns.data() + first_entry_index,
                                         values.data() + first_entry_index),
            "MatMPIAIJSetPreallocationCSR");
    check(MatSetOption(matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
    check(MatCreateVecs(matrix, &solution, &rhs), "MatCreateVecs");
    check(VecDuplicate(rhs, &residual), "VecDuplicate");
    if (ranks > 1) check(VecScatterCreateToAll(solution, &to_all, &whole_solution), "VecScatterCreateToAll");

    // Splits by position in the node's block: velocity (all but the last), pressure (the last).
    std::vector<PetscInt> velocity_index, pressure_index;
    velocity_index.reserve(static_cast<std::size_t>(local_rows));
    for (PetscInt r = first_row; r < first_row + local_rows; ++r)
      ((r % block_size == block_size - 1) ? pressure_index : velocity_index).push_back(r);
    check(ISCreateGeneral(PETSC_COMM_WORLD, static_cast<PetscInt>(velocity_index.size()), velocity_index.data(),
                          PETSC_COPY_VALUES, &velocity_rows),
          "ISCreateGeneral");
    check(ISCreateGeneral(PETSC_COMM_WORLD, static_cast<PetscInt>(pressure_index.size()), pressure_index.data(),
                          PETSC_COPY_VALUES, &pressure_rows),
          "ISCreateGeneral");

    check(KSPCreate(PETSC_COMM_WORLD, &ksp), "KSPCreate");
    check(PetscObjectSetOptions(reinterpret_cast<PetscObject>(ksp), options), "PetscObjectSetOptions");
    check(KSPSetOperators(ksp, matrix, matrix), "KSPSetOperators");
  }

  void configure() {
    const OptionsScope scope(options);
    check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
    // Start from the caller's guess (the extrapolated solution), except for a
    // direct solve (-ksp_type preonly), which PETSc refuses one.
    PetscBool preonly = PETSC_FALSE;
    check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(ksp), KSPPREONLY, &preonly), "PetscObjectTypeCompare");
    check(KSPSetInitialGuessNonzero(ksp, preonly ? PETSC_FALSE : PETSC_TRUE), "KSPSetInitialGuessNonzero");
    PC pc = nullptr;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    PetscBool fieldsplit = PETSC_FALSE;
    check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &fieldsplit),
          "PetscObjectTypeCompare");
    if (fieldsplit) {
      check(PCFieldSplitSetIS(pc, "u", velocity_rows), "PCFieldSplitSetIS");
      check(PCFieldSplitSetIS(pc, "p", pressure_rows), "PCFieldSplitSetIS");
    }
    configured = true;
  }

  // The preconditioner's matrix for a singular A with a pin row: a copy of A
  // whose pin row and column are the identity's (nonsingular, as the pinned
  // system is), refreshed only when the preconditioner is rebuilt.
  void update_pinned() {
    if (!pinned) {
      check(MatDuplicate(matrix, MAT_COPY_VALUES, &pinned), "MatDuplicate");
      check(MatSetOption(pinned, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE), "MatSetOption");
      check(KSPSetOperators(ksp, matrix, pinned), "KSPSetOperators");
    } else {
      check(MatCopy(matrix, pinned, SAME_NONZERO_PATTERN), "MatCopy");
    }
    const bool owned = pin_row >= first_row && pin_row < first_row + local_rows;
    check(MatZeroRowsColumns(pinned, owned ? 1 : 0, &pin_row, 1.0, nullptr, nullptr), "MatZeroRowsColumns");
  }

  // Options no PETSc object asked for: a misspelt name is bad input, not a
  // silently different solver.
  void check_options_used() {
    options_checked = true;
    PetscInt count = 0;
    char** names = nullptr;
    char** values = nullptr;
    check(PetscOptionsLeftGet(options, &count, &names, &values), "PetscOptionsLeftGet");
    std::string unused;
    for (PetscInt i = 0; i < count; ++i)
      if (std::find(caller_option_names.begin(), caller_option_names.end(), names[i]) != caller_option_names.end())
        unused += fmt::format(" -{}", names[i]);
    PetscOptionsLeftRestore(options, &count, &names, &values);
    if (!unused.empty())
      throw SolverError(fmt::format("PETSc: options not used by the solver (misspelt, or not for this "
                                    "preconditioner):{} (options \"{}\")",
                                    unused, options_text.substr(petsc_default_options.size() + 1)));
  }
};

PetscLinearSolver::PetscLinearSolver(std::string_view options, int block_size)
    : impl_(std::make_unique<Impl>(options, block_size)) {}
PetscLinearSolver::~PetscLinearSolver() = default;

void PetscLinearSolver::set_matrix(std::span<const int> row_start, std::span<const int> columns,
                                   std::span<const double> values) {
  Impl& m = *impl_;
  if (!m.matrix) {
    m.create(row_start, columns, values);
  } else {
    if (m.sequential) {
      // The same CSR order as the preallocation: the values in place.
      PetscScalar* array = nullptr;
      check(MatSeqAIJGetArrayWrite(m.matrix, &array), "MatSeqAIJGetArrayWrite");
      std::copy_n(values.begin(), m.local_entries, array);
      check(MatSeqAIJRestoreArrayWrite(m.matrix, &array), "MatSeqAIJRestoreArrayWrite");
    } else {
      check(MatUpdateMPIAIJWithArray(m.matrix, values.data() + m.first_entry), "MatUpdateMPIAIJWithArray");
    }
  }
}

bool PetscLinearSolver::solves_singular_systems() const { return !impl_->direct_solve; }

void PetscLinearSolver::set_null_space(std::span<const double> right, std::span<const double> left,
                                       Index preconditioner_pin_row) {
  Impl& m = *impl_;
  if (!m.matrix) throw SolverError("PETSc: set_null_space before set_matrix");
  if (!solves_singular_systems())
    throw SolverError("PETSc: set_null_space with a direct solve (solves_singular_systems)");
  if (preconditioner_pin_row >= m.global_rows)
    throw SolverError(fmt::format("PETSc: preconditioner pin row {} of {} rows", preconditioner_pin_row,
                                  m.global_rows));
  if (right.size() != static_cast<std::size_t>(m.global_rows) || left.size() != right.size())
    throw SolverError(fmt::format("PETSc: null space of {} rows given vectors of {} and {}", m.global_rows,
                                  right.size(), left.size()));
  if (!m.right_null) {
    check(VecDuplicate(m.solution, &m.right_null), "VecDuplicate");
    check(VecDuplicate(m.rhs, &m.left_null), "VecDuplicate");
  }
  const auto first = static_cast<std::size_t>(m.first_row);
  const auto n = static_cast<std::size_t>(m.local_rows);
  PetscScalar* array = nullptr;
  for (auto [vec, values] : {std::pair{m.right_null, right}, std::pair{m.left_null, left}}) {
    check(VecGetArray(vec, &array), "VecGetArray");
    std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(first), n, array);
    check(VecRestoreArray(vec, &array), "VecRestoreArray");
  }
  for (Vec v : {m.right_null, m.left_null}) check(VecNormalize(v, nullptr), "VecNormalize");
  MatNullSpaceDestroy(&m.right_space);
  MatNullSpaceDestroy(&m.left_space);
  check(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, 1, &m.right_null, &m.right_space), "MatNullSpaceCreate");
  check(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, 1, &m.left_null, &m.left_space), "MatNullSpaceCreate");
  check(MatSetNullSpace(m.matrix, m.right_space), "MatSetNullSpace");
  check(MatSetTransposeNullSpace(m.matrix, m.left_space), "MatSetTransposeNullSpace");
  const PetscInt pin = m.fieldsplit_preconditioner ? static_cast<PetscInt>(preconditioner_pin_row) : -1;
  if (pin != m.pin_row) {
    m.pin_row = pin;
    m.setup_requested = true;
  }
}

std::pair<Index, Index> PetscLinearSolver::owned_node_range(Index nodes, int rank, int ranks) {
  const auto n = static_cast<long long>(nodes);
  return {static_cast<Index>(n * rank / ranks), static_cast<Index>(n * (rank + 1) / ranks)};
}

Index PetscLinearSolver::first_owned_row() const { return impl_->first_row; }
Index PetscLinearSolver::owned_rows() const { return impl_->local_rows; }

void PetscLinearSolver::request_preconditioner_setup() { impl_->setup_requested = true; }

PetscLinearSolveResult PetscLinearSolver::solve(std::span<const double> rhs, std::span<double> solution,
                                                double tolerance, int max_iterations) {
  Impl& m = *impl_;
  if (!m.matrix) throw SolverError("PETSc: solve before set_matrix");
  if (!m.configured) m.configure();
  const auto n = static_cast<std::size_t>(m.local_rows);
  const auto first = static_cast<std::ptrdiff_t>(m.first_row);
  if (rhs.size() != static_cast<std::size_t>(m.global_rows) || solution.size() != rhs.size())
    throw SolverError(fmt::format("PETSc: solve of {} rows given vectors of {} and {}", m.global_rows, rhs.size(),
                                  solution.size()));
  PetscScalar* array = nullptr;
  check(VecGetArray(m.rhs, &array), "VecGetArray");
  std::copy_n(rhs.begin() + first, n, array);
  check(VecRestoreArray(m.rhs, &array), "VecRestoreArray");
  check(VecGetArray(m.solution, &array), "VecGetArray");
  std::copy_n(solution.begin() + first, n, array);
  check(VecRestoreArray(m.solution, &array), "VecRestoreArray");

  // A singular system is solved for b less its component along the left
  // null vector (KSPSolve would project a copy; the residual test below needs
  // the projected b too).
  if (m.left_space) check(MatNullSpaceRemove(m.left_space, m.rhs), "MatNullSpaceRemove");
  PetscReal b_norm = 0.0;
  check(VecNorm(m.rhs, NORM_2, &b_norm), "VecNorm");
  if (m.setup_requested && m.pin_row >= 0) m.update_pinned();
  // |r| <= tolerance |b| (rtol 0: relative to |b|, not to the guess's residual).
  check(KSPSetReusePreconditioner(m.ksp, m.setup_requested ? PETSC_FALSE : PETSC_TRUE),
        "KSPSetReusePreconditioner");
  m.setup_requested = false;
  // Converged by PETSc's test and by the true residual. The two can part:
  // a direct solve (preonly) with a reused, stale factorisation passes the
  // first only, and FGMRES's Arnoldi estimate of |r| drifts from the true
  // residual on hard systems (measured: 4.9e-8 true at an estimated 1e-8,
  // ILU(0), first step on a study mesh). Then the solve restarts from its own result (a
  // true-residual restart), at most twice and within the iteration cap.
  PetscLinearSolveResult result;
  const PetscReal target = tolerance * b_norm;
  PetscReal r_norm = 0.0;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const int remaining = max_iterations - result.iterations;
    if (remaining < 1) break;
    check(KSPSetTolerances(m.ksp, 0.0, target, PETSC_DEFAULT, remaining), "KSPSetTolerances");
    {
      const OptionsScope scope(m.options);
      check(KSPSolve(m.ksp, m.rhs, m.solution), "KSPSolve");
    }
    check(KSPSetReusePreconditioner(m.ksp, PETSC_TRUE), "KSPSetReusePreconditioner");
    PetscInt iterations = 0;
    check(KSPGetIterationNumber(m.ksp, &iterations), "KSPGetIterationNumber");
    // After the first solve that applied the preconditioner: nested solvers
    // (a block Jacobi inside a split) read their options at their first
    // application, which a zero right-hand side (a fluid at rest) never makes.
    if (!m.options_checked && iterations > 0) m.check_options_used();
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    check(KSPGetConvergedReason(m.ksp, &reason), "KSPGetConvergedReason");
    result.iterations += static_cast<int>(iterations);
    result.reason = KSPConvergedReasons[reason];
    // The true residual: for a left-preconditioned method the KSP's own norm
    // is the preconditioned one.
    check(MatMult(m.matrix, m.solution, m.residual), "MatMult");
    check(VecAYPX(m.residual, -1.0, m.rhs), "VecAYPX");
    check(VecNorm(m.residual, NORM_2, &r_norm), "VecNorm");
    // 2x: the estimate and the true norm differ by round-off when all is well.
    result.converged = reason > 0 && r_norm <= 2.0 * target;
    if (result.converged || reason < 0) break;
  }
  result.relative_residual = b_norm > 0.0 ? r_norm / b_norm : r_norm;

  // Every rank continues with the whole solution (one process: its own rows are all of it).
  Vec whole = m.solution;
  if (m.to_all) {
    check(VecScatterBegin(m.to_all, m.solution, m.whole_solution, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
    check(VecScatterEnd(m.to_all, m.solution, m.whole_solution, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
    whole = m.whole_solution;
  }
  const PetscScalar* out = nullptr;
  check(VecGetArrayRead(whole, &out), "VecGetArrayRead");
  std::copy_n(out, solution.size(), solution.begin());
  check(VecRestoreArrayRead(whole, &out), "VecRestoreArrayRead");
  return result;
}

std::string PetscLinearSolver::description() const {
  const Impl& m = *impl_;
  if (!m.ksp) return "petsc (not set up)";
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  PC pc = nullptr;
  KSPGetType(m.ksp, &ksp_type);
  KSPGetPC(m.ksp, &pc);
  PCGetType(pc, &pc_type);
  return fmt::format("{} + {}", ksp_type ? ksp_type : "?", pc_type ? pc_type : "?");
}

}  // namespace fdem

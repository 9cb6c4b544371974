// GCC 12 reports a false -Wmaybe-uninitialized inside its own AVX-512
// intrinsics (_mm512_extractf64x4_pd's __Y = __Y idiom) when Eigen's dynamic
// reductions are inlined with -march=native; the warning is about the
// compiler's header, not this file. It must precede the first Eigen include.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include "fluid/fluid_solver.hpp"

#include <omp.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "fluid/fluid_boundary.hpp"
#include "fluid/fluid_element.hpp"
#include "fluid/fluid_system_size.hpp"
#include "fluid/petsc_linear_solver.hpp"
#include "fluid/projection_scheme.hpp"
#include "mesh/layer_colouring.hpp"
#include "core/binary_stream.hpp"
#include "core/petsc_runtime.hpp"

namespace fdem {

namespace {

using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr int dofs_per_node = 4;  // u, v, w, p interleaved
// The row (and column) of node `node`'s pressure unknown: the last of its block.
constexpr Index pressure_row(Index node) { return dofs_per_node * node + 3; }
constexpr std::ptrdiff_t parallel_min_cells = 256;  // the unit of the node and residual loops' thread thresholds

}  // namespace

struct FluidSolver::Impl {
  BoxMesh mesh;
  FluidSpec spec;
  FluidSolverOptions options;
  Index num_nodes = 0;

  // The system the linear solver sees, one CSR matrix whose pattern is built
  // once: prescribed unknowns (no-slip and inlet velocities, free-slip normal
  // components, the pinned pressure) are eliminated from the other rows
  // during assembly (their columns go to the right-hand side with their
  // values), so a prescribed row is a bare identity row and no entry couples
  // a free unknown to a prescribed one. On the study meshes ~30 % of the
  // unknowns are prescribed (wall nodes): the Krylov mat-vecs and ILUT work
  // on ~40 % fewer entries. Every free row of node n holds the free
  // unknowns of n's neighbours m in increasing order; block_offset[e][4a+b]
  // is where node n_b's free columns start inside the free rows of node n_a
  // (relative to the row start), free_rank[4m+j] the place of unknown j among
  // node m's free ones (-1: prescribed).
  RowMatrix reduced;
  std::vector<std::array<int, 16>> block_offset;
  std::vector<std::int8_t> free_rank;
  std::vector<std::uint8_t> dof_fixed;  // per dof row: prescribed (fixed for the solver's life)
  std::vector<std::uint8_t> node_all_free;  // per node: none of its 4 unknowns prescribed
  Eigen::VectorXd prescribed;           // per dof: its prescribed value at the new time level (0 when free)
  // The rows this process assembles and hands to the linear solver: all of
  // them on one process; on several MPI ranks its block of whole nodes
  // (PetscLinearSolver::owned_node_range), the other ranks assembling the rest.
  Index first_owned_node = 0, end_owned_node = 0;

  FluidConstraints constraints;
  BoundaryVelocity boundary_field;

  // State, node-major.
  Eigen::VectorXd solution;   // 4*num_nodes interleaved (u, v, w, p)
  Eigen::VectorXd rhs;
  Eigen::VectorXd row_scale, column_scale;  // equilibration of the assembled system
  std::vector<double> velocity, pressure;   // views for the public API
  std::vector<double> velocity_n, velocity_nm1;  // u^n, u^{n-1}
  std::vector<double> pressure_n, pressure_nm1;  // p^n, p^{n-1}: the initial guess's extrapolation
  std::vector<double> body_force;
  std::vector<double> advecting, history;
  // Volume-averaged models (scene fluid.model): nodal P1 porosity at the new
  // level and the last two, its BDF rate, the element values as given.
  bool volume_averaged = false;
  bool porosity_given = false;
  std::vector<double> node_volume;                 // sum of V_e / 4 over the elements at the node
  std::vector<double> element_porosity;            // as given (num_elements)
  std::vector<double> porosity_new, porosity_n, porosity_nm1, porosity_rate;  // nodal
  // Semi-implicit momentum exchange; empty = off.
  std::vector<double> exchange_beta, exchange_velocity;
  double time_s = 0.0;
  double dt_previous = 0.0;
  int steps = 0;
  int steps_since_reset = 0;

  // Linear solvers.
  Eigen::BiCGSTAB<RowMatrix, Eigen::IncompleteLUT<double>> bicgstab;
  bool preconditioner_ready = false;
  // alpha0 / dt (the mass term's coefficient over rho) of the matrix the
  // preconditioner was last built or marked for building from (NaN: none). It changes from BDF1's
  // first step to BDF2 (alpha0 1 -> 3/2) and with dt; a preconditioner of
  // the other coefficient is a poorer one (measured on the settling scene:
  // 30 Krylov iterations a step with BDF1's ILUT against 23 with BDF2's), so
  // the change is a rebuild point.
  double preconditioner_mass_rate = std::numeric_limits<double>::quiet_NaN();
  bool pattern_analyzed = false;
  int last_krylov_iterations = 0;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  bool lu_analyzed = false;
  FluidLinearSolver linear_solver = FluidLinearSolver::bicgstab_ilut;  // options', else the scene's
  std::unique_ptr<PetscLinearSolver> petsc;
  // A closed domain's pressure level. Pinning one node's pressure (the Eigen
  // solvers and PETSc's direct ones) leaves the system nonsingular but with
  // one eigenvalue near zero (a point Dirichlet condition on the pressure
  // Laplacian), which an ILU does not capture: FGMRES + ILU(1) on the
  // settling scene stalled for ~5 iterations a step near 1e-5 until it had
  // resolved it. PETSc's Krylov solves (PetscLinearSolver::
  // solves_singular_systems) instead get the pressure unpinned and the
  // constant-pressure null space (a fieldsplit builds its preconditioner from
  // the pinned matrix: its pressure AMG needs a nonsingular block); the
  // solution is then shifted to pressure 0 at the same node, the same gauge.
  // Default fieldsplit, 8.6e3 / 4e4 / 9.8e4 tetrahedra: 12.4 / 13.0 / 13.6
  // Krylov iterations a step against 15.2 / 17.6 / 18.2 pinned.
  bool pressure_level_by_null_space = false;
  // scene fluid.scheme: projection: the segregated step replaces the
  // monolithic system (the system above is then never assembled).
  std::unique_ptr<ProjectionScheme> projection;

  Impl(const BoxMesh& m, const Scene& scene, FluidSolverOptions opts)
      : mesh(m), spec(scene.fluid), options(opts), num_nodes(m.num_nodes()) {
    if (!(spec.density > 0.0) || !(spec.viscosity > 0.0))
      throw SolverError(fmt::format("fluid: density ({}) and viscosity ({}) must be positive", spec.density,
                                    spec.viscosity));
    require_indexable_fluid_system(mesh.cells(), options.ilut_fill_factor, scene.source_file);  // before any allocation
    constraints = fluid_constraints(mesh, spec);
    linear_solver = options.linear_solver.value_or(spec.linear_solver == FluidLinearSolverChoice::petsc
                                                       ? FluidLinearSolver::petsc
                                                       : FluidLinearSolver::bicgstab_ilut);
    if (spec.scheme == FluidScheme::projection) {
      if (mpi_ranks() > 1)
        throw SolverError(fmt::format("{}: fluid.scheme: projection runs on one MPI rank only ({} ranks here); use "
                                      "scheme: monolithic to share the fluid solve",
                                      scene.source_file, mpi_ranks()));
      if (spec.model != FluidModel::simplified)
        throw SolverError(fmt::format("{}: fluid.scheme: projection solves fluid.model: simplified only",
                                      scene.source_file));
      linear_solver = FluidLinearSolver::bicgstab_ilut;  // not used: no monolithic system is solved
    }
    // On several MPI ranks the solve is shared, which only PETSc's can be.
    if (mpi_ranks() > 1) linear_solver = FluidLinearSolver::petsc;
    if (linear_solver == FluidLinearSolver::petsc) {
      petsc = std::make_unique<PetscLinearSolver>(spec.petsc_options, dofs_per_node);
      pressure_level_by_null_space = constraints.pressure_node >= 0 && petsc->solves_singular_systems();
    }
    build_pattern();
    const auto n = static_cast<std::size_t>(num_nodes);
    solution = Eigen::VectorXd::Zero(dofs_per_node * num_nodes);
    rhs = Eigen::VectorXd::Zero(dofs_per_node * num_nodes);
    velocity.assign(3 * n, 0.0);
    pressure.assign(n, 0.0);
    velocity_n.assign(3 * n, 0.0);
    velocity_nm1.assign(3 * n, 0.0);
    pressure_n.assign(n, 0.0);
    pressure_nm1.assign(n, 0.0);
    body_force.assign(3 * n, 0.0);
    advecting.assign(3 * n, 0.0);
    history.assign(3 * n, 0.0);
    volume_averaged = spec.model != FluidModel::simplified;
    element_porosity.assign(static_cast<std::size_t>(mesh.num_elements()), 1.0);
    node_volume.assign(n, 0.0);
    for (Index e = 0; e < mesh.num_elements(); ++e)
      for (Index a : mesh.element_nodes(e)) node_volume[static_cast<std::size_t>(a)] += mesh.element_volume(e) / 4.0;
    for (auto* v : {&porosity_new, &porosity_n, &porosity_nm1}) v->assign(n, 1.0);
    porosity_rate.assign(n, 0.0);
    bicgstab.preconditioner().setDroptol(options.ilut_drop_tolerance);
    bicgstab.preconditioner().setFillfactor(options.ilut_fill_factor);
    if (spec.scheme == FluidScheme::projection) projection = std::make_unique<ProjectionScheme>(mesh, spec, constraints);
    std::tie(first_owned_node, end_owned_node) =
        mpi_ranks() > 1 ? PetscLinearSolver::owned_node_range(num_nodes, mpi_rank(), mpi_ranks())
                        : std::pair<Index, Index>{0, num_nodes};
  }

  // Gathers one element's nodal data into the kernel's input.
  void gather(Index e, FluidElementInput& in) const {
    const auto& nodes = mesh.element_nodes(e);
    in.gradients = mesh.shape_gradients(e);
    in.volume = mesh.element_volume(e);
    for (int a = 0; a < 4; ++a) {
      const auto s = 3 * static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)]);
      for (int d = 0; d < 3; ++d) {
        in.advecting(a, d) = advecting[s + static_cast<std::size_t>(d)];
        in.history(a, d) = history[s + static_cast<std::size_t>(d)];
        in.body_force(a, d) = body_force[s + static_cast<std::size_t>(d)];
      }
      if (volume_averaged) {
        const auto node = static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)]);
        in.porosity[a] = porosity_new[node];
        in.porosity_rate[a] = porosity_rate[node];
      }
    }
    if (!exchange_beta.empty()) {
      const auto se = static_cast<std::size_t>(e);
      in.exchange_coefficient = exchange_beta[se];
      in.exchange_velocity = Vec3(exchange_velocity[3 * se], exchange_velocity[3 * se + 1], exchange_velocity[3 * se + 2]);
    }
  }

  void build_pattern() {
    const auto n = static_cast<std::size_t>(num_nodes);
    const std::size_t rows = dofs_per_node * n;
    dof_fixed.assign(rows, 0);
    for (std::size_t node = 0; node < n; ++node)
      for (std::size_t d = 0; d < 3; ++d) dof_fixed[dofs_per_node * node + d] = constraints.velocity_fixed[3 * node + d];
    if (constraints.pressure_node >= 0 && !pressure_level_by_null_space)
      dof_fixed[dofs_per_node * static_cast<std::size_t>(constraints.pressure_node) + 3] = 1;
    free_rank.assign(rows, -1);
    node_all_free.assign(n, 1);
    for (std::size_t r = 0; r < rows; ++r)
      if (dof_fixed[r]) node_all_free[r / dofs_per_node] = 0;
    std::vector<int> free_count(n, 0);
    for (std::size_t node = 0; node < n; ++node)
      for (std::size_t j = 0; j < dofs_per_node; ++j)
        if (!dof_fixed[dofs_per_node * node + j]) free_rank[dofs_per_node * node + j] = static_cast<std::int8_t>(free_count[node]++);

    std::vector<std::vector<Index>> neighbours(n);
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto& nodes = mesh.element_nodes(e);
      for (Index a : nodes)
        for (Index b : nodes) neighbours[static_cast<std::size_t>(a)].push_back(b);
    }
    // Per node: the free columns of each neighbour start at neighbour_start[a][index in the list].
    std::vector<std::vector<int>> neighbour_start(n);
    std::vector<int> outer(rows + 1, 0);
    for (std::size_t a = 0; a < n; ++a) {
      auto& list = neighbours[a];
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
      int width = 0;
      for (Index m : list) {
        neighbour_start[a].push_back(width);
        width += free_count[static_cast<std::size_t>(m)];
      }
      for (std::size_t i = 0; i < dofs_per_node; ++i)
        outer[dofs_per_node * a + i + 1] = dof_fixed[dofs_per_node * a + i] ? 1 : width;
    }
    for (std::size_t r = 0; r < rows; ++r) outer[r + 1] += outer[r];
    reduced.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(rows));
    reduced.resizeNonZeros(outer.back());
    std::copy(outer.begin(), outer.end(), reduced.outerIndexPtr());
    int* inner = reduced.innerIndexPtr();
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t i = 0; i < dofs_per_node; ++i) {
        const std::size_t row = dofs_per_node * a + i;
        int pos = outer[row];
        if (dof_fixed[row]) {
          inner[pos] = static_cast<int>(row);
          continue;
        }
        for (Index m : neighbours[a])
          for (int j = 0; j < dofs_per_node; ++j)
            if (!dof_fixed[static_cast<std::size_t>(dofs_per_node * m + j)]) inner[pos++] = dofs_per_node * static_cast<int>(m) + j;
      }
    std::fill_n(reduced.valuePtr(), reduced.nonZeros(), 0.0);

    block_offset.resize(static_cast<std::size_t>(mesh.num_elements()));
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto& nodes = mesh.element_nodes(e);
      for (std::size_t a = 0; a < 4; ++a) {
        const auto na = static_cast<std::size_t>(nodes[a]);
        const auto& list = neighbours[na];
        for (std::size_t b = 0; b < 4; ++b) {
          const auto it = std::lower_bound(list.begin(), list.end(), nodes[b]);
          block_offset[static_cast<std::size_t>(e)][4 * a + b] = neighbour_start[na][static_cast<std::size_t>(it - list.begin())];
        }
      }
    }
  }

  // The prescribed values at the new time level (prescribed), for the
  // identity rows and the elimination of their columns.
  void prescribe(double time_new) {
    prescribed.setZero(dofs_per_node * num_nodes);
#pragma omp parallel for schedule(static) if (num_nodes > 8 * parallel_min_cells)
    for (Index node = 0; node < num_nodes; ++node) {
      const auto s = static_cast<std::size_t>(node);
      Vec3 field_value = Vec3::Zero();
      const bool use_field = boundary_field && constraints.fully_prescribed[s];
      if (use_field) field_value = boundary_field(mesh.node(node), time_new);
      // A superficial inlet asks for the flux eps u: the volume-averaged
      // models' node takes it over the node's porosity at the new level.
      const double scale = volume_averaged && constraints.superficial[s] ? 1.0 / porosity_new[s] : 1.0;
      for (std::size_t d = 0; d < 3; ++d)
        if (constraints.velocity_fixed[3 * s + d])
          prescribed[dofs_per_node * node + static_cast<int>(d)] =
              use_field ? field_value[static_cast<Eigen::Index>(d)] : scale * constraints.velocity_value[3 * s + d];
    }
    // The pinned pressure (if any) is 0: prescribed already holds it.
  }

  // Assembles the Picard system with the current `advecting` velocity at the
  // new time level time_new, prescribed unknowns eliminated (see reduced):
  // the element rows of free unknowns go into the matrix, their entries in
  // prescribed columns (times the value) to the right-hand side; prescribed
  // rows become identity rows holding their values. Only this process's rows.
  void assemble(double dt, double alpha0, double time_new) {
    prescribe(time_new);
    double* values = reduced.valuePtr();
    const int* outer = reduced.outerIndexPtr();
    std::fill_n(values, reduced.nonZeros(), 0.0);
    rhs.setZero();
    const int first_row = dofs_per_node * static_cast<int>(first_owned_node);
    const int end_row = dofs_per_node * static_cast<int>(end_owned_node);
    // The layers holding an element with an owned node: a layer k touches node levels k and k + 1.
    const auto nodes_per_level = static_cast<Index>(mesh.cells()[0] + 1) * (mesh.cells()[1] + 1);
    const Index first_layer = std::max<Index>(0, first_owned_node / nodes_per_level - 1);
    const Index last_layer = end_owned_node > first_owned_node ? (end_owned_node - 1) / nodes_per_level : -1;
    // Each entry receives its element terms in the same order on any
    // thread count (mesh/layer_colouring.hpp); a thread's element input and
    // system are its own.
    struct ElementWorkspace {
      FluidElementInput in;
      FluidElementSystem sys;
    };
    const auto make_workspace = [&] {
      ElementWorkspace w;
      w.in.density = spec.density;
      w.in.viscosity = spec.viscosity;
      w.in.dt = dt;
      w.in.alpha0 = alpha0;
      w.in.h = std::cbrt(mesh.cell_size().prod());  // one tau per cell: see fluid_element.hpp
      w.in.porosity_weighted_stress = spec.model == FluidModel::vans_a;
      w.in.volume_averaged = volume_averaged;
      return w;
    };
    for_each_element_by_layer_colour(mesh, {first_layer, last_layer}, layer_colours_worth_threads(mesh), make_workspace,
                                     [&](Index e, ElementWorkspace& w) {
                                       gather(e, w.in);
                                       fluid_element_system(w.in, w.sys);
                                       scatter(e, w.sys, values, outer, first_row, end_row);
                                     });
    for (int r = first_row; r < end_row; ++r)
      if (dof_fixed[static_cast<std::size_t>(r)]) {
        values[outer[r]] = 1.0;
        rhs[r] = prescribed[r];
      }
  }

  void scatter(Index e, const FluidElementSystem& sys, double* values, const int* outer, int first_row, int end_row) {
    const auto& nodes = mesh.element_nodes(e);
    const auto& offset = block_offset[static_cast<std::size_t>(e)];
    for (int a = 0; a < 4; ++a) {
      const int row0 = dofs_per_node * static_cast<int>(nodes[static_cast<std::size_t>(a)]);
      if (row0 < first_row || row0 >= end_row) continue;
      for (int i = 0; i < 4; ++i) {
        const int row = row0 + i;
        if (dof_fixed[static_cast<std::size_t>(row)]) continue;
        double moved = 0.0;  // sum over prescribed columns of A_rc x_c, to the right-hand side
        for (int b = 0; b < 4; ++b) {
          const int col0 = dofs_per_node * static_cast<int>(nodes[static_cast<std::size_t>(b)]);
          double* block = values + outer[row] + offset[static_cast<std::size_t>(4 * a + b)];
          if (node_all_free[static_cast<std::size_t>(col0 / dofs_per_node)]) {
            // An interior node (most of them): its four columns are free and
            // contiguous; the same additions as below, without the lookups.
            for (int j = 0; j < 4; ++j) block[j] += sys.matrix(4 * a + i, 4 * b + j);
            continue;
          }
          for (int j = 0; j < 4; ++j) {
            const int rank = free_rank[static_cast<std::size_t>(col0 + j)];
            if (rank >= 0)
              block[rank] += sys.matrix(4 * a + i, 4 * b + j);
            else
              moved += sys.matrix(4 * a + i, 4 * b + j) * prescribed[col0 + j];
          }
        }
        rhs[row] += sys.rhs[4 * a + i] - moved;
      }
    }
  }

  // Row then column equilibration (R A C)(C^-1 x) = R b: momentum rows scale
  // with rho V/dt, continuity rows with V/h and tau/rho; unscaled, the
  // continuity residual would be invisible in |b - A x| / |b|, and ILUT's
  // dropping would treat the two blocks unequally.
  // The free pressure rows share one scale, and so do the free pressure
  // columns (the largest of their per-row and per-column maxima; prescribed
  // ones are identity rows and keep theirs, 1): scaled
  // node by node, the pressure block R_p A_pp C_p has C_p^-1 1, not the
  // constant, as its near-null vector, which the pressure AMG's
  // interpolation (exact for constants) then misses on every level; its
  // V-cycle weakened with the number of levels and the fieldsplit's Krylov
  // count grew 12.0 -> 17 from 8.6e3 to 1.03e6 tetrahedra; with one scale
  // it is 6.4 -> 7 (benchmarks/README.md, "Pressure block scaled as a whole").
  // On several ranks each equilibrates its own rows; a column's scale is the
  // largest over all rows, so the ranks take the maximum of theirs (and of
  // the largest pressure row).
  void equilibrate() {
    double* values = reduced.valuePtr();
    const int* outer = reduced.outerIndexPtr();
    const int* inner = reduced.innerIndexPtr();
    const auto rows = static_cast<Index>(reduced.rows());
    const Index first_row = dofs_per_node * first_owned_node, end_row = dofs_per_node * end_owned_node;
    const auto is_free_pressure = [this](Index dof) {
      return dof % dofs_per_node == dofs_per_node - 1 && !dof_fixed[static_cast<std::size_t>(dof)];
    };
    row_scale.setOnes(rows);
    column_scale.setZero(rows);
    // Three passes over the values: the row maxima (the pressure rows' common
    // scale needs all of them), the column maxima of the row-scaled values,
    // then one write of (v r) c, the same products as scaling in place.
    double largest_pressure_row = 0.0;
    for (Index r = first_row; r < end_row; ++r) {
      double largest = 0.0;
      for (int k = outer[r]; k < outer[r + 1]; ++k) largest = std::max(largest, std::abs(values[k]));
      row_scale[r] = 1.0 / largest;  // never 0: every row holds a diagonal block
      if (is_free_pressure(r)) largest_pressure_row = std::max(largest_pressure_row, largest);
    }
    max_over_ranks({&largest_pressure_row, 1});
    for (Index r = first_row; r < end_row; ++r) {
      if (is_free_pressure(r)) row_scale[r] = 1.0 / largest_pressure_row;
      const double scale = row_scale[r];
      for (int k = outer[r]; k < outer[r + 1]; ++k)
        column_scale[inner[k]] = std::max(column_scale[inner[k]], std::abs(values[k] * scale));
    }
    max_over_ranks({column_scale.data(), static_cast<std::size_t>(rows)});
    double largest_pressure_column = 0.0;
    for (Index c = dofs_per_node - 1; c < rows; c += dofs_per_node)
      if (is_free_pressure(c)) largest_pressure_column = std::max(largest_pressure_column, column_scale[c]);
    for (Index c = dofs_per_node - 1; c < rows; c += dofs_per_node)
      if (is_free_pressure(c)) column_scale[c] = largest_pressure_column;
    column_scale = column_scale.cwiseInverse();
    for (Index r = first_row; r < end_row; ++r) {
      const double scale = row_scale[r];
      for (int k = outer[r]; k < outer[r + 1]; ++k) values[k] = values[k] * scale * column_scale[inner[k]];
    }
    rhs.array() *= row_scale.array();
  }

  // |rhs - reduced x| / |rhs| over all rows (this process's, summed over the ranks).
  double relative_residual(const Eigen::VectorXd& x) const {
    const int* outer = reduced.outerIndexPtr();
    const int* inner = reduced.innerIndexPtr();
    const double* values = reduced.valuePtr();
    double r_sq = 0.0, b_sq = 0.0;
    for (Index r = dofs_per_node * first_owned_node; r < dofs_per_node * end_owned_node; ++r) {
      double ax = 0.0;
      for (int k = outer[r]; k < outer[r + 1]; ++k) ax += values[k] * x[inner[k]];
      r_sq += (rhs[r] - ax) * (rhs[r] - ax);
      b_sq += rhs[r] * rhs[r];
    }
    r_sq = sum_over_ranks(r_sq);
    b_sq = sum_over_ranks(b_sq);
    return b_sq > 0.0 ? std::sqrt(r_sq / b_sq) : 0.0;
  }

  // Solves reduced * solution = rhs, starting from the current solution.
  void solve_linear(FluidStepReport& report, int picard_iteration, double tolerance) {
    equilibrate();
    Eigen::VectorXd scaled = solution.cwiseQuotient(column_scale);
    if (linear_solver == FluidLinearSolver::petsc) {
      // PETSc computed the same true residual of the same system: one mat-vec less.
      report.linear_residual = solve_petsc(report, picard_iteration, tolerance, scaled);
      solution = scaled.cwiseProduct(column_scale);
      if (pressure_level_by_null_space) {
        const double level = solution[pressure_row(constraints.pressure_node)];
        for (Index node = 0; node < num_nodes; ++node) solution[pressure_row(node)] -= level;
      }
      return;
    } else if (linear_solver == FluidLinearSolver::sparse_lu) {
      const Eigen::SparseMatrix<double> column_major = reduced;
      if (!lu_analyzed) {
        lu.analyzePattern(column_major);
        lu_analyzed = true;
      }
      lu.factorize(column_major);
      if (lu.info() != Eigen::Success)
        throw SolverError(fmt::format("fluid step {}: Picard iteration {}: sparse LU factorization failed: {}",
                                      steps + 1, picard_iteration, lu.lastErrorMessage()));
      scaled = lu.solve(rhs);
      report.linear_iterations += 1;
    } else if (rhs.squaredNorm() == 0.0) {
      // A zero right-hand side (a fluid at rest under no force and resting
      // walls): x = 0 exactly, with no factorization and no iteration (Eigen's
      // BiCGSTAB would return x = 0 too, but report its iteration cap).
      scaled.setZero();
    } else {
      bicgstab.setTolerance(tolerance);
      bicgstab.setMaxIterations(spec.max_linear_iterations);
      const bool refactor = !preconditioner_ready || last_krylov_iterations > options.refactor_above_iterations;
      if (refactor) factor_preconditioner(picard_iteration, report);
      scaled = bicgstab.solveWithGuess(rhs, scaled);
      int iterations = static_cast<int>(bicgstab.iterations());
      if (bicgstab.info() != Eigen::Success && !refactor) {
        // A stale preconditioner may be what failed: refactor once and retry.
        report.linear_iterations += iterations;
        factor_preconditioner(picard_iteration, report);
        scaled = bicgstab.solveWithGuess(rhs, scaled);
        iterations = static_cast<int>(bicgstab.iterations());
      }
      last_krylov_iterations = iterations;
      report.linear_iterations += iterations;
      if (bicgstab.info() != Eigen::Success || !scaled.allFinite())
        throw SolverError(fmt::format(
            "fluid step {} (t = {:.6g} s): Picard iteration {}: BiCGSTAB did not converge in {} iterations "
            "(relative residual {:.3e}, tolerance {:.1e}, max_linear_iterations {})",
            steps + 1, time_s, picard_iteration, iterations, bicgstab.error(), tolerance,
            spec.max_linear_iterations));
    }
    report.linear_residual = relative_residual(scaled);
    solution = scaled.cwiseProduct(column_scale);
  }

  // The PETSc solve of the same reduced, equilibrated system; its
  // preconditioner is rebuilt as ILUT's is refactored (slow solve, checkpoint).
  // Returns the solve's relative true residual.
  double solve_petsc(FluidStepReport& report, int picard_iteration, double tolerance, Eigen::VectorXd& scaled) {
    const auto rows = static_cast<std::size_t>(reduced.rows());
    const auto entries = static_cast<std::size_t>(reduced.nonZeros());
    petsc->set_matrix({reduced.outerIndexPtr(), rows + 1}, {reduced.innerIndexPtr(), entries},
                      {reduced.valuePtr(), entries});
    if (pressure_level_by_null_space) {
      // Constant pressure, zero velocity: A z = 0 (every free velocity's
      // test function vanishes on the walls, so its divergence integrates to
      // 0; the PSPG and SUPG terms see grad p = 0), and the continuity rows
      // sum to zero in every column (partition of unity, the same reason).
      // In the equilibrated system (R A C) that is C^-1 z on the right and
      // R^-1 z on the left.
      Eigen::VectorXd right = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows));
      Eigen::VectorXd left = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows));
      for (Index node = 0; node < num_nodes; ++node) {
        const Index p = pressure_row(node);
        right[p] = 1.0 / column_scale[p];
        left[p] = 1.0 / row_scale[p];
      }
      petsc->set_null_space({right.data(), rows}, {left.data(), rows}, pressure_row(constraints.pressure_node));
    }
    const bool rebuild = !preconditioner_ready || last_krylov_iterations > options.petsc_rebuild_above_iterations;
    if (rebuild) {
      petsc->request_preconditioner_setup();
      ++report.preconditioner_factorizations;
    }
    const Eigen::VectorXd guess = scaled;
    const std::span<double> x{scaled.data(), rows};
    PetscLinearSolveResult result = petsc->solve({rhs.data(), rows}, x, tolerance, spec.max_linear_iterations);
    if (!result.converged && !rebuild) {
      // A stale preconditioner may be what failed: rebuild once and retry.
      report.linear_iterations += result.iterations;
      ++report.preconditioner_factorizations;
      petsc->request_preconditioner_setup();
      scaled = guess;
      result = petsc->solve({rhs.data(), rows}, x, tolerance, spec.max_linear_iterations);
    }
    preconditioner_ready = true;
    last_krylov_iterations = result.iterations;
    report.linear_iterations += result.iterations;
    if (!result.converged || !scaled.allFinite())
      throw SolverError(fmt::format(
          "fluid step {} (t = {:.6g} s): Picard iteration {}: PETSc {} did not converge in {} iterations "
          "({}, relative residual {:.3e}, tolerance {:.1e}, max_linear_iterations {})",
          steps + 1, time_s, picard_iteration, petsc->description(), result.iterations, result.reason,
          result.relative_residual, tolerance, spec.max_linear_iterations));
    return result.relative_residual;
  }

  void factor_preconditioner(int picard_iteration, FluidStepReport& report) {
    ++report.preconditioner_factorizations;
    // IncompleteLUT: the AMD ordering depends on the pattern only, which is
    // fixed (the reduced pattern is built once): order once, then
    // only the threshold factorization on later refactors.
    // (The first call goes through compute(): Eigen's IterativeSolverBase::
    // analyzePattern alone reads IncompleteLUT's still uninitialized m_info.)
    if (!pattern_analyzed) {
      bicgstab.compute(reduced);
      pattern_analyzed = true;
    } else {
      bicgstab.factorize(reduced);
    }
    if (bicgstab.info() != Eigen::Success)
      throw SolverError(fmt::format("fluid step {}: Picard iteration {}: ILUT factorization failed", steps + 1,
                                    picard_iteration));
    preconditioner_ready = true;
  }

  void unpack_solution() {
    for (Index node = 0; node < num_nodes; ++node) {
      const auto s = static_cast<std::size_t>(node);
      for (std::size_t d = 0; d < 3; ++d)
        velocity[3 * s + d] = solution[dofs_per_node * node + static_cast<int>(d)];
      pressure[s] = solution[pressure_row(node)];
    }
  }

  double divergence_l2(double* gradient_l2 = nullptr) const {
    double div_sq = 0.0, grad_sq = 0.0;
#pragma omp parallel for reduction(+ : div_sq, grad_sq) schedule(static) if (mesh.num_elements() > 40 * parallel_min_cells)
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto& g = mesh.shape_gradients(e);
      const auto& nodes = mesh.element_nodes(e);
      Eigen::Matrix3d grad_u = Eigen::Matrix3d::Zero();  // (d u_i / d x_j)
      for (int a = 0; a < 4; ++a) {
        const auto s = 3 * static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)]);
        const Vec3 u(velocity[s], velocity[s + 1], velocity[s + 2]);
        grad_u += u * g.row(a);
      }
      const double v = mesh.element_volume(e);
      div_sq += v * grad_u.trace() * grad_u.trace();
      grad_sq += v * grad_u.squaredNorm();
    }
    if (gradient_l2) *gradient_l2 = std::sqrt(grad_sq);
    return std::sqrt(div_sq);
  }

  FluidStepReport step(double dt) {
    if (!(dt > 0.0)) throw SolverError(fmt::format("fluid step {}: time step {} s must be positive", steps + 1, dt));
    FluidStepReport report;
    const std::size_t n3 = 3 * static_cast<std::size_t>(num_nodes);

    // 1. Time scheme: BDF1 on the first step after a reset, else the scene's
    //    (variable-step BDF2, omega = dt / dt_previous).
    const bool bdf2 = spec.time_scheme == TimeScheme::bdf2 && steps_since_reset >= 1 && std::isfinite(dt);
    double alpha0 = 1.0, alpha1 = -1.0, alpha2 = 0.0;
    double omega = 1.0;
    if (bdf2) {
      omega = dt / dt_previous;
      alpha0 = (1.0 + 2.0 * omega) / (1.0 + omega);
      alpha1 = -(1.0 + omega);
      alpha2 = omega * omega / (1.0 + omega);
    }
    for (std::size_t i = 0; i < n3; ++i) {
      history[i] = -(alpha1 * velocity_n[i] + alpha2 * velocity_nm1[i]);
      // First Picard guess: extrapolated velocity (second order) when a history exists.
      advecting[i] = bdf2 ? (1.0 + omega) * velocity_n[i] - omega * velocity_nm1[i] : velocity_n[i];
    }
    const double time_new = time_s + (std::isfinite(dt) ? dt : 0.0);
    // d(eps)/dt of Eq. 18 with the velocity's BDF coefficients (0 for a steady
    // solve, with the switch off, or for the simplified model).
    if (volume_averaged && spec.porosity_time_derivative && std::isfinite(dt)) {
      for (std::size_t i = 0; i < porosity_rate.size(); ++i)
        porosity_rate[i] = (alpha0 * porosity_new[i] + alpha1 * porosity_n[i] + alpha2 * porosity_nm1[i]) / dt;
    } else {
      std::fill(porosity_rate.begin(), porosity_rate.end(), 0.0);
    }
    // Initial guess of the (first) linear solve: the extrapolated velocity and
    // pressure (p^n after a reset); constrained components are replaced by
    // their identity rows anyway. Measured on the plume mesh: 27 Krylov
    // iterations a step instead of 32 from u*, p^n.
    std::copy(pressure.begin(), pressure.end(), pressure_n.begin());
    for (Index node = 0; node < num_nodes; ++node) {
      const auto s = static_cast<std::size_t>(node);
      for (int d = 0; d < 3; ++d)
        solution[dofs_per_node * node + d] = advecting[3 * s + static_cast<std::size_t>(d)];
      solution[pressure_row(node)] =
          bdf2 ? (1.0 + omega) * pressure[s] - omega * pressure_nm1[s] : pressure[s];
    }

    // 2. Linearization. Extrapolated (semi-implicit BDF): one solve with the
    //    advecting velocity u* above; its error u^{n+1} - u* = O(dt^2) enters
    //    the convection term only, so the step keeps BDF2's local O(dt^3).
    //    A steady solve (dt = inf) has no history to extrapolate: Picard.
    //    Picard: assemble with the last iterate, solve, compare, repeat.
    const double mass_rate = std::isfinite(dt) ? alpha0 / dt : 0.0;
    if (mass_rate != preconditioner_mass_rate) {
      preconditioner_ready = false;  // rebuilt by this step's first solve
      preconditioner_mass_rate = mass_rate;
    }
    const bool extrapolated = spec.linearization == FluidLinearization::extrapolated && std::isfinite(dt);
    bool converged = false;
    const int max_picard = extrapolated ? 1 : std::max(1, spec.max_picard_iterations);
    // (An inexact Picard with linear tolerance 1e-2 x the last update was
    // tried: on the plume mesh it doubled the Picard count and saved no
    // Krylov iterations, so every solve uses the scene's tolerance.)
    const double tolerance = spec.linear_tolerance;
    if (projection) {
      if (!std::isfinite(dt))
        throw SolverError(fmt::format("fluid step {}: fluid.scheme: projection has no steady solve (dt = inf); "
                                      "use scheme: monolithic", steps + 1));
      prescribe(time_new);
      const ProjectionStepResult r = projection->step(
          {.dt = dt, .alpha0 = alpha0, .advecting = advecting, .history = history, .body_force = body_force,
           .prescribed = {prescribed.data(), static_cast<std::size_t>(prescribed.size())},
           .exchange_beta = exchange_beta, .exchange_velocity = exchange_velocity,
           .linear_tolerance = tolerance, .max_linear_iterations = spec.max_linear_iterations},
          steps + 1, velocity, pressure);
      report.picard_iterations = 1;
      report.picard_converged = true;
      report.linear_iterations = r.predictor_iterations;
      report.linear_residual = r.predictor_residual;
      report.assembly_seconds = r.assembly_seconds;
      report.solve_seconds = r.solve_seconds;
      double change_sq = 0.0, norm_sq = 0.0;
      for (std::size_t i = 0; i < n3; ++i) {
        change_sq += (velocity[i] - advecting[i]) * (velocity[i] - advecting[i]);
        norm_sq += velocity[i] * velocity[i];
      }
      report.picard_change = norm_sq > 0.0 ? std::sqrt(change_sq / norm_sq) : std::sqrt(change_sq);
      // The monolithic layout's copy: the checkpoint's `solution` and set_velocity's guess.
      for (Index node = 0; node < num_nodes; ++node) {
        const auto s = static_cast<std::size_t>(node);
        for (int d = 0; d < 3; ++d) solution[dofs_per_node * node + d] = velocity[3 * s + static_cast<std::size_t>(d)];
        solution[pressure_row(node)] = pressure[s];
      }
      converged = true;
    }
    for (int k = 1; k <= max_picard && !projection; ++k) {
      auto t0 = Clock::now();
      assemble(dt, alpha0, time_new);
      report.assembly_seconds += seconds_since(t0);
      t0 = Clock::now();
      solve_linear(report, k, tolerance);
      report.solve_seconds += seconds_since(t0);
      unpack_solution();
      double change_sq = 0.0, norm_sq = 0.0;
      for (std::size_t i = 0; i < n3; ++i) {
        change_sq += (velocity[i] - advecting[i]) * (velocity[i] - advecting[i]);
        norm_sq += velocity[i] * velocity[i];
      }
      report.picard_iterations = k;
      report.picard_change = norm_sq > 0.0 ? std::sqrt(change_sq / norm_sq) : std::sqrt(change_sq);
      if (!std::isfinite(report.picard_change))
        throw SolverError(fmt::format("fluid step {}: Picard iteration {}: non-finite velocity", steps + 1, k));
      std::copy(velocity.begin(), velocity.end(), advecting.begin());
      if (extrapolated || report.picard_change <= spec.picard_tolerance) {
        converged = true;
        break;
      }
    }
    // Picard contracts with factor ~ dt |grad u|; an update still larger than the
    // velocity itself after the allowed iterations means it diverges.
    if (!converged && spec.max_picard_iterations > 1 && report.picard_change > 1.0)
      throw SolverError(fmt::format(
          "fluid step {} (t = {:.6g} s): Picard iteration diverges: relative update {:.3e} after {} iterations "
          "(picard_tolerance {:.1e}); reduce the fluid time step",
          steps + 1, time_s, report.picard_change, report.picard_iterations, spec.picard_tolerance));
    report.picard_converged = converged;

    // 3. Advance the history.
    velocity_nm1.swap(velocity_n);
    pressure_nm1.swap(pressure_n);
    porosity_nm1.swap(porosity_n);
    std::copy(porosity_new.begin(), porosity_new.end(), porosity_n.begin());
    std::copy(velocity.begin(), velocity.end(), velocity_n.begin());
    time_s = time_new;
    dt_previous = dt;
    ++steps;
    ++steps_since_reset;
    if (options.report_divergence) {
      double gradient_l2 = 0.0;
      report.divergence_l2 = divergence_l2(&gradient_l2);
      report.divergence_relative = gradient_l2 > 0.0 ? report.divergence_l2 / gradient_l2 : 0.0;
    }
    report.time_s = time_s;
    return report;
  }
};

FluidSolver::FluidSolver(const BoxMesh& mesh, const Scene& scene, FluidSolverOptions options)
    : impl_(std::make_unique<Impl>(mesh, scene, options)) {}
FluidSolver::~FluidSolver() = default;
FluidSolver::FluidSolver(FluidSolver&&) noexcept = default;
FluidSolver& FluidSolver::operator=(FluidSolver&&) noexcept = default;

void FluidSolver::set_body_force(std::span<const double> nodal_force_density) {
  if (nodal_force_density.size() != impl_->body_force.size())
    throw SolverError(fmt::format("fluid: body force has {} values, expected 3 x {} nodes",
                                  nodal_force_density.size(), impl_->num_nodes));
  std::copy(nodal_force_density.begin(), nodal_force_density.end(), impl_->body_force.begin());
}

void FluidSolver::set_porosity(std::span<const double> element_porosity) {
  auto& m = *impl_;
  if (element_porosity.size() != m.element_porosity.size())
    throw SolverError(fmt::format("fluid: porosity has {} values, expected one per element ({})",
                                  element_porosity.size(), m.element_porosity.size()));
  for (std::size_t e = 0; e < element_porosity.size(); ++e)
    if (!(element_porosity[e] > 0.0 && element_porosity[e] <= 1.0))
      throw SolverError(fmt::format("fluid: porosity {} of element {} is outside (0, 1]", element_porosity[e], e));
  std::copy(element_porosity.begin(), element_porosity.end(), m.element_porosity.begin());
  // Lumped L2 projection onto P1: eps_n = sum_e (V_e / 4) eps_e / sum_e V_e / 4.
  std::fill(m.porosity_new.begin(), m.porosity_new.end(), 0.0);
  for (Index e = 0; e < m.mesh.num_elements(); ++e) {
    const double weight = m.mesh.element_volume(e) / 4.0 * element_porosity[static_cast<std::size_t>(e)];
    for (Index a : m.mesh.element_nodes(e)) m.porosity_new[static_cast<std::size_t>(a)] += weight;
  }
  for (std::size_t n = 0; n < m.porosity_new.size(); ++n) m.porosity_new[n] /= m.node_volume[n];
  if (!m.porosity_given) {  // the history starts here: the first rate is zero
    m.porosity_n = m.porosity_new;
    m.porosity_nm1 = m.porosity_new;
    m.porosity_given = true;
  }
}

void FluidSolver::set_momentum_exchange(std::span<const double> element_beta,
                                        std::span<const double> element_particle_velocity) {
  auto& m = *impl_;
  if (element_beta.empty() && element_particle_velocity.empty()) {
    m.exchange_beta.clear();
    m.exchange_velocity.clear();
    return;
  }
  const auto elements = static_cast<std::size_t>(m.mesh.num_elements());
  if (element_beta.size() != elements || element_particle_velocity.size() != 3 * elements)
    throw SolverError(fmt::format("fluid: momentum exchange has {} coefficients and {} velocity values, expected {} "
                                  "and 3 x {}",
                                  element_beta.size(), element_particle_velocity.size(), elements, elements));
  for (std::size_t e = 0; e < elements; ++e)
    if (!(element_beta[e] >= 0.0 && std::isfinite(element_beta[e])))
      throw SolverError(fmt::format("fluid: momentum exchange coefficient {} of element {} must be finite and >= 0",
                                    element_beta[e], e));
  m.exchange_beta.assign(element_beta.begin(), element_beta.end());
  m.exchange_velocity.assign(element_particle_velocity.begin(), element_particle_velocity.end());
}

Vec3 FluidSolver::pressure_gradient(Index element) const {
  const auto& g = impl_->mesh.shape_gradients(element);
  const auto& nodes = impl_->mesh.element_nodes(element);
  Vec3 grad = Vec3::Zero();
  for (std::size_t a = 0; a < 4; ++a)
    grad += impl_->pressure[static_cast<std::size_t>(nodes[a])] * g.row(static_cast<Eigen::Index>(a)).transpose();
  return grad;
}

FluidStepReport FluidSolver::step(double dt) { return impl_->step(dt); }

std::span<const double> FluidSolver::velocity() const { return impl_->velocity; }
std::span<const double> FluidSolver::pressure() const { return impl_->pressure; }

Vec3 FluidSolver::velocity_at(Index element, const Eigen::Vector4d& volume_coordinates) const {
  const auto& nodes = impl_->mesh.element_nodes(element);
  Vec3 u = Vec3::Zero();
  for (std::size_t a = 0; a < 4; ++a) {
    const auto s = 3 * static_cast<std::size_t>(nodes[a]);
    u += volume_coordinates[static_cast<Eigen::Index>(a)] *
         Vec3(impl_->velocity[s], impl_->velocity[s + 1], impl_->velocity[s + 2]);
  }
  return u;
}

double FluidSolver::time() const { return impl_->time_s; }
int FluidSolver::step_count() const { return impl_->steps; }
const BoxMesh& FluidSolver::mesh() const { return impl_->mesh; }

void FluidSolver::set_velocity(std::span<const double> nodal_velocity) {
  auto& m = *impl_;
  if (nodal_velocity.size() != m.velocity.size())
    throw SolverError(fmt::format("fluid: initial velocity has {} values, expected 3 x {} nodes",
                                  nodal_velocity.size(), m.num_nodes));
  std::copy(nodal_velocity.begin(), nodal_velocity.end(), m.velocity.begin());
  std::copy(nodal_velocity.begin(), nodal_velocity.end(), m.velocity_n.begin());
  std::copy(nodal_velocity.begin(), nodal_velocity.end(), m.velocity_nm1.begin());
  for (Index node = 0; node < m.num_nodes; ++node)
    for (int d = 0; d < 3; ++d)
      m.solution[dofs_per_node * node + d] = nodal_velocity[3 * static_cast<std::size_t>(node) + static_cast<std::size_t>(d)];
  m.steps_since_reset = 0;
}

void FluidSolver::set_time(double time_s) { impl_->time_s = time_s; }
void FluidSolver::set_boundary_velocity(BoundaryVelocity field) { impl_->boundary_field = std::move(field); }
void FluidSolver::set_inlet_velocity(BoxFace face, const Vec3& velocity_m_s) {
  auto& m = *impl_;
  FaceBoundary& f = m.spec.faces[static_cast<std::size_t>(face)];
  if (f.condition != FaceCondition::inlet)
    throw SolverError(fmt::format("fluid: set_inlet_velocity on face {}, which is not an inlet", static_cast<int>(face)));
  if (!velocity_m_s.allFinite())
    throw SolverError(fmt::format("fluid: inlet velocity ({}, {}, {}) is not finite", velocity_m_s.x(), velocity_m_s.y(),
                                  velocity_m_s.z()));
  f.velocity = velocity_m_s;
  // Same conditions, new values: which unknowns are prescribed (and so the
  // reduced pattern) does not change.
  m.constraints = fluid_constraints(m.mesh, m.spec);
}
Index FluidSolver::pressure_reference_node() const { return impl_->constraints.pressure_node; }
double FluidSolver::divergence_l2() const { return impl_->divergence_l2(); }

double FluidSolver::assemble_only(double dt) {
  auto& m = *impl_;
  std::copy(m.velocity_n.begin(), m.velocity_n.end(), m.advecting.begin());
  const auto start = Clock::now();
  m.assemble(dt, 1.0, m.time_s + dt);
  return seconds_since(start);
}

// Checkpoint, section "FLUI" (layout: the order of the writes). Marks the
// preconditioner for refactoring: a checkpoint is a refactor point (header).
void FluidSolver::save_state(std::ostream& out) const {
  Impl& m = *impl_;
  checkpoint::Writer w(out);
  w.section("FLUI", 2);
  w.u64(static_cast<std::uint64_t>(m.num_nodes));
  w.f64(m.time_s);
  w.f64(m.dt_previous);
  w.i64(m.steps);
  w.i64(m.steps_since_reset);
  w.doubles({m.solution.data(), static_cast<std::size_t>(m.solution.size())});
  for (const auto* v : {&m.velocity, &m.pressure, &m.velocity_n, &m.velocity_nm1, &m.pressure_n, &m.pressure_nm1,
                        &m.body_force})
    w.doubles(*v);
  // Version 2: the volume-averaged state (porosity history, momentum exchange).
  w.boolean(m.porosity_given);
  for (const auto* v : {&m.element_porosity, &m.porosity_new, &m.porosity_n, &m.porosity_nm1, &m.exchange_beta,
                        &m.exchange_velocity})
    w.doubles(*v);
  m.preconditioner_ready = false;
}

void FluidSolver::load_state(std::istream& in) {
  Impl& m = *impl_;
  checkpoint::Reader r(in);
  const std::uint32_t version = r.section("FLUI", 2);
  const std::uint64_t nodes = r.u64("the fluid node count");
  if (nodes != static_cast<std::uint64_t>(m.num_nodes))
    throw SolverError(fmt::format("checkpoint: fluid mesh of {} nodes, this run has {}", nodes, m.num_nodes));
  const double time_s = r.f64("the fluid time"), dt_previous = r.f64("the previous fluid step");
  const std::int64_t steps = r.i64("the fluid step count"), since_reset = r.i64("the BDF start state");
  if (steps < 0 || since_reset < 0 || since_reset > steps || steps > std::numeric_limits<int>::max())
    throw SolverError("checkpoint: fluid step counts out of range (corrupt)");
  const auto n = static_cast<std::size_t>(m.num_nodes);
  const std::vector<double> solution = r.doubles_exactly("the fluid solution", dofs_per_node * n);
  std::vector<std::vector<double>> fields;
  for (const auto* v : {&m.velocity, &m.pressure, &m.velocity_n, &m.velocity_nm1, &m.pressure_n, &m.pressure_nm1,
                        &m.body_force})
    fields.push_back(r.doubles_exactly("a fluid field", v->size()));
  // Version 1 (before the volume-averaged models): eps = 1, no exchange.
  const auto elements = static_cast<std::size_t>(m.mesh.num_elements());
  bool porosity_given = false;
  std::vector<std::vector<double>> averaged{std::vector<double>(elements, 1.0), std::vector<double>(n, 1.0),
                                            std::vector<double>(n, 1.0), std::vector<double>(n, 1.0),
                                            std::vector<double>{}, std::vector<double>{}};
  if (version >= 2) {
    porosity_given = r.boolean("whether a porosity was given");
    averaged[0] = r.doubles_exactly("the element porosity", elements);
    for (std::size_t i = 1; i < 4; ++i) averaged[i] = r.doubles_exactly("a nodal porosity", n);
    averaged[4] = r.doubles("the momentum exchange coefficients", elements);
    averaged[5] = r.doubles("the momentum exchange velocities", 3 * elements);
    if (averaged[5].size() != 3 * averaged[4].size() || (!averaged[4].empty() && averaged[4].size() != elements))
      throw SolverError("checkpoint: fluid momentum exchange of mismatched size (corrupt)");
  }
  m.solution = Eigen::Map<const Eigen::VectorXd>(solution.data(), static_cast<Eigen::Index>(solution.size()));
  std::size_t k = 0;
  for (auto* v : {&m.velocity, &m.pressure, &m.velocity_n, &m.velocity_nm1, &m.pressure_n, &m.pressure_nm1,
                  &m.body_force})
    *v = std::move(fields[k++]);
  m.porosity_given = porosity_given;
  k = 0;
  for (auto* v : {&m.element_porosity, &m.porosity_new, &m.porosity_n, &m.porosity_nm1, &m.exchange_beta,
                  &m.exchange_velocity})
    *v = std::move(averaged[k++]);
  m.time_s = time_s;
  m.dt_previous = dt_previous;
  m.steps = static_cast<int>(steps);
  m.steps_since_reset = static_cast<int>(since_reset);
  m.preconditioner_ready = false;
}

}  // namespace fdem

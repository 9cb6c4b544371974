// Fluid solver cost: assembly and one full implicit time step on box meshes
// of ~1e3 to ~1e5 tetrahedra (quick set), 1 and 2 threads, and one step on
// each study mesh. Counters: elements, elements_per_s (rate), and for steps
// the Picard and Krylov iteration counts.
//
// The ~1e6-element meshes (59^3 cells, ~5 GB-free memory needed, minutes per
// step on 2 cores) are registered only with FDEM_BENCH_FLUID_LARGE=1 in the
// environment, and then best run alone:
//   FDEM_BENCH_FLUID_LARGE=1 bench_fluid --benchmark_filter=Large
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "fluid/fluid_solver.hpp"

namespace {

using namespace fdem;

// A blob of downward force density, like a particle cloud's source term, so
// that the step has a flow to converge on.
std::vector<double> blob_force(const BoxMesh& mesh, double force_density) {
  std::vector<double> f(3 * static_cast<std::size_t>(mesh.num_nodes()), 0.0);
  const Vec3 centre = 0.5 * (mesh.lower() + mesh.upper()) + Vec3(0, 0, 0.25 * (mesh.upper().z() - mesh.lower().z()));
  const double radius = 0.2 * (mesh.upper() - mesh.lower()).minCoeff();
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if ((mesh.node(n) - centre).norm() < radius) f[3 * static_cast<std::size_t>(n) + 2] = -force_density;
  return f;
}

// Linear tolerance 1e-8: the value this solver's owner asked to be the scene
// default (verify_fluid_mms LinearTolerance1e8And1e6_...: it changes the
// discretization error by ~1e-6); everything else the scene's defaults.
constexpr double bench_linear_tolerance = 1e-8;

Scene closed_box() {
  Scene scene;  // water, no-slip walls, BDF2, extrapolated linearization
  scene.fluid.linear_tolerance = bench_linear_tolerance;
  return scene;
}

struct Study {
  const char* name;
  Vec3 upper;
  std::array<int, 3> cells;
  double dt;
  bool channel;
  FluidScheme scheme = FluidScheme::monolithic;
};

// The paper's meshes (Sect. 4.1-4.4, Table 2). The finest mesh-sensitivity mesh: cells of
// 3 d = 2.28 mm in the settling box, 19 x 19 x 35 cells.
const Study studies[] = {
    {"settling_12100", Vec3(0.044, 0.044, 0.08), {11, 11, 20}, 0.01, false},
    {"channel_6000", Vec3(0.012, 0.0018, 0.012), {20, 3, 20}, 5e-3, true},
    {"plume_12500", Vec3(0.1, 0.1, 0.25), {10, 10, 25}, 1e-3, false},
    {"mesh_sensitivity_3d_63175", Vec3(0.044, 0.044, 0.08), {19, 19, 35}, 0.01, false},
    // The plume as its scene runs it (verification/plume/plume.yaml: fluid.scheme projection).
    {"plume_12500_projection", Vec3(0.1, 0.1, 0.25), {10, 10, 25}, 1e-3, false, FluidScheme::projection},
};

Scene channel_scene() {
  Scene scene;
  scene.fluid.linear_tolerance = bench_linear_tolerance;
  using FC = FaceCondition;
  auto& f = scene.fluid.faces;
  f[0] = {FC::inlet, Vec3(0.03, 0.0, 0.0), 0.004};  // 30 mm/s above a 4 mm bed
  f[1].condition = FC::outlet;
  f[2].condition = FC::free_slip;
  f[3].condition = FC::free_slip;
  f[4].condition = FC::no_slip;
  f[5].condition = FC::free_slip;
  return scene;
}

void set_threads(benchmark::State& state, int threads) {
  omp_set_num_threads(threads);
  state.counters["threads"] = threads;
}

void BM_FluidAssembly(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  set_threads(state, static_cast<int>(state.range(1)));
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.1, 0.1, 0.1), {n, n, n});
  FluidSolver solver(mesh, closed_box());
  solver.set_body_force(blob_force(mesh, 500.0));
  for (auto _ : state) state.SetIterationTime(solver.assemble_only(1e-3));
  state.counters["elements"] = mesh.num_elements();
  state.counters["elements_per_s"] =
      benchmark::Counter(static_cast<double>(mesh.num_elements()), benchmark::Counter::kIsIterationInvariantRate);
}

// Times steps of a solver that has its force: two warm-up steps (the
// preconditioner built, the BDF2 history in place), then one step per
// benchmark iteration. Counters: elements and elements per second, Picard
// and Krylov iterations, preconditioner rebuilds (ILUT refactorisations or
// PETSc set-ups) per step, and the assembly and the linear solve alone (the
// step's assembly_seconds and solve_seconds: ILUT refactorisation when due +
// BiCGSTAB, or PETSc's set-up + KSP): wall ms per step, the solve's
// throughput in elements/s.
void timed_steps(benchmark::State& state, FluidSolver& solver, const BoxMesh& mesh, double dt) {
  solver.set_body_force(blob_force(mesh, 500.0));
  solver.step(dt);
  solver.step(dt);
  double picard = 0, krylov = 0, steps = 0, assembly = 0, solve = 0, rebuilds = 0;
  for (auto _ : state) {
    const FluidStepReport r = solver.step(dt);
    picard += r.picard_iterations;
    krylov += r.linear_iterations;
    rebuilds += r.preconditioner_factorizations;
    assembly += r.assembly_seconds;
    solve += r.solve_seconds;
    steps += 1;
  }
  state.counters["elements"] = mesh.num_elements();
  state.counters["elements_per_s"] =
      benchmark::Counter(static_cast<double>(mesh.num_elements()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["picard_per_step"] = picard / steps;
  state.counters["krylov_per_step"] = krylov / steps;
  state.counters["rebuilds_per_step"] = rebuilds / steps;
  state.counters["assembly_ms"] = 1e3 * assembly / steps;  // wall
  state.counters["solve_ms"] = 1e3 * solve / steps;        // wall
  state.counters["solve_elements_per_s"] =
      solve > 0.0 ? static_cast<double>(mesh.num_elements()) * steps / solve : 0.0;
}

void step_benchmark(benchmark::State& state, const BoxMesh& mesh, const Scene& scene, double dt) {
  FluidSolver solver(mesh, scene);
  timed_steps(state, solver, mesh, dt);
}

void BM_FluidStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  set_threads(state, static_cast<int>(state.range(1)));
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.1, 0.1, 0.1), {n, n, n});
  step_benchmark(state, mesh, closed_box(), 1e-3);
}

void BM_FluidStudyStep(benchmark::State& state, const Study& study) {
  set_threads(state, static_cast<int>(state.range(0)));
  const BoxMesh mesh(Vec3::Zero(), study.upper, study.cells);
  Scene scene = study.channel ? channel_scene() : closed_box();
  scene.fluid.scheme = study.scheme;
  step_benchmark(state, mesh, scene, study.dt);
}

// Solver settings compared on the study meshes (the step's speed/accuracy
// trade-offs): linearization, linear tolerance, preconditioner.
struct Variant {
  const char* name;
  FluidLinearization linearization;
  double linear_tolerance;
  FluidSolverOptions options;
};

const Variant variants[] = {
    {"picard_tol1e-10", FluidLinearization::picard, 1e-10, {}},
    {"picard_tol1e-8", FluidLinearization::picard, 1e-8, {}},
    {"extrapolated_tol1e-10", FluidLinearization::extrapolated, 1e-10, {}},
    {"extrapolated_tol1e-8", FluidLinearization::extrapolated, 1e-8, {}},
    {"extrapolated_tol1e-8_ilut1e-3x5", FluidLinearization::extrapolated, 1e-8,
     {.ilut_drop_tolerance = 1e-3, .ilut_fill_factor = 5}},
    {"extrapolated_tol1e-8_ilut3e-2x2", FluidLinearization::extrapolated, 1e-8,
     {.ilut_drop_tolerance = 3e-2, .ilut_fill_factor = 2}},
    {"extrapolated_tol1e-8_ilut1e-2x2", FluidLinearization::extrapolated, 1e-8,
     {.ilut_drop_tolerance = 1e-2, .ilut_fill_factor = 2}},
    {"extrapolated_tol1e-6", FluidLinearization::extrapolated, 1e-6, {}},
    {"extrapolated_tol1e-8_refactor20", FluidLinearization::extrapolated, 1e-8,
     {.refactor_above_iterations = 20}},
    {"extrapolated_tol1e-8_refactor80", FluidLinearization::extrapolated, 1e-8,
     {.refactor_above_iterations = 80}},
};

// One thread, a fixed 10 timed steps after 2 warm-up steps: compare the CPU
// column (the shared machine's load inflates wall time).
void BM_FluidStudyVariant(benchmark::State& state, const Study& study, const Variant& variant) {
  omp_set_num_threads(1);
  const BoxMesh mesh(Vec3::Zero(), study.upper, study.cells);
  Scene scene = study.channel ? channel_scene() : closed_box();
  scene.fluid.linearization = variant.linearization;
  scene.fluid.linear_tolerance = variant.linear_tolerance;
  FluidSolver solver(mesh, scene, variant.options);
  timed_steps(state, solver, mesh, study.dt);
}

// Linear solvers compared against mesh size (benchmarks/README.md, "Fluid
// linear solver"): Eigen's BiCGSTAB + ILUT against PETSc's defaults and the
// block preconditioners tried for them. One thread.
struct SolverCase {
  const char* name;
  FluidLinearSolver solver;
  const char* petsc_options;
};

const SolverCase solver_cases[] = {
    {"eigen_bicgstab_ilut", FluidLinearSolver::bicgstab_ilut, ""},
    // fieldsplit Schur (upper, a11: two BoomerAMG V-cycles on A_pp), BoomerAMG on both blocks: petsc_default_options
    {"petsc_default", FluidLinearSolver::petsc, ""},
    // the default before 2026-12-02: selfp, one V-cycle on it
    {"petsc_fieldsplit_selfp", FluidLinearSolver::petsc,
     "-pc_fieldsplit_schur_precondition selfp -fieldsplit_p_ksp_type preonly"},
    {"petsc_boomeramg_monolithic", FluidLinearSolver::petsc,
     "-pc_type hypre -pc_hypre_type boomeramg -pc_hypre_boomeramg_strong_threshold 0.7 "
     "-pc_hypre_boomeramg_coarsen_type HMIS -pc_hypre_boomeramg_interp_type ext+i -pc_hypre_boomeramg_P_max 4 "
     "-pc_hypre_boomeramg_agg_nl 1"},
    {"petsc_fgmres_ilu0", FluidLinearSolver::petsc, "-pc_type bjacobi -sub_pc_type ilu"},
};

void solver_case_benchmark(benchmark::State& state, const SolverCase& solver_case, const BoxMesh& mesh, Scene scene,
                           double dt) {
  omp_set_num_threads(1);
  scene.fluid.petsc_options = solver_case.petsc_options;
  if (const char* extra = std::getenv("FDEM_BENCH_PETSC_OPTIONS"); extra && solver_case.solver == FluidLinearSolver::petsc)
    scene.fluid.petsc_options += std::string(" ") + extra;
  FluidSolver solver(mesh, scene, {.linear_solver = solver_case.solver});
  timed_steps(state, solver, mesh, dt);
}

void BM_FluidSolverScaling(benchmark::State& state, const SolverCase& solver_case) {
  const int n = static_cast<int>(state.range(0));
  solver_case_benchmark(state, solver_case, BoxMesh(Vec3::Zero(), Vec3(0.1, 0.1, 0.1), {n, n, n}), closed_box(),
                        1e-3);
}

void BM_FluidStudySolver(benchmark::State& state, const Study& study, const SolverCase& solver_case) {
  solver_case_benchmark(state, solver_case, BoxMesh(Vec3::Zero(), study.upper, study.cells),
                        study.channel ? channel_scene() : closed_box(), study.dt);
}

// Cube meshes of n^3 cells = 5 n^3 tetrahedra: 1080, 8640, 40000, 98415.
constexpr int quick_sizes[] = {6, 12, 20, 27};

}  // namespace

int main(int argc, char** argv) {
  // Timed steps per variant (default 10). Two runs under `perf stat -e
  // instructions:u` with different counts give instructions per step free of
  // the set-up and of the machine's load.
  const char* steps_env = std::getenv("FDEM_BENCH_FLUID_STEPS");
  const benchmark::IterationCount variant_steps = steps_env ? std::max(1L, std::atol(steps_env)) : 10;
  for (int threads : {1, 2})
    for (int n : quick_sizes) {
      benchmark::RegisterBenchmark("BM_FluidAssembly", BM_FluidAssembly)
          ->Args({n, threads})->UseManualTime()->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark("BM_FluidStep", BM_FluidStep)
          ->Args({n, threads})->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(0.2);
    }
  for (const Study& s : studies)
    benchmark::RegisterBenchmark((std::string("BM_FluidStudyStep/") + s.name).c_str(), BM_FluidStudyStep, s)
        ->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(0.2);
  for (std::size_t i = 0; i < 3; ++i)
    for (const Variant& v : variants)
      benchmark::RegisterBenchmark((std::string("BM_FluidStudyVariant/") + studies[i].name + "/" + v.name).c_str(),
                                   BM_FluidStudyVariant, studies[i], v)
          ->Iterations(variant_steps)->Unit(benchmark::kMillisecond);
  // 8640 to 1.03e6 tetrahedra; the largest two only with FDEM_BENCH_FLUID_LARGE=1.
  const char* large = std::getenv("FDEM_BENCH_FLUID_LARGE");
  const bool with_large = large && std::string(large) == "1";
  for (std::size_t i = 0; i < 3; ++i)
    for (const SolverCase& c : solver_cases)
      benchmark::RegisterBenchmark((std::string("BM_FluidStudySolver/") + studies[i].name + "/" + c.name).c_str(),
                                   BM_FluidStudySolver, studies[i], c)
          ->Iterations(variant_steps)->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const SolverCase& c : solver_cases)
    for (int n : {12, 20, 27, 40, 59}) {
      if (n > 27 && !with_large) continue;
      benchmark::RegisterBenchmark((std::string("BM_FluidSolverScaling/") + c.name).c_str(), BM_FluidSolverScaling, c)
          ->Arg(n)->Iterations(n > 27 ? 2 : 5)->UseRealTime()->Unit(benchmark::kMillisecond);
    }
  if (large && std::string(large) == "1")
    for (int threads : {1, 2}) {
      benchmark::RegisterBenchmark("BM_FluidAssemblyLarge", BM_FluidAssembly)
          ->Args({59, threads})->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(2);
      benchmark::RegisterBenchmark("BM_FluidStepLarge", BM_FluidStep)
          ->Args({59, threads})->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(1);
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

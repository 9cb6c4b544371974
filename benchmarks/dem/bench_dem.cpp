// DEM engine throughput on the LIGGGHTS anchor scenes, set up exactly as
// ../shared/anchors/liggghts/README.md runs them (contact model, walls, dt,
// skin, step counts), so particle-steps/s compare directly with LIGGGHTS's
// "Loop time" figures (setup excluded on both sides).
//   P: 28224 grains, free fall in a 0.1 x 0.1 x 0.25 m walled box, Kn 100 N/m,
//      Cn 8.5e-4 N s/m (absolute), dt 1e-5 s, skin 3e-4 m, 5000 steps.
//   B: 4800 grains, settled bed in 0.012 x 0.0018 x 0.012 m, Kn 1e5 N/m,
//      Cn 0.026 N s/m, dt 1e-7 s, skin 1.5e-4 m, 10000 steps.
// Environment: FDEM_ANCHORS_DIR overrides the compiled-in folder of the CSVs.
//
// Kernel micro benchmarks, public API only (dem_engine.hpp,
// neighbour_list.hpp), threads 1 and 2 as the last argument:
//   BM_NeighbourBuild_SceneP / _SceneB / _DenseLattice/<N>: one
//       NeighbourList::build (cell grid + Verlet list); particles_per_s, entries.
//   BM_ContactForces_SceneB: DemEngine steps of the settled bed B between list
//       rebuilds (the list is built before timing; rebuilds_timed must be 0):
//       contacts_per_s = contacts (pairs in overlap) x steps / s.
//   BM_Integration_Gas: 28224 grains of d 0.25 mm on a lattice of spacing 4 d
//       (solid fraction 0.8 %, no pair within the cutoff), scene P's free fall
//       (Kn 100, dt 1e-5 s, skin 3e-4 m, walls far): velocity Verlet, gravity,
//       wall tests and empty neighbour loops; particle_steps_per_s.
// Scaling (dem/scaling.py runs them, fits, writes the CSV):
//   BM_Scaling_DenseLattice/<N>/<threads>: N = n^3 spheres d 0.25 mm,
//       rho 2170, on a simple cubic lattice of spacing d with offsets uniform
//       in +-0.1 % d (about half the lattice pairs in contact, ~1.5 pairs per
//       grain as in bed B), walls touching the outer layer, scene B's Kn 1e5,
//       Cn 0.026, dt 1e-7 s, skin 1.5e-4 m.
//   BM_Scaling_Gas/<N>/<threads>: the same at spacing 4 d (contact-free).
//   N = 1e3 .. 3.1e5; 1e6 (n = 100) only with FDEM_BENCH_DEM_LARGE=1 (set-up
//   and steps ~5 s a variant on one core), which dem/scaling.py sets: the
//   trend command's runs of every benchmark stay short.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "anchor_particles.hpp"
#include "dem/dem_engine.hpp"
#include "dem/neighbour_list.hpp"

namespace {

using namespace fdem;

// P_init.csv has no velocity columns: the block starts at rest.
Particles read_anchor_csv(const std::string& name) {
  const char* env = std::getenv("FDEM_ANCHORS_DIR");
  const std::string path = std::string(env ? env : FDEM_ANCHORS_DIR) + "/" + name;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("bench_dem: cannot open " + path);
  return read_anchor_particles(in);
}

Scene anchor_scene(Vec3 upper, double kn, double cn, double dt) {
  Scene s;
  s.source_file = "bench_dem";
  s.domain.upper = upper;
  s.effects.fluid = false;
  s.effects.coupling = CouplingMode::off;
  s.effects.buoyancy = false;
  s.contact.normal_stiffness = kn;
  s.contact.normal_damping = cn;
  // P's 100 um grains are refused at dt 1e-5 (dt = 1.3 t_c, zeta 1.8); the
  // anchor runs them anyway (no contacts occur in the timed 5000 steps).
  s.contact.allow_unstable_step = true;
  s.time.dem_step = dt;
  return s;
}

void run_scene(benchmark::State& state, const Particles& initial, const Scene& scene, double skin_m,
               std::size_t steps) {
  const int threads = static_cast<int>(state.range(0));
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  DemDiagnostics last;
  for (auto _ : state) {
    state.PauseTiming();
    DemEngine dem(initial, scene);
    dem.set_skin(skin_m);
    dem.step();  // first step builds the list with this skin (setup, like LIGGGHTS's run setup)
    state.ResumeTiming();
    dem.run_sorting(steps);  // as a dry run: the grains sorted every GrainSortPolicy::interval steps
    state.PauseTiming();
    last = dem.diagnostics();
    state.ResumeTiming();
  }
  omp_set_num_threads(saved);
  const double particle_steps = static_cast<double>(initial.size() * steps);
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(particle_steps * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
  state.counters["contacts"] = static_cast<double>(last.contacts);
  state.counters["rebuilds"] = static_cast<double>(last.neighbour_rebuilds);
  state.counters["sorts"] = static_cast<double>(last.grain_sorts);
  state.counters["lost"] = static_cast<double>(last.particles_removed);
}

void BM_SceneP_SaltPlumeBlock(benchmark::State& state) {
  static const Particles p = read_anchor_csv("P_init.csv");
  static const Scene s = anchor_scene(Vec3(0.1, 0.1, 0.25), 100.0, 8.5e-4, 1e-5);
  run_scene(state, p, s, 3e-4, 5000);
}

void BM_SceneB_SettledBed(benchmark::State& state) {
  static const Particles p = read_anchor_csv("B_settled.csv");
  static const Scene s = anchor_scene(Vec3(0.012, 0.0018, 0.012), 1e5, 0.026, 1e-7);
  run_scene(state, p, s, 1.5e-4, 10000);
}

BENCHMARK(BM_SceneP_SaltPlumeBlock)->Arg(1)->Arg(2)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SceneB_SettledBed)->Arg(1)->Arg(2)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// ---------------------------------------------------------------------------
// Kernel micro benchmarks and scaling.

constexpr double kLatticeDiameter = 0.25e-3;  // [m]
constexpr double kGrainDensity = 2170.0;      // [kg/m^3], the salt of scenes P and B

// Sets OMP's thread count for one benchmark and restores it after.
class ThreadScope {
 public:
  explicit ThreadScope(int threads) : saved_(omp_get_max_threads()) { omp_set_num_threads(threads); }
  ~ThreadScope() { omp_set_num_threads(saved_); }
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

 private:
  int saved_;
};

// nx x ny x nz spheres of kLatticeDiameter at spacing `spacing_over_d` x d, each
// moved by a uniform offset of at most `jitter_over_d` x d per axis (seeded:
// the same set on every run). The first layer's centres sit d/2 from the
// origin, so walls at 0 and n x spacing touch the outer spheres when the
// spacing is d.
Particles lattice_particles(int nx, int ny, int nz, double spacing_over_d, double jitter_over_d) {
  const double d = kLatticeDiameter, a = spacing_over_d * d;
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> jitter(-jitter_over_d * d, jitter_over_d * d);
  Particles p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = (i + 0.5) * a + jitter(rng), y = (j + 0.5) * a + jitter(rng), z = (k + 0.5) * a + jitter(rng);
        p.add(x, y, z, d, kGrainDensity);
      }
  return p;
}

// Scene B's contact model and step in a box of edge `edge_m` with walls.
Scene lattice_scene(double edge_m) {
  return anchor_scene(Vec3(edge_m, edge_m, edge_m), 1e5, 0.026, 1e-7);
}

void set_common_counters(benchmark::State& state, int threads, std::size_t particles) {
  state.counters["threads"] = threads;
  state.counters["particles"] = static_cast<double>(particles);
}

void neighbour_build(benchmark::State& state, const Particles& p, double skin_m, int threads) {
  const ThreadScope scope(threads);
  NeighbourList list;
  for (auto _ : state) {
    list.build(p, skin_m);
    benchmark::DoNotOptimize(list.entries());
  }
  set_common_counters(state, threads, p.size());
  state.counters["particles_per_s"] = benchmark::Counter(
      static_cast<double>(p.size()) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["entries"] = static_cast<double>(list.entries());
  state.counters["entries_per_particle"] = static_cast<double>(list.entries()) / static_cast<double>(p.size());
}

void BM_NeighbourBuild_SceneP(benchmark::State& state) {
  static const Particles p = read_anchor_csv("P_init.csv");
  neighbour_build(state, p, 3e-4, static_cast<int>(state.range(0)));
}

void BM_NeighbourBuild_SceneB(benchmark::State& state) {
  static const Particles p = read_anchor_csv("B_settled.csv");
  neighbour_build(state, p, 1.5e-4, static_cast<int>(state.range(0)));
}

void BM_NeighbourBuild_DenseLattice(benchmark::State& state) {
  const auto n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(state.range(0)))));
  const Particles p = lattice_particles(n, n, n, 1.0, 1e-3);
  neighbour_build(state, p, 1.5e-4, static_cast<int>(state.range(1)));
}

// Steps of a live engine, `steps` per benchmark iteration; construction and
// the first step (list build) excluded. Counters from the state after timing.
void engine_steps(benchmark::State& state, const Particles& initial, const Scene& scene, double skin_m,
                  std::size_t steps, int threads) {
  const ThreadScope scope(threads);
  DemEngine dem(initial, scene);
  dem.set_skin(skin_m);
  dem.step();
  const std::size_t rebuilds_before = dem.diagnostics().neighbour_rebuilds;
  for (auto _ : state) dem.run(steps);
  const DemDiagnostics d = dem.diagnostics();
  const double iterations = static_cast<double>(state.iterations());
  const double step_count = static_cast<double>(steps) * iterations;
  set_common_counters(state, threads, initial.size());
  state.counters["steps_per_iteration"] = static_cast<double>(steps);
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(initial.size()) * step_count, benchmark::Counter::kIsRate);
  // Contacts at the end of the timed steps: a settled bed keeps its contact
  // set over these few steps (no rebuild), so contacts x steps is the work.
  state.counters["contacts"] = static_cast<double>(d.contacts);
  state.counters["contacts_per_s"] =
      benchmark::Counter(static_cast<double>(d.contacts) * step_count, benchmark::Counter::kIsRate);
  state.counters["rebuilds_timed"] = static_cast<double>(d.neighbour_rebuilds - rebuilds_before);
  state.counters["lost"] = static_cast<double>(d.particles_removed);
}

void BM_ContactForces_SceneB(benchmark::State& state) {
  static const Particles p = read_anchor_csv("B_settled.csv");
  static const Scene s = anchor_scene(Vec3(0.012, 0.0018, 0.012), 1e5, 0.026, 1e-7);
  engine_steps(state, p, s, 1.5e-4, 100, static_cast<int>(state.range(0)));
}

void BM_Integration_Gas(benchmark::State& state) {
  // 28 x 28 x 36 = 28224 grains (scene P's count) at spacing 4 d: the pair
  // cutoff d + skin = 2.2 d lists no pair, the walls are >= 1.5 d away.
  static const Particles p = lattice_particles(28, 28, 36, 4.0, 0.0);
  static const Scene s = anchor_scene(
      Vec3(28 * 4 * kLatticeDiameter, 28 * 4 * kLatticeDiameter, 36 * 4 * kLatticeDiameter), 100.0, 8.5e-4, 1e-5);
  engine_steps(state, p, s, 3e-4, 50, static_cast<int>(state.range(0)));
}

// Fixed steps per iteration (20) so the cost per particle-step is comparable
// across sizes; Google Benchmark repeats iterations up to its minimum time.
constexpr std::size_t kScalingSteps = 20;

void BM_Scaling_DenseLattice(benchmark::State& state) {
  const auto n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(state.range(0)))));
  const Particles p = lattice_particles(n, n, n, 1.0, 1e-3);
  engine_steps(state, p, lattice_scene(n * kLatticeDiameter), 1.5e-4, kScalingSteps,
               static_cast<int>(state.range(1)));
}

void BM_Scaling_Gas(benchmark::State& state) {
  const auto n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(state.range(0)))));
  const Particles p = lattice_particles(n, n, n, 4.0, 1e-3);
  engine_steps(state, p, lattice_scene(n * 4.0 * kLatticeDiameter), 1.5e-4, kScalingSteps,
               static_cast<int>(state.range(1)));
}

BENCHMARK(BM_NeighbourBuild_SceneP)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NeighbourBuild_SceneB)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NeighbourBuild_DenseLattice)
    ->ArgsProduct({{1000, 32768, 314432}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
// 100 steps of 1e-7 s per iteration; B's grains creep (2 rebuilds in the
// anchor's 10000 steps), so the count is fixed to stay between rebuilds.
BENCHMARK(BM_ContactForces_SceneB)->Arg(1)->Arg(2)->Iterations(20)->Unit(benchmark::kMillisecond)->UseRealTime();
// 10 x 50 steps of 1e-5 s: a grain falls 0.12 mm from rest, below skin/2.
BENCHMARK(BM_Integration_Gas)->Arg(1)->Arg(2)->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime();

void register_scaling() {
  // n^3 particles: 1e3, 3.4e3, 1.1e4, 3.3e4, 9.7e4, 3.1e5 (and 1e6 on request).
  std::vector<long> sizes = {1000, 3375, 10648, 32768, 97336, 314432};
  const char* large = std::getenv("FDEM_BENCH_DEM_LARGE");
  if (large && std::string(large) == "1") sizes.push_back(1000000);
  for (const char* name : {"BM_Scaling_DenseLattice", "BM_Scaling_Gas"})
    for (long n : sizes)
      for (long threads : {1L, 2L})
        benchmark::RegisterBenchmark(name, std::string(name) == "BM_Scaling_Gas" ? BM_Scaling_Gas
                                                                                 : BM_Scaling_DenseLattice)
            ->Args({n, threads})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.3);
}

}  // namespace

// --- The machine's streaming bound (how far the free-fall scene P is from it) ---
// A triad a[i] = b[i] + s c[i] over three arrays of state.range(0) bytes in
// all, the access pattern of the engine's per-particle passes: 3.8 MB is
// scene P's per-step traffic set (past L2, inside L3), 768 MB is main memory.
// bytes_per_s counts 24 bytes per element (two reads, one write; the
// write-allocate read is not counted, as in STREAM).
void BM_MachineTriad(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(1));
  const auto n = static_cast<std::ptrdiff_t>(state.range(0) / 24);
  std::vector<double> a(static_cast<std::size_t>(n), 0.0), b(static_cast<std::size_t>(n), 1.0),
      c(static_cast<std::size_t>(n), 2.0);
  double* __restrict pa = a.data();
  const double* __restrict pb = b.data();
  const double* __restrict pc = c.data();
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  for (auto _ : state) {
#pragma omp parallel for simd schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) pa[i] = pb[i] + 0.5 * pc[i];
    benchmark::DoNotOptimize(pa);
    benchmark::ClobberMemory();
  }
  omp_set_num_threads(saved);
  state.counters["bytes_per_s"] =
      benchmark::Counter(24.0 * static_cast<double>(n) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
}
BENCHMARK(BM_MachineTriad)
    ->ArgNames({"bytes", "omp"})
    ->ArgsProduct({{3800000, 768000000}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

int main(int argc, char** argv) {
  register_scaling();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

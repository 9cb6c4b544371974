// DEM engine throughput on the LIGGGHTS anchor scenes, set up exactly as
// ../shared/anchors/liggghts/README.md runs them (contact model, walls, dt,
// skin, step counts), so particle-steps/s compare directly with LIGGGHTS's
// "Loop time" figures (setup excluded on both sides).
//   P: 28224 grains, free fall in a 0.1 x 0.1 x 0.25 m walled box, Kn 100 N/m,
//      Cn 8.5e-4 N s/m (absolute), dt 1e-5 s, skin 3e-4 m, 5000 steps.
//   B: 4800 grains, settled bed in 0.012 x 0.0018 x 0.012 m, Kn 1e5 N/m,
//      Cn 0.026 N s/m, dt 1e-7 s, skin 1.5e-4 m, 10000 steps.
// Environment: FDEM_ANCHORS_DIR overrides the compiled-in folder of the CSVs.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "dem/dem_engine.hpp"

namespace {

using namespace fdem;

// Anchor CSV: id,d,rho,x,y,z[,vx,vy,vz] with one header line (P_init.csv
// has no velocity columns: the block starts at rest).
Particles read_anchor_csv(const std::string& name) {
  const char* env = std::getenv("FDEM_ANCHORS_DIR");
  const std::string path = std::string(env ? env : FDEM_ANCHORS_DIR) + "/" + name;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("bench_dem: cannot open " + path);
  Particles p;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream row(line);
    double v[9] = {};
    std::string cell;
    for (int c = 0; c < 9 && std::getline(row, cell, ','); ++c) v[c] = std::stod(cell);
    p.add(v[3], v[4], v[5], v[1], v[2], v[6], v[7], v[8]);
  }
  return p;
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
    dem.run(steps);
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

}  // namespace

BENCHMARK_MAIN();

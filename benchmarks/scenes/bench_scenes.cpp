// Scene benchmarks: one coupled step (one fluid step with its DEM subcycles,
// Fig. 2-3) of each study scene, through Simulation::step(), exactly as a
// study runs it. Scenes: the verified study scenes
// (verification/<study>/*.yaml) with the overrides benchmark_scenes.hpp names.
//
// Counters:
//   particle_steps_per_s     particles x DEM subcycles / wall time of the step
//   wall_s_per_simulated_s   wall time to advance one simulated second
//   fluid_share, dem_share, coupling_share   where the step's time went
//                            (Simulation's own per-phase timers)
//   drag_share               the part of dem_share spent on drag (Eq. 11-15) in the subcycles
//   subcycles, particles, elements
// Two steps are taken before timing: the first is BDF1 and builds the
// solver's preconditioner; the second switches to BDF2, whose matrix the old
// factors precondition badly, so it refactors and iterates long (channel:
// 0.3-0.9 s against ~0.03 s a step after it, the spread coming from the
// packed bed's sensitivity to the last bits of the drag). A steady step is
// what a run costs; 5 steps are timed so no single one dominates.
// The thread count is OpenMP's default (OMP_NUM_THREADS).
#include <benchmark/benchmark.h>

#include <chrono>

#include "coupling/simulation.hpp"
#include "benchmark_scenes.hpp"

namespace {

void BM_SceneFluidStep(benchmark::State& state, const char* study) {
  fdem::Simulation sim(fdem::bench::load_benchmark_scene(study));
  sim.step();  // BDF1 start and preconditioner set-up, not a steady step
  sim.step();  // the switch to BDF2 and its refactorisation, not a steady step either
  double fluid_s = 0.0, dem_s = 0.0, drag_s = 0.0, coupling_s = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    sim.step();
    const fdem::CouplingDiagnostics d = sim.diagnostics();
    fluid_s += d.fluid_seconds;
    dem_s += d.dem_seconds;
    drag_s += d.drag_seconds;
    coupling_s += d.coupling_seconds;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto steps = static_cast<double>(state.iterations());
  const auto particles = static_cast<double>(sim.particles().size());
  const double total = fluid_s + dem_s + coupling_s;
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(steps * sim.subcycles() * particles, benchmark::Counter::kIsRate);
  state.counters["wall_s_per_simulated_s"] = wall_s / (steps * sim.step_size());
  state.counters["fluid_share"] = total > 0.0 ? fluid_s / total : 0.0;
  state.counters["dem_share"] = total > 0.0 ? dem_s / total : 0.0;
  state.counters["coupling_share"] = total > 0.0 ? coupling_s / total : 0.0;
  state.counters["drag_share"] = total > 0.0 ? drag_s / total : 0.0;
  state.counters["subcycles"] = sim.subcycles();
  state.counters["particles"] = particles;
  state.counters["elements"] = sim.mesh() != nullptr ? sim.mesh()->num_elements() : 0;
}

// One step is 0.1-1 s, so --benchmark_min_time decides how many steps are
// timed (the smoke test's 0.001 s: one).
BENCHMARK_CAPTURE(BM_SceneFluidStep, settling, "settling")->UseRealTime()->Iterations(5)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SceneFluidStep, channel, "channel")->UseRealTime()->Iterations(5)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SceneFluidStep, plume, "plume")->UseRealTime()->Iterations(5)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

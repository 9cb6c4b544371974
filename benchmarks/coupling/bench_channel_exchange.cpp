// Time to solution of the channel study's bed case (verification/channel,
// paper Sect. 4.3) with each momentum exchange at its own largest stable
// fluid step, over the same simulated time, in one run: what the
// semi-implicit exchange (coupling/momentum_exchange.hpp) buys.
//
// The steps are those the channel study measures by bisection
// (verification/channel/README.md, "Largest stable fluid step", 0.03 s
// probes from rest): explicit 2.74e-3 s (3.16e-3 s diverges), semi-implicit
// 1e-2 s (the range's end). Each exchange runs at that step and at the one
// the studies use: explicit 1e-3 s (longer runs above it turn noisy),
// semi-implicit the paper's 5e-3 s. The bed is settled once by the study's
// own code (0.1 s dry DEM, ~6 s CPU), then each benchmark runs the bed case
// from rest (no freeze) for kSimulated_s.
// Counters: fluid_step_s, fluid_steps, and wall seconds per simulated second.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <string>

#include "channel_study.hpp"
#include "coupling/simulation.hpp"

namespace {

using fdem::MomentumExchange;

// [0]: the studies' step; [1]: the bisection's largest stable step (header).
constexpr double kExplicitStep_s[] = {1.0e-3, 2.74e-3};
constexpr double kSemiImplicitStep_s[] = {5.0e-3, 1.0e-2};
constexpr double kSimulated_s = 0.1;

struct Bed {
  fdem::Scene scene;  // the bed case, from rest
};

const Bed& bed() {
  static const Bed b = [] {
    const fdem::Scene base = fdem::channel::base_scene();
    const std::string csv = std::string(FDEM_BINARY_DIR) + "/benchmarks/coupling/channel_bed.csv";
    const fdem::channel::BedStats stats = fdem::channel::settle_bed(base, 0.1, csv);
    Bed out{fdem::channel::bed_case(base, kSimulated_s, csv, stats.top_m)};
    out.scene.coupling.freeze_until = 0.0;
    return out;
  }();
  return b;
}

void BM_ChannelTimeToSolution(benchmark::State& state) {
  omp_set_num_threads(1);
  const bool semi = state.range(0) == 1;
  fdem::Scene s = bed().scene;
  s.coupling.exchange = semi ? MomentumExchange::semi_implicit : MomentumExchange::explicit_drag;
  const auto which = static_cast<std::size_t>(state.range(1));
  s.time.fluid_step = semi ? kSemiImplicitStep_s[which] : kExplicitStep_s[which];
  s.time.subcycles = 0;
  state.SetLabel(semi ? "semi_implicit" : "explicit");
  long steps = 0;
  for (auto _ : state) {
    fdem::Simulation sim(s);
    while (!sim.finished()) sim.step();
    steps = sim.step_index();
    benchmark::DoNotOptimize(sim.fluid_velocity().data());
  }
  state.counters["fluid_step_s"] = s.time.fluid_step;
  state.counters["fluid_steps"] = static_cast<double>(steps);
  state.counters["simulated_s"] = kSimulated_s;
}

BENCHMARK(BM_ChannelTimeToSolution)
    ->ArgNames({"semi_implicit", "largest_stable"})
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

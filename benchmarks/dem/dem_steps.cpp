// dem_steps: a fixed number of DEM steps of one dry scene, with a hash of the
// final state, for two jobs the Google Benchmark runs cannot do:
//   * instruction counts (valgrind --tool=callgrind, load-independent): the
//     cost of a step is the difference of two runs of different length, so
//     reading the CSV and building the engine cancel;
//   * bit-identity between engine versions and thread counts: the hash
//     (FNV-1a over the bits of position, velocity and force, particles taken
//     in the order of their id) must not move when only speed was meant to.
// Scenes (set up as bench_dem.cpp and ../shared/anchors/liggghts/README.md):
//   P      the anchors' free-falling block (P_init.csv), skin 3e-4 m;
//   B      the anchors' settled bed (B_settled.csv), skin 1.5e-4 m;
//   cloud  a state of the coupled plume (plume_dem_profile --write-dem-csv)
//          with verification/plume/plume.yaml's box, contact law, step and
//          default skin, run dry: gravity, contacts and walls, no fluid, so
//          drag and buoyancy are absent and the cloud's contacts over a few
//          hundred steps are those of the coupled run.
// Prints one JSON object.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "anchor_particles.hpp"
#include "dem/dem_engine.hpp"

namespace {

using namespace fdem;

Particles read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "--csv", path, "cannot open the particle CSV");
  return read_anchor_particles(in);
}

std::uint64_t state_hash(const Particles& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (p.id.size() == p.size())
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::uint64_t v) {
    for (int k = 0; k < 8; ++k) {
      h ^= (v >> (8 * k)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  for (std::size_t i : order) {
    mix(p.id.empty() ? i : static_cast<std::uint64_t>(p.id[i]));
    for (const auto* v : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz})
      mix(std::bit_cast<std::uint64_t>((*v)[i]));
  }
  return h;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DEM steps of a dry scene (P, B or a plume cloud): state hash and phase times, for callgrind"};
  std::string scene_name = "P", csv;
  long steps = 100;
  int threads = 1;
  std::size_t sort_interval = DemEngine::GrainSortPolicy{}.interval;
  bool sort_first = false;
  bool step_quantiles = false;
  app.add_option("--scene", scene_name, "P, B or cloud")->check(CLI::IsMember({"P", "B", "cloud"}));
  app.add_option("--csv", csv, "particle CSV (default: the anchor's for P and B; required for cloud)");
  app.add_option("--steps", steps, "DEM steps after the first")->check(CLI::NonNegativeNumber);
  app.add_option("--threads", threads, "OpenMP threads")->check(CLI::PositiveNumber);
  app.add_option("--sort-interval", sort_interval, "DEM steps between grain sorts, as a dry run sorts (0: never)");
  app.add_flag("--sort-first", sort_first, "sort the grains before the timed steps (a cloud read from an older run)");
  app.add_flag("--step-quantiles", step_quantiles,
               "time every step and print the 5/10/25/50 % quantiles of the step times: on a loaded machine the "
               "low quantiles are the steps no other process interrupted (two threads spin while one is "
               "descheduled, so whole-run times measure the scheduler)");
  CLI11_PARSE(app, argc, argv);
  return run_with_exit_codes("dem_steps", [&] {
    omp_set_num_threads(threads);
    Scene s;
    s.source_file = "dem_steps";
    s.effects.fluid = false;
    s.effects.coupling = CouplingMode::off;
    s.effects.buoyancy = false;
    double skin = 0.0;  // 0: the engine's default
    if (scene_name == "P") {
      s.domain.upper = Vec3(0.1, 0.1, 0.25);
      s.contact.normal_stiffness = 100.0;
      s.contact.normal_damping = 8.5e-4;
      s.contact.allow_unstable_step = true;  // as bench_dem: the anchor runs P's 100 um grains at dt 1e-5 s
      s.time.dem_step = 1e-5;
      skin = 3e-4;
      if (csv.empty()) csv = std::string(FDEM_ANCHORS_DIR) + "/P_init.csv";
    } else if (scene_name == "B") {
      s.domain.upper = Vec3(0.012, 0.0018, 0.012);
      s.contact.normal_stiffness = 1e5;
      s.contact.normal_damping = 0.026;
      s.contact.allow_unstable_step = true;
      s.time.dem_step = 1e-7;
      skin = 1.5e-4;
      if (csv.empty()) csv = std::string(FDEM_ANCHORS_DIR) + "/B_settled.csv";
    } else {
      if (csv.empty()) throw InputError("dem_steps", "--csv", "", "scene cloud needs the CSV of plume_dem_profile");
      s.domain.upper = Vec3(0.1, 0.1, 0.25);  // verification/plume/plume.yaml
      s.contact.normal_stiffness = 100.0;
      s.contact.normal_damping = 8.5e-4;
      s.time.dem_step = 1e-5;
    }
    const Particles initial = read_csv(csv);
    DemEngine dem(initial, s);
    if (skin > 0.0) dem.set_skin(skin);
    DemEngine::GrainSortPolicy policy;
    policy.interval = sort_interval;
    dem.set_grain_sort_policy(policy);
    if (sort_first) dem.sort_in_cell_order();
    dem.step();  // the list build at this skin
    std::vector<double> step_s;
    const auto t0 = std::chrono::steady_clock::now();
    if (step_quantiles) {
      step_s.reserve(static_cast<std::size_t>(steps));
      for (long k = 0; k < steps; ++k) {
        const auto s0 = std::chrono::steady_clock::now();
        dem.run_sorting(1);
        step_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count());
      }
    } else {
      dem.run_sorting(static_cast<std::size_t>(steps));
    }
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::string quantiles;
    if (!step_s.empty()) {
      std::sort(step_s.begin(), step_s.end());
      const auto at = [&](double q) { return step_s[static_cast<std::size_t>(q * static_cast<double>(step_s.size() - 1))]; };
      quantiles = fmt::format("\"step_us_q05\": {:.4g}, \"step_us_q10\": {:.4g}, \"step_us_q25\": {:.4g}, "
                              "\"step_us_q50\": {:.4g}, ",
                              1e6 * at(0.05), 1e6 * at(0.10), 1e6 * at(0.25), 1e6 * at(0.50));
    }
    const DemDiagnostics d = dem.diagnostics();
    const DemPhaseSeconds& ph = d.phases;
    const auto per_evaluation = [&](std::size_t count) {
      return ph.force_evaluations > 0 ? static_cast<double>(count) / static_cast<double>(ph.force_evaluations) : 0.0;
    };
    fmt::print(
        "{{\"scene\": \"{}\", \"threads\": {}, \"particles\": {}, \"steps\": {}, \"contacts\": {}, "
        "\"wall_contacts\": {}, \"neighbour_entries\": {}, \"rebuilds\": {}, \"wall_s\": {:.6g}, "
        "\"particle_steps_per_s\": {:.6g}, \"integration_s\": {:.6g}, \"neighbour_build_s\": {:.6g}, "
        "\"pairs_s\": {:.6g}, \"walls_s\": {:.6g}, \"sorting_s\": {:.6g}, \"grain_sorts\": {}, \"pairs_tested_per_evaluation\": {:.6g}, \"touching_pairs_per_evaluation\": {:.6g}, \"contact_cost_in_pair_tests\": {:.6g}, \"near_pair_filters\": {}, {}\"kinetic_energy_j\": {:.17g}, \"hash\": \"{:016x}\"}}\n",
        scene_name, threads, d.particles, steps, d.contacts, d.wall_contacts, d.neighbour_entries,
        d.neighbour_rebuilds, wall_s, static_cast<double>(d.particles) * static_cast<double>(steps) / wall_s,
        ph.integration, ph.neighbour_build, ph.pairs, ph.walls, ph.sorting, d.grain_sorts,
        per_evaluation(ph.pairs_tested), per_evaluation(ph.pairs_touching), fdem::contact_cost_in_pair_tests,
        ph.near_pair_filters, quantiles, d.kinetic_energy_j, state_hash(dem.particles()));
    return 0;
  });
}

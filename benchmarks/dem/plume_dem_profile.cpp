// plume_dem_profile: the DEM phase of the coupled salt plume, measured where
// the study really spends it. Loads a checkpoint of the full plume
// (verification/plume/plume.yaml, written by `fdem run`; plume_workload.py
// makes them at 0.2, 0.5 and 0.9 s), takes warm-up fluid steps (the first
// after a load rebuilds the neighbour list and refactors the fluid's
// preconditioner), then times `--steps` coupled steps through
// Simulation::step() and prints one JSON object: particle-steps per second
// of the DEM subcycles with and without the drag, and where the DEM's time
// went (DemPhaseSeconds: integration, list rebuilds and their count, pairs,
// walls, drag), next to the fluid and coupling time of the same steps, and
// the two largest phases over their streaming floors (streaming_floor.hpp,
// measured after the steps on as many grains and threads): the integration
// against a pass loading and storing the fused kick-drift's arrays, the drag
// against one with the drag kernel's.
// --write-dem-csv PATH writes the loaded grains first (anchor CSV layout,
// id,d,rho,x,y,z,vx,vy,vz, 17 digits), so dem_steps can run the same cloud
// dry, without the fluid (under valgrind, or against scene P in one run).
// The grains are sorted in memory order as in any run (DemEngine::
// GrainSortPolicy); --sort-interval 0 switches it off (the unsorted engine,
// for a before/after in one binary), and --warmup-until-sorted takes warm-up
// steps until the first sort after the load, so the timed steps see the
// order a run that sorted all along has (a checkpoint of an older build
// holds the grains unsorted).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "core/types.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include "streaming_floor.hpp"
#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "coupling/simulation.hpp"
#include "scene/scene_loader.hpp"

namespace {

struct Window {
  double fluid_s = 0.0, dem_s = 0.0, drag_s = 0.0, coupling_s = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DEM phase of the coupled plume from a checkpoint: particle-steps/s and where the time goes"};
  std::string scene_path, checkpoint_path, csv_path;
  int steps = 10, warmup = 1, threads = 1;
  std::size_t sort_interval = fdem::DemEngine::GrainSortPolicy{}.interval;
  bool warmup_until_sorted = false;
  app.add_option("--scene", scene_path, "the scene the checkpoint was written with")->required();
  app.add_option("--checkpoint", checkpoint_path, "checkpoint.bin of that scene")->required();
  app.add_option("--steps", steps, "timed fluid steps")->check(CLI::PositiveNumber);
  app.add_option("--warmup", warmup, "untimed fluid steps first")->check(CLI::NonNegativeNumber);
  app.add_option("--threads", threads, "OpenMP threads")->check(CLI::PositiveNumber);
  app.add_option("--sort-interval", sort_interval, "DEM steps between grain sorts (0: never)");
  app.add_flag("--warmup-until-sorted", warmup_until_sorted, "after --warmup, more warm-up steps until the grains were sorted");
  app.add_option("--write-dem-csv", csv_path, "write the loaded grains (id,d,rho,x,y,z,vx,vy,vz) here first");
  CLI11_PARSE(app, argc, argv);
  return fdem::run_with_exit_codes("plume_dem_profile", [&] {
    omp_set_num_threads(threads);
    const fdem::Scene scene = fdem::load_scene(scene_path);
    fdem::Simulation sim(scene);
    fdem::DemEngine::GrainSortPolicy policy;
    policy.interval = sort_interval;
    sim.set_grain_sort_policy(policy);
    {
      std::ifstream in(checkpoint_path, std::ios::binary);
      if (!in) throw fdem::InputError(checkpoint_path, "--checkpoint", checkpoint_path, "cannot open the checkpoint");
      sim.load_checkpoint(in);
    }
    if (!csv_path.empty()) {
      std::ofstream csv(csv_path);
      if (!csv) throw fdem::InputError(csv_path, "--write-dem-csv", csv_path, "cannot write the CSV");
      const fdem::Particles& p = sim.particles();
      csv << "id,d,rho,x,y,z,vx,vy,vz\n";
      for (std::size_t i = 0; i < p.size(); ++i)
        csv << fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", p.id[i],
                           p.diameter[i], p.mass[i] / fdem::sphere_volume(p.diameter[i]), p.x[i], p.y[i], p.z[i],
                           p.vx[i], p.vy[i], p.vz[i]);
    }
    const double t_start = sim.time();
    for (int s = 0; s < warmup; ++s) sim.step();
    if (warmup_until_sorted && sort_interval > 0) {
      const std::size_t sorts = sim.diagnostics().dem.grain_sorts;
      for (std::size_t s = 0; s * static_cast<std::size_t>(sim.subcycles()) <= sort_interval + 1; ++s) {
        if (sim.diagnostics().dem.grain_sorts > sorts) break;
        sim.step();
      }
    }
    const fdem::DemDiagnostics before = sim.diagnostics().dem;
    Window w;
    const auto wall0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) {
      sim.step();
      const fdem::CouplingDiagnostics d = sim.diagnostics();
      w.fluid_s += d.fluid_seconds;
      w.dem_s += d.dem_seconds;
      w.drag_s += d.drag_seconds;
      w.coupling_s += d.coupling_seconds;
    }
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const fdem::DemDiagnostics after = sim.diagnostics().dem;
    const fdem::DemPhaseSeconds& a = after.phases;
    const fdem::DemPhaseSeconds& b = before.phases;
    const double dem_steps = static_cast<double>(after.steps - before.steps);
    const double particle_steps = static_cast<double>(after.particles) * dem_steps;
    const double pairs_s = a.pairs - b.pairs, walls_s = a.walls - b.walls;
    const double integration_s = a.integration - b.integration, build_s = a.neighbour_build - b.neighbour_build;
    const double body_s = a.body_force - b.body_force, external_s = a.external - b.external;
    const double sorting_s = a.sorting - b.sorting;
    const double engine_s = a.total() - b.total();
    const double engine_dry_s = engine_s - external_s;
    const double evaluations = static_cast<double>(a.force_evaluations - b.force_evaluations);
    const auto per_evaluation = [&](std::size_t count) {
      return evaluations > 0 ? static_cast<double>(count) / evaluations : 0.0;
    };
    // Per DEM step: one fused pass and one drag subcycle each.
    const double integration_floor_s =
        fdem::bench::streaming_floor_seconds<fdem::bench::kKickDriftStreams>(after.particles) * dem_steps;
    const double drag_floor_s =
        fdem::bench::streaming_floor_seconds<fdem::bench::kDragStreams>(after.particles) * dem_steps;
    fmt::print(
        "{{\"t_start_s\": {:.6g}, \"t_end_s\": {:.6g}, \"threads\": {}, "
        "\"fluid_steps\": {}, \"dem_steps\": {:.0f}, \"particles\": {}, \"contacts\": {}, \"wall_contacts\": {}, "
        "\"neighbour_entries\": {}, \"mean_entries_tested_per_step\": {:.6g}, \"pairs_tested_per_step\": {:.6g}, "
        "\"touching_pairs_per_step\": {:.6g}, \"contact_cost_in_pair_tests\": {:.6g}, \"near_pair_filters\": {}, \"rebuilds\": {}, "
        "\"wall_s\": {:.6g}, \"fluid_s\": {:.6g}, \"coupling_s\": {:.6g}, \"dem_s\": {:.6g}, \"drag_s\": {:.6g}, "
        "\"engine_s\": {:.6g}, \"integration_s\": {:.6g}, \"neighbour_build_s\": {:.6g}, \"body_force_s\": {:.6g}, "
        "\"pairs_s\": {:.6g}, \"walls_s\": {:.6g}, \"external_s\": {:.6g}, \"sorting_s\": {:.6g}, \"grain_sorts\": {}, "
        "\"dem_particle_steps_per_s\": {:.6g}, \"dem_dry_particle_steps_per_s\": {:.6g}, "
        "\"coupled_particle_steps_per_s\": {:.6g}, \"integration_floor_s\": {:.6g}, \"integration_over_floor\": {:.4g}, "
        "\"drag_floor_s\": {:.6g}, \"drag_over_floor\": {:.4g}}}\n",
        t_start, sim.time(), threads, steps, dem_steps, after.particles, after.contacts, after.wall_contacts,
        after.neighbour_entries,
        per_evaluation(a.pair_entries_tested - b.pair_entries_tested), per_evaluation(a.pairs_tested - b.pairs_tested),
        per_evaluation(a.pairs_touching - b.pairs_touching), fdem::contact_cost_in_pair_tests,
        a.near_pair_filters - b.near_pair_filters,
        after.neighbour_rebuilds - before.neighbour_rebuilds, wall_s, w.fluid_s, w.coupling_s, w.dem_s, w.drag_s,
        engine_s, integration_s, build_s, body_s, pairs_s, walls_s, external_s, sorting_s, after.grain_sorts, particle_steps / engine_s,
        particle_steps / engine_dry_s, particle_steps / wall_s, integration_floor_s, integration_s / integration_floor_s,
        drag_floor_s, w.drag_s / drag_floor_s);
    return 0;
  });
}

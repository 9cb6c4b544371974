// fdem_plume: runs the salt plume study's scene in one coupling mode from the
// command line, prints the metrics and the per-phase wall time (fluid / DEM /
// coupling). For profiling (`valgrind --tool=callgrind fdem_plume --end 0.005`)
// and for exploring DEM steps and size truncations; the gates are the ctest
// tests beside it.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "plume_study.hpp"
#include "scene/scene_loader.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fdem salt plume study, one coupling mode"};
  std::string scene_path = std::string(FDEM_SOURCE_DIR) + "/verification/plume/plume.yaml";
  std::string mode = "twoway", out_dir;
  double end_s = -1.0, dem_step_s = -1.0, d_min = -1.0, sample_s = 0.01;
  bool allow_unstable = false, unstable_flag_given = false;
  app.add_option("--scene", scene_path, "scene file");
  app.add_option("--mode", mode, "twoway | oneway_f2p | oneway_p2f");
  app.add_option("--end", end_s, "end time [s] (default: the scene's)");
  app.add_option("--dem-step", dem_step_s, "DEM step [s] (default: the scene's)");
  app.add_option("--d-min", d_min, "lower truncation of the size distribution [m] (default: the scene's)");
  app.add_option("--sample", sample_s, "metrics interval [s]");
  app.add_option("--out", out_dir, "write the report's files here");
  std::vector<double> snapshots;
  app.add_option("--snapshots", snapshots, "times [s] of the particle and mid-plane fluid speed files");
  auto* flag = app.add_option("--allow-unstable", allow_unstable, "contact.allow_unstable_step (true/false)");
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress lines appear as they come, also in a log file
  unstable_flag_given = flag->count() > 0;
  return fdem::run_with_exit_codes("fdem_plume", [&] {
    fdem::Scene scene = fdem::load_scene(scene_path);
    if (end_s > 0.0) scene.time.end_time = end_s;
    if (dem_step_s > 0.0) {
      scene.time.dem_step = dem_step_s;
      scene.time.subcycles = 0;
    }
    if (d_min > 0.0)
      for (auto& set : scene.particles) set.size.minimum = d_min;
    if (unstable_flag_given) scene.contact.allow_unstable_step = allow_unstable;
    fdem::plume::PlumeRunOptions opt;
    opt.mode = mode == "twoway"       ? fdem::CouplingMode::two_way
               : mode == "oneway_f2p" ? fdem::CouplingMode::fluid_to_particle
               : mode == "oneway_p2f" ? fdem::CouplingMode::particle_to_fluid
                                      : throw fdem::InputError("--mode", "mode", mode, "twoway | oneway_f2p | oneway_p2f");
    opt.sample_interval_s = sample_s;
    opt.output_dir = out_dir;
    opt.snapshot_times_s = snapshots;
    opt.verbose = true;
    const auto run = fdem::plume::run_plume(scene, opt);
    fmt::print("{}: {} steps x {} subcycles (DEM step {:g} s); wall {:.1f} s = setup {:.1f} + fluid {:.1f} + DEM {:.1f} "
               "(of which drag {:.1f}) + coupling {:.1f} (+ {:.1f} study); {:.1f} ms per fluid step; {} OpenMP threads\n",
               run.mode, run.steps, run.subcycles, run.dem_step_s, run.wall_s, run.setup_s, run.fluid_s, run.dem_s,
               run.drag_s, run.coupling_s, run.wall_s - run.setup_s - run.fluid_s - run.dem_s - run.coupling_s,
               1e3 * run.wall_s_per_fluid_step(), omp_get_max_threads());
    fmt::print("max contacts {:g}, max overlap/d {:.3g}, max grain speed {:.3f} m/s, grains lost {}, floor reached at "
               "{:g} s, min porosity {:.3f}, max momentum imbalance {:.3g}\n",
               run.max_contacts, run.max_overlap_over_diameter, run.max_grain_speed_mps, run.grains_lost,
               run.floor_contact_time_s, run.min_porosity, run.max_momentum_imbalance);
    return 0;
  });
}

// Plume metrics against grain count and mesh size (the report's
// accuracy-cost section, reports/FORMATS.md "benchmarks").
//
// Scene family: the reduced salt plume (verification/plume/plume_fast.yaml:
// water, two-way Ergun / Wen & Yu drag, Kn 100 N/m, Cn 8.5e-4 N s/m, no
// tangential force, no-slip walls, 60 x 60 x 120 mm column, the paper's
// 20 x 20 x 40 mm block 20 mm below the lid, fluid step 2 ms). Two settings
// change, each run of the cross product of
//   grains   N grains of one diameter on a lattice filling the block, the
//            block's solid fraction held at the reduced scene's
//            (4704 grains of 0.6 mm: 3.33 %), so d = (6 phi V_block / (pi N))^(1/3).
//            Counts are given as fractions of the paper's 28224 grains
//            (1/8 = 3528 ... 1 = 28224, d 0.66 ... 0.33 mm); the lattice
//            rounds them (nx = ny, nz ~ 2 nx as the block is 1:1:2).
//   cells    nominal cell size 20, 10, 7 mm -> round(L / h) cells per axis.
// The DEM step follows the grain size: subcycles = max(60 (the reduced
// scene's), ceil(fluid step / (0.9 x the solver's stable step for the pair
// and the wall))), so every run passes DemEngine's stability check unforced.
// The plume metrics (verification/plume/plume_metrics.hpp: front depth,
// centroid depth, radial spread, dome shape, peak fluid speed) are taken at
// the end time by the study's own run_plume (plume_study.hpp).
//
// Modes:
//   --quick  grains 1/8, 1/4, 1/2 of 28224 x cells 20, 10, 7 mm, 0.2 s:
//            9 runs (17 s CPU; 34 s wall at load 6.6)
//   --full   grains 1/8, 1/4, 1/2, 1 x cells 20, 10, 7, 5 mm, 0.4 s (the
//            reduced scene's end): 16 runs, nightly (2.5 min CPU)
//   --tiny   grains 1/64, 1/32 x cells 20, 10 mm, 0.02 s: 4 runs in seconds
//            (the fast-tier test of the driver and its CSV)
// --grains-fraction, --cells-mm, --end override the mode's lists.
//
// Output (--out, default $FDEM_RESULTS_DIR/benchmarks):
//   plume_sweep.csv   one row per run: settings, metrics at the end time and
//                     wall times (reports/FORMATS.md, "benchmarks").
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "io/atomic_file.hpp"
#include "plume_study.hpp"
#include "scene/scene_loader.hpp"
#include "scene/stability.hpp"

namespace {

using namespace fdem;

constexpr double kPaperGrains = 28224.0;  // the paper's plume (Table 4)

struct Setting {
  double grains_fraction = 0.0;  // of kPaperGrains (requested)
  double cell_mm = 0.0;          // nominal cell size (requested)
};

struct Outcome {
  Setting setting;
  std::array<int, 3> lattice{};
  std::array<int, 3> cells{};
  long grains = 0;
  double diameter_m = 0.0;
  double cell_m = 0.0;        // (cell volume)^(1/3) of the mesh actually run
  double solid_fraction = 0.0;
  int subcycles = 0;
  double dem_step_s = 0.0;
  plume::PlumeRun run;
};

double block_volume(const ParticleSet& set) {
  const Vec3 e = set.region.upper - set.region.lower;
  return e.x() * e.y() * e.z();
}

// The scene of one setting, from the reduced plume.
Outcome prepare(const Scene& base, const Setting& s, double end_s, Scene& scene) {
  Outcome o;
  o.setting = s;
  scene = base;
  scene.time.end_time = end_s;
  if (scene.particles.size() != 1 || scene.particles.front().placement != PlacementKind::lattice ||
      scene.particles.front().size.kind != SizeKind::fixed)
    throw std::invalid_argument("plume_sweep: expects the reduced plume's one lattice set of one size");
  ParticleSet& set = scene.particles.front();
  const double v_block = block_volume(set);
  const double base_count = static_cast<double>(set.lattice[0]) * set.lattice[1] * set.lattice[2];
  o.solid_fraction = base_count * sphere_volume(set.size.diameter) / v_block;

  const Vec3 e = set.region.upper - set.region.lower;
  const double target = s.grains_fraction * kPaperGrains;
  // nx = ny, nz / nx = block aspect (2 for 20 x 20 x 40 mm).
  const double aspect = e.z() / e.x();
  const int nx = std::max(1, static_cast<int>(std::lround(std::cbrt(target / aspect))));
  const int nz = std::max(1, static_cast<int>(std::lround(target / (static_cast<double>(nx) * nx))));
  o.lattice = {nx, nx, nz};
  set.lattice = o.lattice;
  o.grains = static_cast<long>(nx) * nx * nz;
  o.diameter_m = std::cbrt(6.0 * o.solid_fraction * v_block / (std::numbers::pi * static_cast<double>(o.grains)));
  set.size.diameter = o.diameter_m;

  const Vec3 l = scene.domain.upper - scene.domain.lower;
  for (int a = 0; a < 3; ++a) o.cells[a] = std::max(1, static_cast<int>(std::lround(l[a] / (1e-3 * s.cell_mm))));
  scene.cells = o.cells;
  o.cell_m = std::cbrt(l.x() * l.y() * l.z() / (static_cast<double>(o.cells[0]) * o.cells[1] * o.cells[2]));

  // Smallest stable DEM step for this size (pair and wall), 10 % margin.
  const MassRange range = mass_range(o.diameter_m, o.diameter_m, set.density);
  const double bound =
      analyse_stability(scene.contact, scene.effects, range, scene.time.dem_step, scene.effects.walls).stable_step_s();
  const int base_subcycles = static_cast<int>(std::lround(base.time.fluid_step / base.time.dem_step));
  o.subcycles = std::max(base_subcycles, static_cast<int>(std::ceil(scene.time.fluid_step / (0.9 * bound))));
  o.dem_step_s = scene.time.fluid_step / o.subcycles;
  scene.time.dem_step = o.dem_step_s;
  scene.time.subcycles = o.subcycles;
  return o;
}

std::string csv_row(const std::string& mode, const Outcome& o, int threads) {
  const plume::PlumeMetrics& m = o.run.metrics.back();
  const plume::PlumeMetrics& m0 = o.run.metrics.front();
  return fmt::format(
      "{},{:.6g},{},{:.6e},{:.6g},{:.6e},{}x{}x{},{},{:.6g},{},{:.6e},{:.6g},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},"
      "{},{},{:.4g},{:.4g},{:.4g},{:.4g},{:.4g},{}\n",
      mode, o.setting.grains_fraction, o.grains, o.diameter_m, o.setting.cell_mm, o.cell_m, o.cells[0], o.cells[1],
      o.cells[2], 5L * o.cells[0] * o.cells[1] * o.cells[2], o.solid_fraction, o.subcycles, o.dem_step_s, m.t_s,
      m.front_depth_m, m.centroid_depth_m, m.radial_spread_m, m.radial_spread_m - m0.radial_spread_m, m.dome_shape,
      m.peak_fluid_speed_mps, o.run.steps, o.run.grains_lost, o.run.wall_s, o.run.setup_s, o.run.fluid_s, o.run.dem_s,
      o.run.coupling_s, threads);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fdem plume sweep: plume metrics and wall time against grain count and mesh size"};
  bool quick = false, full = false, tiny = false;
  std::string out_dir = std::string(FDEM_RESULTS_DIR) + "/benchmarks";
  std::string scene_path = std::string(FDEM_SOURCE_DIR) + "/verification/plume/plume_fast.yaml";
  std::vector<double> fractions, cells_mm;
  double end_s = -1.0;
  int threads = 1;
  auto* g = app.add_option_group("mode");
  g->add_flag("--quick", quick, "grains 1/8, 1/4, 1/2 x cells 20, 10, 7 mm, 0.2 s (default)");
  g->add_flag("--full", full, "grains 1/8, 1/4, 1/2, 1 x cells 20, 10, 7, 5 mm, 0.4 s (nightly)");
  g->add_flag("--tiny", tiny, "grains 1/64, 1/32 x cells 20, 10 mm, 0.02 s (smoke test)");
  g->require_option(0, 1);
  app.add_option("--grains-fraction", fractions, "grain counts as fractions of the paper's 28224");
  app.add_option("--cells-mm", cells_mm, "nominal cell sizes [mm]");
  app.add_option("--end", end_s, "simulated time [s]");
  app.add_option("--scene", scene_path, "the reduced plume scene");
  app.add_option("--out", out_dir, "output folder (plume_sweep.csv)");
  app.add_option("--threads", threads,
                 "OpenMP threads (default 1: runs are compared with each other, and one thread measures their work "
                 "steadily on a shared machine)");
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const std::string mode = full ? "full" : tiny ? "tiny" : "quick";
  if (fractions.empty())
    fractions = full ? std::vector<double>{0.125, 0.25, 0.5, 1.0}
                : tiny ? std::vector<double>{1.0 / 64, 1.0 / 32}
                       : std::vector<double>{0.125, 0.25, 0.5};
  if (cells_mm.empty())
    cells_mm = tiny ? std::vector<double>{20, 10} : full ? std::vector<double>{20, 10, 7, 5} : std::vector<double>{20, 10, 7};
  if (end_s <= 0.0) end_s = full ? 0.4 : tiny ? 0.02 : 0.2;
  omp_set_num_threads(std::max(1, threads));

  return fdem::run_with_exit_codes("fdem_plume_sweep", [&] {
    const Scene base = load_scene(scene_path);
    std::string csv =
        "# fdem_plume_sweep: reduced plume (" + scene_path + "), mode " + mode +
        ", metrics at the end time (verification/plume/plume_metrics.hpp), wall times in s\n"
        "mode,grains_fraction,grains,d_m,cell_nominal_mm,cell_m,cells,tets,solid_fraction,subcycles,dem_step_s,t_s,"
        "front_depth_m,centroid_depth_m,radial_spread_m,spread_growth_m,dome_shape,peak_fluid_speed_mps,steps,"
        "grains_lost,wall_time_s,setup_s,fluid_s,dem_s,coupling_s,threads\n";
    std::filesystem::create_directories(out_dir);
    const std::string path = out_dir + "/plume_sweep.csv";
    for (double f : fractions)
      for (double h : cells_mm) {
        Scene scene;
        Outcome o = prepare(base, Setting{f, h}, end_s, scene);
        plume::PlumeRunOptions opt;
        opt.mode = CouplingMode::two_way;
        opt.sample_interval_s = end_s;  // samples at 0 and at the end
        o.run = plume::run_plume(scene, opt);
        const plume::PlumeMetrics& m = o.run.metrics.back();
        fmt::print("grains {:6d} (d {:.3f} mm)  cells {:2d}x{:2d}x{:2d} ({:.1f} mm)  subcycles {:3d}  t {:.3f} s: "
                   "front {:6.2f} mm  centroid {:6.2f} mm  spread {:.3f} mm  dome {:+.4f}  |u|max {:.4f} m/s  "
                   "wall {:6.1f} s (fluid {:.1f}, DEM {:.1f})\n",
                   o.grains, 1e3 * o.diameter_m, o.cells[0], o.cells[1], o.cells[2], 1e3 * o.cell_m, o.subcycles,
                   m.t_s, 1e3 * m.front_depth_m, 1e3 * m.centroid_depth_m, 1e3 * m.radial_spread_m, m.dome_shape,
                   m.peak_fluid_speed_mps, o.run.wall_s, o.run.fluid_s, o.run.dem_s);
        csv += csv_row(mode, o, threads);
        write_file_atomically(path, csv);  // complete up to now, also when a long sweep is stopped
      }
    fmt::print("wrote {}\n", path);
    return 0;
  });
}

// Accuracy-cost sweeps: what each numerical choice of a coupled run
// buys in accuracy and costs in wall time, for the report's Pareto plots.
//
// Case: one grain settling from rest in water (paper Sect. 4.1: the verified
// scene verification/settling/settling.yaml, the sweep's settings written as
// named overrides), d = 0.76 mm (the mesh-sensitivity
// grain, paper Sect. 4.2), two-way coupling. Accuracy: the grain's terminal
// velocity (mean over the last 20 % of the run) against the GSL terminal
// velocity of the same drag law for an isolated sphere (eps = 1,
// reference/settling_reference: Brent root of weight - buoyancy = drag). This
// error gathers everything the coupled model adds to the single-sphere ODE:
// porosity below 1 in the grain's element, the fluid the grain drags along
// (two-way), time discretisation. A second measure, the largest deviation of
// v(t) from the GSL trajectory (rk8pd, same ODE) over the run, over v_t, also
// sees the transient, where the DEM step matters.
//
// Sweeps, each varying one setting from the base (fluid step 0.01 s, 1000
// subcycles, cell / d = 5.26 (4 mm cells), centre porosity):
// (sweep names as reports/FORMATS.md suggests)
//   subcycles        DEM steps per fluid step: 10, 30, 100, 300, 1000
//   dt_fluid         0.04, 0.02, 0.01, 0.005, 0.0025 s at a DEM step of 1e-5 s
//   ratio            cell size / d: 3, 4, 5, 7, 10
//   porosity_scheme  centre and shape_function at cell / d 3 and 5; --full
//                    also diffused (L = one cell) at 3 and 5 (not in --quick:
//                    check_sweep.py fixes the quick settings)
// DEM steps coarser than the wall-contact bound are allowed
// (allow_unstable_step): the grain touches no wall in the run (checked: the
// run is refused if it gets within one diameter of a wall).
//
// Modes: --quick (a 12 x 12 x 24 mm box, 0.15 s, fluid step 0.02 s, two
// settings per sweep: ~2 s on one core; for the smoke test) and --full
// (44 x 44 x 80 mm box, 0.5 s, every setting; tens of minutes: nightly).
//
// The error of a row: the terminal-velocity error above for ratio and
// porosity_scheme; for the time-step sweeps (subcycles, dt_fluid), whose
// terminal velocity moves by < 2e-4, the time-discretisation error against a
// run one step finer than the sweep (time_reference below); error_kind says which.
//
// Output (--out, default $FDEM_RESULTS_DIR/benchmarks):
//   accuracy_cost.csv          sweep,setting,error,wall_time_s,error_kind
//                              (reports/FORMATS.md, read by the report)
//   sweeps/accuracy_cost_detail.csv   every setting of every run and both errors
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "coupling/simulation.hpp"
#include "reference/settling_reference.hpp"
#include "scene/scene_overrides.hpp"

namespace {

struct Setting {
  std::string sweep;         // which sweep this run belongs to
  std::string label;         // the value swept, as the report prints it
  int subcycles = 1000;
  double fluid_step_s = 0.01;
  double cell_ratio = 0.0;   // 0 = the box's base mesh (4 mm cells)
  fdem::PorosityScheme scheme = fdem::PorosityScheme::centre;
};

struct Case {
  double diameter_m = 0.76e-3;
  fdem::Vec3 box = fdem::Vec3(0.044, 0.044, 0.080);
  double start_height_m = 0.070;
  double end_time_s = 0.5;
};

struct Outcome {
  double terminal_mps = 0.0;         // simulated, mean over the last 20 % of the run
  double terminal_gsl_mps = 0.0;
  double terminal_error = 0.0;       // relative
  double trajectory_error = 0.0;     // max_t |v - v_gsl(t)| / v_t,gsl
  std::vector<double> times, velocity;  // v_z after every fluid step
  double wall_time_s = 0.0;          // set-up and all steps
  long steps = 0;
  double cell_m = 0.0, ratio = 0.0, dem_step_s = 0.0;
};

std::string scheme_name(fdem::PorosityScheme s) {
  return std::string(fdem::porosity_scheme_entry(s).name);
}

// The shortest text that reads back as v, bit for bit.
std::string exact(double v) { return fmt::format("{}", v); }

Outcome run(const Case& c, const Setting& s) {
  const double target_cell = s.cell_ratio > 0.0 ? s.cell_ratio * c.diameter_m : 0.004;
  std::array<int, 3> cells{};
  for (int a = 0; a < 3; ++a) cells[static_cast<std::size_t>(a)] = std::max(1, static_cast<int>(std::lround(c.box[a] / target_cell)));
  fdem::Scene scene = fdem::load_scene_with_overrides(
      std::string(FDEM_SOURCE_DIR) + "/verification/settling/settling.yaml",
      {{"domain.upper", fmt::format("[{}, {}, {}]", exact(c.box.x()), exact(c.box.y()), exact(c.box.z())), "the case's box"},
       {"mesh.cells", fmt::format("[{}, {}, {}]", cells[0], cells[1], cells[2]), "cell size = ratio x d"},
       {"particles[0].position", fmt::format("[{}, {}, {}]", exact(0.5 * c.box.x()), exact(0.5 * c.box.y()), exact(c.start_height_m)), "on the box's axis at the case's start height"},
       {"particles[0].size", exact(c.diameter_m), "the case's grain"},
       {"time.fluid_step", exact(s.fluid_step_s), "swept"},
       {"time.dem_step", exact(s.fluid_step_s / s.subcycles), "swept: fluid step / subcycles"},
       {"time.subcycles", std::to_string(s.subcycles), "swept"},
       {"time.end", exact(c.end_time_s), "the case's run"},
       {"contact.allow_unstable_step", "true", "no contact in the run (checked below)"},
       {"coupling.porosity", scheme_name(s.scheme), "swept"}});
  // diffused smooths over one cell here (the sweep's setting), not the scene default of 2 d.
  if (s.scheme == fdem::PorosityScheme::diffused) scene.coupling.porosity_smoothing_length = c.box.z() / cells[2];

  Outcome o;
  o.cell_m = c.box.z() / scene.cells[2];
  o.ratio = o.cell_m / c.diameter_m;
  o.dem_step_s = s.fluid_step_s / s.subcycles;

  std::vector<double>& times = o.times;
  std::vector<double>& velocity = o.velocity;
  times.push_back(0.0);
  velocity.push_back(0.0);
  const auto t0 = std::chrono::steady_clock::now();
  fdem::Simulation sim(scene);
  while (!sim.finished()) {
    sim.step();
    const fdem::Particles& p = sim.particles();
    if (p.size() != 1) throw fdem::SolverError(fmt::format("sweep {} {}: the grain was lost", s.sweep, s.label));
    const double r = 0.5 * c.diameter_m;
    if (p.z[0] < 2.0 * r || p.x[0] < 2.0 * r || p.x[0] > c.box.x() - 2.0 * r || p.y[0] < 2.0 * r ||
        p.y[0] > c.box.y() - 2.0 * r)
      throw fdem::SolverError(fmt::format("sweep {} {}: the grain came within one diameter of a wall", s.sweep, s.label));
    times.push_back(sim.time());
    velocity.push_back(p.vz[0]);
  }
  o.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.steps = sim.step_index();

  // GSL reference of the same model for an isolated sphere (eps = 1).
  fdem::SettlingModel model;
  model.diameter_m = c.diameter_m;
  model.particle_density = scene.particles[0].density;
  model.fluid = fdem::FluidProperties{scene.fluid.density, scene.fluid.viscosity};
  model.gravity_z = scene.gravity.z();
  model.drag = scene.effects.drag;
  o.terminal_gsl_mps = fdem::terminal_velocity(model, 1.0);
  const std::vector<fdem::SettlingState> ref =
      fdem::integrate_settling(model, scene.particles[0].position, 0.0, times);

  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    o.trajectory_error = std::max(o.trajectory_error, std::abs(velocity[k] - ref[k].w_m_s) / o.terminal_gsl_mps);
    if (times[k] >= 0.8 * c.end_time_s - 1e-12) {
      sum += -velocity[k];
      ++count;
    }
  }
  o.terminal_mps = sum / std::max(count, 1);
  o.terminal_error = std::abs(o.terminal_mps - o.terminal_gsl_mps) / o.terminal_gsl_mps;
  return o;
}

// Quick mode: fluid step 0.02 s (8 steps of the 0.15 s run) and 100
// subcycles as its base; the dt_fluid sweep still shows 0.04 against 0.02 s.
std::vector<Setting> settings(bool quick) {
  std::vector<Setting> out;
  const double base_dt = quick ? 0.02 : 0.01;
  const int base_subcycles = quick ? 100 : 1000;
  const auto centre = fdem::PorosityScheme::centre;
  const std::vector<int> subcycles = quick ? std::vector<int>{10, 100} : std::vector<int>{10, 30, 100, 300, 1000};
  for (int n : subcycles) out.push_back({"subcycles", fmt::format("N={}", n), n, base_dt, 0.0, centre});
  const std::vector<double> fluid_steps =
      quick ? std::vector<double>{0.04, 0.02} : std::vector<double>{0.04, 0.02, 0.01, 0.005, 0.0025};
  for (double dt : fluid_steps)  // DEM step held at 1e-5 s (full) or 2e-4 s (quick)
    out.push_back({"dt_fluid", fmt::format("dt={:g} s", dt),
                   static_cast<int>(std::lround(dt / (base_dt / base_subcycles))), dt, 0.0, centre});
  const std::vector<double> ratios = quick ? std::vector<double>{3, 5} : std::vector<double>{3, 4, 5, 7, 10};
  for (double r : ratios) out.push_back({"ratio", fmt::format("r={:g}", r), base_subcycles, base_dt, r, centre});
  const std::vector<double> scheme_ratios = quick ? std::vector<double>{3} : std::vector<double>{3, 5};
  std::vector<fdem::PorosityScheme> schemes{centre, fdem::PorosityScheme::shape_function};
  if (!quick) schemes.push_back(fdem::PorosityScheme::diffused);
  for (double r : scheme_ratios)
    for (auto sch : schemes)
      out.push_back({"porosity_scheme", fmt::format("{} r={:g}", scheme_name(sch), r), base_subcycles, base_dt, r, sch});
  return out;
}

// The time-step sweeps (subcycles, dt_fluid) change the terminal velocity by
// less than 2e-4 of it (the fluid step only sets how often the grain sees the
// fluid; the porosity of its element dominates the error against the
// isolated-sphere GSL root): their error is the time-discretisation error
// itself, max_t |v(t) - v_ref(t)| / v_t over the fluid steps they share with a
// reference run one step finer than the sweep (subcycles: 3 x the most;
// dt_fluid: half the smallest fluid step at the same DEM step).
Setting time_reference(const std::string& sweep, bool quick) {
  const double base_dt = quick ? 0.02 : 0.01;
  const int base_subcycles = quick ? 100 : 1000;
  const auto centre = fdem::PorosityScheme::centre;
  if (sweep == "subcycles") {
    const int n = quick ? 300 : 3000;
    return {"subcycles", fmt::format("N={}", n), n, base_dt, 0.0, centre};
  }
  const double dt = quick ? 0.01 : 0.00125;
  return {"dt_fluid", fmt::format("dt={:g} s", dt), static_cast<int>(std::lround(dt / (base_dt / base_subcycles))), dt,
          0.0, centre};
}

// max over the reference's sample times that o shares (both sample every fluid
// step from t = 0; the sweep's fluid steps are multiples of the reference's).
double time_discretisation_error(const Outcome& o, const Outcome& ref) {
  std::map<long long, double> ref_v;
  for (std::size_t k = 0; k < ref.times.size(); ++k) ref_v[std::llround(ref.times[k] * 1e7)] = ref.velocity[k];
  double err = 0.0;
  for (std::size_t k = 0; k < o.times.size(); ++k) {
    const auto it = ref_v.find(std::llround(o.times[k] * 1e7));
    if (it != ref_v.end()) err = std::max(err, std::abs(o.velocity[k] - it->second) / o.terminal_gsl_mps);
  }
  return err;
}

// Settings that appear in two sweeps (e.g. the base run, or centre r=3 in the
// ratio and the porosity sweeps) run once.
using RunKey = std::tuple<int, double, double, int>;
RunKey key_of(const Setting& s) { return {s.subcycles, s.fluid_step_s, s.cell_ratio, static_cast<int>(s.scheme)}; }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fdem accuracy-cost sweeps: terminal settling velocity error and wall time"};
  bool quick = false, full = false;
  std::string out_dir = std::string(FDEM_RESULTS_DIR) + "/benchmarks";
  std::string only;
  int threads = 1;
  app.add_option("--threads", threads,
                 "OpenMP threads (default 1: the sweep compares settings, and one thread measures their work "
                 "steadily on a shared machine, where two threads ran the quick mode 10x slower)");
  app.add_flag("--quick", quick, "small box, short run, two settings per sweep (< 1 min)");
  app.add_flag("--full", full, "paper box, every setting (nightly)");
  app.add_option("--out", out_dir, "output folder (accuracy_cost.csv, sweeps/)");
  app.add_option("--sweep", only, "run only this sweep (subcycles, dt_fluid, ratio, porosity_scheme)");
  CLI11_PARSE(app, argc, argv);
  if (quick == full) {
    std::fprintf(stderr, "fdem_sweep: give exactly one of --quick or --full\n");
    return 2;
  }
  omp_set_num_threads(std::max(1, threads));
  Case c;
  if (quick) {
    c.box = fdem::Vec3(0.012, 0.012, 0.024);
    c.start_height_m = 0.020;
    c.end_time_s = 0.15;
  }
  return fdem::run_with_exit_codes("fdem_sweep", [&] {
    namespace fs = std::filesystem;
    fs::create_directories(fs::path(out_dir) / "sweeps");
    std::ofstream summary(fs::path(out_dir) / "accuracy_cost.csv");
    std::ofstream detail(fs::path(out_dir) / "sweeps" / "accuracy_cost_detail.csv");
    const std::string mode_text = quick ? ", quick mode" : "";
    const std::string kind = "rel. error of v_t vs GSL" + mode_text;
    summary << "sweep,setting,error,wall_time_s,error_kind\n";
    detail << "sweep,setting,mode,diameter_m,subcycles,fluid_step_s,dem_step_s,cell_m,cell_ratio,porosity_scheme,"
              "v_terminal_mps,v_terminal_gsl_mps,terminal_error_rel,trajectory_error_rel,steps,wall_time_s,threads,"
              "time_discretisation_error_rel\n";
    std::printf("%-15s %-22s %10s %10s %10s %10s %9s\n", "sweep", "setting", "v_t m/s", "GSL m/s", "err_vt", "err_traj",
                "wall s");
    std::map<RunKey, Outcome> done;
    auto outcome = [&](const Setting& s) -> const Outcome& {
      auto it = done.find(key_of(s));
      if (it == done.end()) it = done.emplace(key_of(s), run(c, s)).first;
      return it->second;
    };
    for (const Setting& s : settings(quick)) {
      if (!only.empty() && s.sweep != only) continue;
      const Outcome& o = outcome(s);
      const bool time_sweep = s.sweep == "subcycles" || s.sweep == "dt_fluid";
      double time_error = std::nan("");
      std::string row_kind = kind;
      double error = o.terminal_error;
      if (time_sweep) {
        const Setting ref = time_reference(s.sweep, quick);
        time_error = time_discretisation_error(o, outcome(ref));
        error = time_error;
        row_kind = fmt::format("max_t |v - v_ref(t)| / v_t, v_ref: {}{}", ref.label, mode_text);
      }
      summary << fmt::format("{},\"{}\",{:.6e},{:.4f},\"{}\"\n", s.sweep, s.label, error, o.wall_time_s, row_kind);
      detail << fmt::format("{},\"{}\",{},{:g},{},{:g},{:g},{:g},{:.4f},{},{:.6e},{:.6e},{:.6e},{:.6e},{},{:.4f},{},{:.6e}\n", s.sweep,
                            s.label, quick ? "quick" : "full", c.diameter_m, s.subcycles, s.fluid_step_s, o.dem_step_s,
                            o.cell_m, o.ratio, scheme_name(s.scheme), o.terminal_mps, o.terminal_gsl_mps,
                            o.terminal_error, o.trajectory_error, o.steps, o.wall_time_s, threads, time_error);
      summary.flush();
      detail.flush();
      std::printf("%-15s %-22s %10.5f %10.5f %10.3e %10.3e %9.2f\n", s.sweep.c_str(), s.label.c_str(), o.terminal_mps,
                  o.terminal_gsl_mps, o.terminal_error, o.trajectory_error, o.wall_time_s);
      std::fflush(stdout);
    }
    std::printf("wrote %s/accuracy_cost.csv and sweeps/accuracy_cost_detail.csv\n", out_dir.c_str());
    return 0;
  });
}

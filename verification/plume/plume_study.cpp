#include "plume_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "coupling/simulation.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_series.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem::plume {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

PlumeGeometry geometry_of(const Scene& scene) {
  PlumeGeometry g;
  g.axis_x_m = 0.5 * (scene.domain.lower.x() + scene.domain.upper.x());
  g.axis_y_m = 0.5 * (scene.domain.lower.y() + scene.domain.upper.y());
  if (scene.particles.empty()) throw std::invalid_argument("plume scene without particles");
  g.top_z_m = -1e300;
  for (const ParticleSet& set : scene.particles) g.top_z_m = std::max(g.top_z_m, set.region.upper.z());
  return g;
}

// Grains' particles as the report draws them (x, y, z up, d).
void write_particles(const std::string& path, const Particles& p) {
  std::string out = "x_m,y_m,z_m,d_m\n";
  out.reserve(p.size() * 80);
  for (std::size_t i = 0; i < p.size(); ++i)
    fmt::format_to(std::back_inserter(out), "{:.6e},{:.6e},{:.6e},{:.4e}\n", p.x[i], p.y[i], p.z[i], p.diameter[i]);
  write_file_atomically(path, out);
}

// Fluid speed on the node plane nearest the mid-plane y = W/2 (exactly on it
// for an even number of cells in y): every (x, z) node once, a full grid.
void write_mid_plane_speed(const std::string& path, const BoxMesh& mesh, std::span<const double> u) {
  const auto& c = mesh.cells();
  const int j_mid = c[1] / 2;
  std::string out = "x_m,z_m,speed_mps\n";
  for (int k = 0; k <= c[2]; ++k)
    for (int i = 0; i <= c[0]; ++i) {
      const Index n = mesh.node_index(i, j_mid, k);
      const auto s = static_cast<std::size_t>(3 * n);
      const Vec3 x = mesh.node(n);
      fmt::format_to(std::back_inserter(out), "{:.6e},{:.6e},{:.6e}\n", x.x(), x.z(),
                     std::sqrt(u[s] * u[s] + u[s + 1] * u[s + 1] + u[s + 2] * u[s + 2]));
    }
  write_file_atomically(path, out);
}

double max_grain_speed(const Particles& p) {
  double v2 = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) v2 = std::max(v2, p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  return std::sqrt(v2);
}

double lowest_grain_height(const Particles& p, double floor_z) {
  double h = 1e300;
  for (std::size_t i = 0; i < p.size(); ++i) h = std::min(h, p.z[i] - 0.5 * p.diameter[i] - floor_z);
  return h;
}

}  // namespace

std::string mode_label(CouplingMode mode) {
  switch (mode) {
    case CouplingMode::two_way: return "twoway";
    case CouplingMode::fluid_to_particle: return "oneway_f2p";
    case CouplingMode::particle_to_fluid: return "oneway_p2f";
    case CouplingMode::off: return "off";
  }
  return "unknown";
}

std::string time_label(double t_s) { return fmt::format("{:.2f}", t_s); }

const PlumeMetrics& PlumeRun::at(double t_s) const {
  if (metrics.empty()) throw std::logic_error("plume run without samples");
  const PlumeMetrics* last = &metrics.front();
  for (const PlumeMetrics& m : metrics)
    if (m.t_s <= t_s + 1e-9) last = &m;
  return *last;
}

const PlumeMetrics& PlumeRun::last_suspended() const {
  if (floor_contact_time_s < 0.0) return metrics.back();
  const PlumeMetrics* last = &metrics.front();
  for (const PlumeMetrics& m : metrics)
    if (m.t_s < floor_contact_time_s - 1e-9) last = &m;
  return *last;
}

PlumeRun run_plume(const Scene& base, const PlumeRunOptions& opt) {
  const auto t_start = Clock::now();
  Scene scene = base;
  scene.effects.coupling = opt.mode;
  PlumeRun run;
  run.mode = mode_label(opt.mode);
  run.geometry = geometry_of(scene);

  Simulation sim(scene);
  run.setup_s = seconds_since(t_start);
  run.subcycles = sim.subcycles();
  run.dem_step_s = sim.step_size() / sim.subcycles();
  const BoxMesh* mesh = sim.mesh();
  if (!mesh) throw std::invalid_argument("the plume study needs a fluid");
  const double floor_z = scene.domain.lower.z();
  const double cell_height = (scene.domain.upper.z() - floor_z) / scene.cells[2];
  const auto grains_at_start = static_cast<long>(sim.particles().size());

  std::unique_ptr<CsvSeries> series;
  if (!opt.output_dir.empty()) {
    std::filesystem::create_directories(opt.output_dir);
    series = std::make_unique<CsvSeries>(
        opt.output_dir + "/metrics_" + run.mode + ".csv",
        std::vector<std::string>{"t_s", "front_depth_m", "centroid_depth_m", "radial_spread_m", "dome_shape",
                                 "peak_fluid_speed_mps"});
  }
  std::vector<double> snapshots = opt.snapshot_times_s;
  std::sort(snapshots.begin(), snapshots.end());
  std::size_t next_snapshot = 0;
  const long steps_per_sample = std::max(1L, std::lround(opt.sample_interval_s / sim.step_size()));

  const auto t_stepping = Clock::now();
  auto sample = [&](const CouplingDiagnostics& d) {
    const Particles& p = sim.particles();
    const double t = sim.time();
    const PlumeMetrics m = measure_plume(p, run.geometry, sim.fluid_velocity(), t);
    run.metrics.push_back(m);
    PlumeHealth h;
    h.t_s = t;
    h.contacts = static_cast<double>(d.dem.contacts);
    h.wall_contacts = static_cast<double>(d.dem.wall_contacts);
    h.max_overlap_over_diameter = d.dem.max_overlap_over_diameter;
    h.max_grain_speed_mps = max_grain_speed(p);
    h.lowest_grain_height_m = lowest_grain_height(p, floor_z);
    h.kinetic_energy_j = d.dem.kinetic_energy_j;
    h.grains = static_cast<double>(p.size());
    run.health.push_back(h);
    if (series) {
      const double row[] = {m.t_s, m.front_depth_m, m.centroid_depth_m, m.radial_spread_m, m.dome_shape,
                            m.peak_fluid_speed_mps};
      series->append(row);
    }
    PlumeProgress progress;
    progress.mode = run.mode;
    progress.t_s = t;
    progress.end_s = scene.time.end_time;
    progress.steps_done = sim.step_index();
    progress.steps_total = sim.steps_to_end();
    progress.wall_s = seconds_since(t_start);
    if (progress.steps_done > 0)
      progress.wall_s_per_fluid_step = seconds_since(t_stepping) / static_cast<double>(progress.steps_done);
    progress.time_left_s =
        static_cast<double>(progress.steps_total - progress.steps_done) * progress.wall_s_per_fluid_step;
    if (opt.verbose)
      fmt::print("{} t={:.3f} front={:.2f}mm centroid={:.2f}mm spread={:.3f}mm dome={:+.4f} |u|max={:.4f} "
                 "contacts={} overlap/d={:.3g} vmax={:.3f} lowest={:.1f}mm wall: fluid {:.1f} dem {:.1f} (drag {:.1f}) "
                 "coupling {:.1f}, {:.1f} ms/step, {:.0f} s left\n",
                 run.mode, t, 1e3 * m.front_depth_m, 1e3 * m.centroid_depth_m, 1e3 * m.radial_spread_m, m.dome_shape,
                 m.peak_fluid_speed_mps, d.dem.contacts, d.dem.max_overlap_over_diameter, h.max_grain_speed_mps,
                 1e3 * h.lowest_grain_height_m, run.fluid_s, run.dem_s, run.drag_s, run.coupling_s,
                 1e3 * progress.wall_s_per_fluid_step, progress.time_left_s);
    if (opt.on_progress) opt.on_progress(progress);
    while (next_snapshot < snapshots.size() && snapshots[next_snapshot] <= t + 0.5 * sim.step_size()) {
      if (!opt.output_dir.empty()) {
        const std::string tl = time_label(snapshots[next_snapshot]);
        write_particles(fmt::format("{}/particles_{}_t{}s.csv", opt.output_dir, run.mode, tl), p);
        write_mid_plane_speed(fmt::format("{}/fluid_speed_{}_t{}s.csv", opt.output_dir, run.mode, tl), *mesh,
                              sim.fluid_velocity());
      }
      ++next_snapshot;
    }
  };

  sample(sim.diagnostics());
  while (!sim.finished()) {
    sim.step();
    const CouplingDiagnostics d = sim.diagnostics();
    run.fluid_s += d.fluid_seconds;
    run.dem_s += d.dem_seconds;
    run.drag_s += d.drag_seconds;
    run.coupling_s += d.coupling_seconds;
    run.max_overlap_over_diameter = std::max(run.max_overlap_over_diameter, d.dem.max_overlap_over_diameter);
    run.max_contacts = std::max(run.max_contacts, static_cast<double>(d.dem.contacts));
    run.max_momentum_imbalance = std::max(run.max_momentum_imbalance, d.momentum_imbalance);
    run.max_grain_speed_mps = std::max(run.max_grain_speed_mps, max_grain_speed(sim.particles()));
    if (run.floor_contact_time_s < 0.0) {
      run.min_porosity = std::min(run.min_porosity, d.min_porosity);
      if (lowest_grain_height(sim.particles(), floor_z) < cell_height) run.floor_contact_time_s = sim.time();
    }
    if (sim.step_index() % steps_per_sample == 0 || sim.finished()) sample(d);
  }
  const CouplingDiagnostics d = sim.diagnostics();
  run.floored_element_updates = d.floored_element_updates;
  run.grains_lost = grains_at_start - static_cast<long>(sim.particles().size());
  run.steps = sim.step_index();
  run.wall_s = seconds_since(t_start);
  return run;
}

}  // namespace fdem::plume

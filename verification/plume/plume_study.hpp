#pragma once
// One run of the salt plume study (paper Sect. 4.4) in one coupling mode:
// loads the scene, steps the coupled simulation to its end time, samples the
// cloud metrics (plume_metrics.hpp) and the run's health (contacts, overlap,
// grain speed, lost grains) at a fixed interval, times the phases, and writes
// the report's files (reports/FORMATS.md, "plume"):
//   metrics_<mode>.csv, particles_<mode>_t<T>s.csv, fluid_speed_<mode>_t<T>s.csv.
#include <functional>
#include <string>
#include <vector>

#include "plume_metrics.hpp"
#include "scene/scene.hpp"

namespace fdem::plume {

/// File-name label of a coupling mode: twoway, oneway_f2p, oneway_p2f.
std::string mode_label(CouplingMode mode);

/// Where a run stands, reported after every sample (PlumeRunOptions::on_progress).
struct PlumeProgress {
  std::string mode;
  double t_s = 0.0, end_s = 0.0;       // simulated time now and at the end
  long steps_done = 0, steps_total = 0; // fluid steps
  double wall_s = 0.0;                  // since the run started, set-up included
  double wall_s_per_fluid_step = 0.0;   // mean over the steps done (one fluid step with its DEM subcycles)
  double time_left_s = 0.0;             // steps left x wall_s_per_fluid_step
};

struct PlumeRunOptions {
  CouplingMode mode = CouplingMode::two_way;
  double sample_interval_s = 0.01;        // metrics and health samples
  std::vector<double> snapshot_times_s;   // particles and mid-plane fluid speed files
  std::string output_dir;                 // empty: write nothing
  bool verbose = false;                   // one progress line per sample to stdout
  std::function<void(const PlumeProgress&)> on_progress;  // called after every sample (may be empty)
};

/// The run's health, sampled with the metrics.
struct PlumeHealth {
  double t_s = 0.0;
  double contacts = 0.0;                   // particle pairs in overlap
  double wall_contacts = 0.0;
  double max_overlap_over_diameter = 0.0;  // at the sample
  double max_grain_speed_mps = 0.0;
  double lowest_grain_height_m = 0.0;      // min over grains of z - d/2, above the floor
  double kinetic_energy_j = 0.0;
  double grains = 0.0;                     // still in the domain
};

struct PlumeRun {
  std::string mode;
  PlumeGeometry geometry;
  std::vector<PlumeMetrics> metrics;       // one per sample, first at t = 0
  std::vector<PlumeHealth> health;
  double floor_contact_time_s = -1.0;      // first sample with a grain within one cell of the floor (-1: never)
  double max_overlap_over_diameter = 0.0;  // over all samples
  double max_grain_speed_mps = 0.0;        // over all samples
  double max_contacts = 0.0;
  double min_porosity = 1.0;               // over all fluid steps, before the floor
  long floored_element_updates = 0;
  double max_momentum_imbalance = 0.0;     // over all fluid steps (two-way: |sum drag + force on fluid| / |sum drag|)
  long grains_lost = 0;
  int subcycles = 0;
  double dem_step_s = 0.0;
  long steps = 0;
  // Wall times [s]: total, and the per-phase sums of CouplingDiagnostics
  // (Fig. 2); drag_s is the part of dem_s spent on the drag in the subcycles.
  double wall_s = 0.0, setup_s = 0.0, fluid_s = 0.0, dem_s = 0.0, drag_s = 0.0, coupling_s = 0.0;

  /// Mean wall time of one fluid step with its subcycles [s] (set-up excluded).
  double wall_s_per_fluid_step() const { return steps > 0 ? (wall_s - setup_s) / static_cast<double>(steps) : 0.0; }

  /// The last metrics sample at or before t_s.
  const PlumeMetrics& at(double t_s) const;
  /// The last sample before the cloud reached the floor (the last sample when it never did).
  const PlumeMetrics& last_suspended() const;
};

/// Runs `scene` with its coupling mode replaced by options.mode.
PlumeRun run_plume(const Scene& scene, const PlumeRunOptions& options);

/// Snapshot file-name time label, e.g. 0.5 -> "0.50".
std::string time_label(double t_s);

}  // namespace fdem::plume

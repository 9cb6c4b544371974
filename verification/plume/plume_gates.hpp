#pragma once
// The plume study's claims, evaluated on the three runs (two-way, fluid to
// particle, particle to fluid), and the numbers the report reads
// (values.csv, meta.json). Shared by the fast tier (reduced plume) and the
// nightly full plume; only the thresholds differ, each argued in README.md.
#include <string>
#include <utility>
#include <vector>

#include "plume_study.hpp"

namespace fdem::plume {

struct PlumeRuns {
  PlumeRun twoway, f2p, p2f;
};

/// What the study measures from the three runs.
struct PlumeFindings {
  double spread_growth_twoway = 0.0;      // radial spread at the end / at t = 0, two-way
  double spread_ratio_over_f2p = 0.0;     // two-way spread / fluid-to-particle spread, both at the end
  double spread_ratio_over_p2f = 0.0;     // two-way spread at the end / particle-to-fluid spread at its last suspended sample
  double spread_change_f2p = 0.0;         // max_t |spread(t) / spread(0) - 1|, fluid to particle
  double spread_change_p2f = 0.0;         // same before the floor, particle to fluid
  double dome_twoway = 0.0;               // dome_shape at the end
  double dome_f2p = 0.0;                  // at the end
  double dome_p2f = 0.0;                  // at the last suspended sample
  // The dome_shape of largest magnitude over the run (p2f: before the floor),
  // with its sign. The shape is not monotone in time (the front widens, then
  // the ring spreads out of the core's reach), so the gate uses the extreme.
  double dome_extreme_twoway = 0.0;
  double dome_extreme_f2p = 0.0;
  double dome_extreme_p2f = 0.0;
  // |dome_extreme_twoway| over the larger one-way |dome_extreme|: the dome
  // forms only in two-way (gated by the *.dome_ratio_twoway_over_oneway rows
  // of reference_data/plume*.csv; a one-way shape of exactly 0 reads as 1e300).
  double dome_ratio_over_oneway = 0.0;
  double peak_fluid_speed_twoway = 0.0;   // max over samples [m/s]
  double peak_fluid_speed_f2p = 0.0;
  double peak_fluid_speed_p2f = 0.0;
  double freefall_error_p2f = 0.0;        // max over suspended samples of |centroid depth - closed form| / fall
  double freefall_checked_until_s = 0.0;  // last sample used for the above
};

/// Free fall with buoyancy: the centroid falls 0.5 g (1 - rho_f / rho_p) t^2.
PlumeFindings evaluate(const PlumeRuns& runs, double gravity_mps2, double fluid_density, double grain_density);

/// Writes values.csv (ids `<prefix>.<name>`) and meta.json into dir.
void write_values(const std::string& dir, const std::string& prefix, const PlumeRuns& runs, const PlumeFindings& f,
                  const std::vector<std::pair<std::string, double>>& extra);
/// The scene file each tier runs, relative to the source tree: full
/// plume.yaml, main plume_main.yaml (the main job's), fast plume_fast.yaml.
std::string tier_scene_file(const std::string& tier);
/// The results folder (and reference file) of each tier: plume_main for the
/// main job's tier, plume for the fast and the full one.
std::string tier_study(const std::string& tier);
/// meta.json through the shared writer (verification/support/study_io.hpp:
/// commit, scene hash, threads, ...) plus status "done", time_left_s = 0 and,
/// given the runs, per mode the wall time in all and per fluid step, and its
/// split (fluid, DEM, of which drag, coupling).
void write_meta(const std::string& dir, const std::string& tier, double wall_time_s, bool passed,
                const PlumeRuns* runs = nullptr);
/// meta.json while the study runs (status "running", passed false): where
/// the current mode stands, its wall time per fluid step, and the time left
/// to the end of this mode and of the study, so a run that is stopped or
/// times out still says how far it got and what it would have cost.
void write_progress_meta(const std::string& dir, const std::string& tier, const PlumeProgress& progress,
                         double study_wall_s, double study_time_left_s);

}  // namespace fdem::plume

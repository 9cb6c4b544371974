#pragma once
// What the plume tests share: run the three coupling modes of one scene,
// evaluate the findings, write the report's files, and (fast and full tiers)
// check the paper's claims on them.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "plume_gates.hpp"
#include "plume_study.hpp"
#include "scene/scene_loader.hpp"
#include "study_io.hpp"

namespace fdem::plume::testing {

/// $FDEM_RESULTS_DIR/plume (fast and full tiers) or .../plume_main (tier main).
inline std::string results_dir(const std::string& tier = "full") {
  return std::string(FDEM_RESULTS_DIR) + "/" + tier_study(tier);
}

inline Scene study_scene(const std::string& file) {
  return load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/plume/" + file);
}

struct StudyOutcome {
  PlumeRuns runs;
  PlumeFindings findings;
  double wall_s = 0.0;
};

// Runs two-way, fluid-to-particle, particle-to-fluid in turn. meta.json says
// "running" until the caller writes the final one: the time left is this
// mode's steps left at its mean wall time per step, plus the modes still to
// run at that same rate (an upper estimate for fluid-to-particle, which
// needs no fluid solve). p2f_end_s > 0 ends the particle-to-fluid run there
// (a scene without walls, whose free-falling grains would leave through the
// floor; the findings use only its suspended samples anyway).
inline StudyOutcome run_three_modes(const Scene& scene, const std::string& tier, double sample_interval_s,
                                    const std::vector<double>& snapshot_times_s, bool verbose,
                                    double p2f_end_s = 0.0) {
  const auto t0 = std::chrono::steady_clock::now();
  StudyOutcome out;
  PlumeRunOptions opt;
  opt.sample_interval_s = sample_interval_s;
  opt.snapshot_times_s = snapshot_times_s;
  opt.output_dir = results_dir(tier);
  opt.verbose = verbose;
  int modes_after_this = 2;
  opt.on_progress = [&](const PlumeProgress& p) {
    const double study_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double left = p.time_left_s + modes_after_this * static_cast<double>(p.steps_total) * p.wall_s_per_fluid_step;
    write_progress_meta(results_dir(tier), tier, p, study_wall_s, left);
  };
  opt.mode = CouplingMode::two_way;
  out.runs.twoway = run_plume(scene, opt);
  modes_after_this = 1;
  opt.mode = CouplingMode::fluid_to_particle;
  out.runs.f2p = run_plume(scene, opt);
  modes_after_this = 0;
  opt.mode = CouplingMode::particle_to_fluid;
  Scene p2f_scene = scene;
  if (p2f_end_s > 0.0) p2f_scene.time.end_time = p2f_end_s;
  out.runs.p2f = run_plume(p2f_scene, opt);
  const double rho_p = scene.particles.front().density;
  out.findings = evaluate(out.runs, -scene.gravity.z(), scene.fluid.density, rho_p);
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

inline void print_summary(const StudyOutcome& o) {
  const PlumeFindings& f = o.findings;
  for (const PlumeRun* r : {&o.runs.twoway, &o.runs.f2p, &o.runs.p2f})
    fmt::print("{:11s} wall {:7.1f} s (setup {:.1f}, fluid {:.1f}, DEM {:.1f} of which drag {:.1f}, coupling {:.1f}); "
               "{} steps x {} subcycles, {:.1f} ms per fluid step; "
               "max contacts {:g}, max overlap/d {:.3g}, max grain speed {:.3f} m/s, lost {}, floor at {:g} s\n",
               r->mode, r->wall_s, r->setup_s, r->fluid_s, r->dem_s, r->drag_s, r->coupling_s, r->steps, r->subcycles,
               1e3 * r->wall_s_per_fluid_step(),
               r->max_contacts, r->max_overlap_over_diameter, r->max_grain_speed_mps, r->grains_lost,
               r->floor_contact_time_s);
  fmt::print("spread growth two-way {:.4f}; ratio two-way/f2p {:.4f}, two-way/p2f {:.4f}; spread change f2p {:.2e}, "
             "p2f {:.2e}\n",
             f.spread_growth_twoway, f.spread_ratio_over_f2p, f.spread_ratio_over_p2f, f.spread_change_f2p,
             f.spread_change_p2f);
  fmt::print("dome shape two-way {:+.4f}, f2p {:+.4f}, p2f {:+.4f}; peak fluid speed two-way {:.4g}, f2p {:.3g}, p2f "
             "{:.4g} m/s; free-fall error p2f {:.2e} (until {:g} s)\n",
             f.dome_twoway, f.dome_f2p, f.dome_p2f, f.peak_fluid_speed_twoway, f.peak_fluid_speed_f2p,
             f.peak_fluid_speed_p2f, f.freefall_error_p2f, f.freefall_checked_until_s);
  std::fflush(stdout);
}

// One tier of the study (fast or full): its scene, sampling, the bound on a
// one-way run's spread change (each tier argues its own), and the rows of
// values.csv it adds beside the common ones.
struct Tier {
  std::string scene_file;     // in verification/plume/
  std::string name;           // fast | full (meta.json)
  std::string values_prefix;  // plume.fast | plume (ids in reference_data/plume.csv)
  double sample_interval_s;
  std::vector<double> snapshot_times_s;
  bool verbose;
  double one_way_spread_change;  // largest |spread change| of a one-way run
  std::function<std::vector<std::pair<std::string, double>>(const StudyOutcome&)> extra_values;
};

// Runs the tier's three modes, writes the report's files, and checks the
// paper's claims, each a named EXPECT: the gated rows of
// reference_data/plume.csv the tier measured (fluid at rest in f2p, free fall
// in p2f, spread ratios, dome ratio; at least 5), then
//   1. fluid to particle: the cloud does not spread;
//   2. particle to fluid: the grains fall freely (no spread, centroid on the
//      closed form) while the fluid they push recirculates, faster than in
//      two-way, where the drag that drives it is capped by the grains' weight;
//   3. two-way: the recirculation carries grains outward; only there (the
//      dome ratio is a gated row);
//   4. health: nothing left the domain.
inline void run_and_check(const Tier& tier) {
  const Scene scene = study_scene(tier.scene_file);
  std::filesystem::create_directories(results_dir());
  const StudyOutcome o = run_three_modes(scene, tier.name, tier.sample_interval_s, tier.snapshot_times_s, tier.verbose);
  print_summary(o);
  const PlumeFindings& f = o.findings;
  write_values(results_dir(), tier.values_prefix, o.runs, f,
               tier.extra_values ? tier.extra_values(o) : std::vector<std::pair<std::string, double>>{});
  int gated = 0;
  for (const std::string& failure : study::gate_failures(study::read_reference("plume"),
                                                         study::read_values(results_dir()), &gated))
    ADD_FAILURE() << failure;
  EXPECT_GE(gated, 5) << "reference_data/plume.csv: the tier's gated rows not measured";
  EXPECT_LE(f.spread_change_f2p, tier.one_way_spread_change);
  EXPECT_GT(f.freefall_checked_until_s, 0.0);
  EXPECT_LE(f.spread_change_p2f, tier.one_way_spread_change);
  EXPECT_GT(f.peak_fluid_speed_p2f, f.peak_fluid_speed_twoway);
  EXPECT_GT(f.peak_fluid_speed_twoway, 0.0);
  EXPECT_EQ(o.runs.twoway.grains_lost + o.runs.f2p.grains_lost + o.runs.p2f.grains_lost, 0);
  write_meta(results_dir(), tier.name, o.wall_s, !::testing::Test::HasFailure(), &o.runs);
}

}  // namespace fdem::plume::testing

#include "plume_gates.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <fmt/format.h>

#include "study_io.hpp"

namespace fdem::plume {

namespace {

double max_spread_change(const PlumeRun& run, double until_s) {
  const double s0 = run.metrics.front().radial_spread_m;
  double change = 0.0;
  for (const PlumeMetrics& m : run.metrics)
    if (m.t_s <= until_s + 1e-9) change = std::max(change, std::abs(m.radial_spread_m / s0 - 1.0));
  return change;
}

double extreme_dome(const PlumeRun& run, double until_s) {
  double dome = 0.0;
  for (const PlumeMetrics& m : run.metrics)
    if (m.t_s <= until_s + 1e-9 && std::abs(m.dome_shape) > std::abs(dome)) dome = m.dome_shape;
  return dome;
}

double max_fluid_speed(const PlumeRun& run) {
  double u = 0.0;
  for (const PlumeMetrics& m : run.metrics) u = std::max(u, m.peak_fluid_speed_mps);
  return u;
}

}  // namespace

PlumeFindings evaluate(const PlumeRuns& r, double g, double rho_f, double rho_p) {
  PlumeFindings f;
  const PlumeMetrics& end2 = r.twoway.metrics.back();
  const PlumeMetrics& end_f2p = r.f2p.metrics.back();
  const PlumeMetrics& susp_p2f = r.p2f.last_suspended();
  f.spread_growth_twoway = end2.radial_spread_m / r.twoway.metrics.front().radial_spread_m;
  f.spread_ratio_over_f2p = end2.radial_spread_m / end_f2p.radial_spread_m;
  f.spread_ratio_over_p2f = end2.radial_spread_m / susp_p2f.radial_spread_m;
  f.spread_change_f2p = max_spread_change(r.f2p, end_f2p.t_s);
  f.spread_change_p2f = max_spread_change(r.p2f, susp_p2f.t_s);
  f.dome_twoway = end2.dome_shape;
  f.dome_f2p = end_f2p.dome_shape;
  f.dome_p2f = susp_p2f.dome_shape;
  f.dome_extreme_twoway = extreme_dome(r.twoway, end2.t_s);
  f.dome_extreme_f2p = extreme_dome(r.f2p, end_f2p.t_s);
  f.dome_extreme_p2f = extreme_dome(r.p2f, susp_p2f.t_s);
  const double oneway_dome = std::max(std::abs(f.dome_extreme_f2p), std::abs(f.dome_extreme_p2f));
  f.dome_ratio_over_oneway = oneway_dome > 0.0 ? std::abs(f.dome_extreme_twoway) / oneway_dome : 1e300;
  f.peak_fluid_speed_twoway = max_fluid_speed(r.twoway);
  f.peak_fluid_speed_f2p = max_fluid_speed(r.f2p);
  f.peak_fluid_speed_p2f = max_fluid_speed(r.p2f);
  // Eq. 4-5 without drag: every grain accelerates at g (1 - rho_f / rho_p).
  const double a = g * (1.0 - rho_f / rho_p);
  const double c0 = r.p2f.metrics.front().centroid_depth_m;
  for (const PlumeMetrics& m : r.p2f.metrics) {
    if (m.t_s > susp_p2f.t_s + 1e-9 || m.t_s <= 0.0) continue;
    const double fall = 0.5 * a * m.t_s * m.t_s;
    f.freefall_error_p2f = std::max(f.freefall_error_p2f, std::abs(m.centroid_depth_m - c0 - fall) / fall);
    f.freefall_checked_until_s = m.t_s;
  }
  return f;
}

void write_values(const std::string& dir, const std::string& prefix, const PlumeRuns& r, const PlumeFindings& f,
                  const std::vector<std::pair<std::string, double>>& extra) {
  std::vector<std::pair<std::string, double>> v{
      {"grains", static_cast<double>(r.twoway.health.front().grains)},
      {"spread_growth_twoway", f.spread_growth_twoway},
      {"spread_ratio_twoway_over_f2p", f.spread_ratio_over_f2p},
      {"spread_ratio_twoway_over_p2f", f.spread_ratio_over_p2f},
      {"spread_change_f2p", f.spread_change_f2p},
      {"spread_change_p2f", f.spread_change_p2f},
      {"dome_shape_twoway", f.dome_twoway},
      {"dome_shape_f2p", f.dome_f2p},
      {"dome_shape_p2f", f.dome_p2f},
      {"dome_shape_extreme_twoway", f.dome_extreme_twoway},
      {"dome_shape_extreme_f2p", f.dome_extreme_f2p},
      {"dome_shape_extreme_p2f", f.dome_extreme_p2f},
      {"dome_ratio_twoway_over_oneway", f.dome_ratio_over_oneway},
      {"front_depth_twoway_m", r.twoway.metrics.back().front_depth_m},
      {"centroid_depth_twoway_m", r.twoway.metrics.back().centroid_depth_m},
      {"radial_spread_twoway_m", r.twoway.metrics.back().radial_spread_m},
      {"centroid_depth_f2p_m", r.f2p.metrics.back().centroid_depth_m},
      {"peak_fluid_speed_twoway_mps", f.peak_fluid_speed_twoway},
      {"peak_fluid_speed_f2p_mps", f.peak_fluid_speed_f2p},
      {"peak_fluid_speed_p2f_mps", f.peak_fluid_speed_p2f},
      {"freefall_error_p2f", f.freefall_error_p2f},
      {"p2f_floor_time_s", r.p2f.floor_contact_time_s},
  };
  for (const PlumeRun* run : {&r.twoway, &r.f2p, &r.p2f}) {
    v.emplace_back("wall_s." + run->mode, run->wall_s);
    v.emplace_back("fluid_s." + run->mode, run->fluid_s);
    v.emplace_back("dem_s." + run->mode, run->dem_s);
    v.emplace_back("drag_s." + run->mode, run->drag_s);
    v.emplace_back("wall_s_per_fluid_step." + run->mode, run->wall_s_per_fluid_step());
    v.emplace_back("coupling_s." + run->mode, run->coupling_s);
    v.emplace_back("max_overlap_over_d." + run->mode, run->max_overlap_over_diameter);
    v.emplace_back("max_grain_speed_mps." + run->mode, run->max_grain_speed_mps);
    v.emplace_back("max_contacts." + run->mode, run->max_contacts);
    v.emplace_back("grains_lost." + run->mode, static_cast<double>(run->grains_lost));
  }
  v.insert(v.end(), extra.begin(), extra.end());
  for (auto& entry : v) entry.first = prefix + "." + entry.first;
  study::write_values(dir, v);
}

std::string tier_scene_file(const std::string& tier) {
  if (tier == "full") return "verification/plume/plume.yaml";
  if (tier == "main") return "verification/plume/plume_main.yaml";
  return "verification/plume/plume_fast.yaml";
}

std::string tier_study(const std::string& tier) { return tier == "main" ? "plume_main" : "plume"; }

namespace {

study::RunRecord run_record(const std::string& tier, double wall_time_s, bool passed, const std::string& status,
                            std::string extra_json) {
  study::RunRecord run;
  run.tier = tier;
  run.scene_file = tier_scene_file(tier);
  run.wall_time_s = wall_time_s;
  run.passed = passed;
  run.status = status;
  run.extra_json = std::move(extra_json);
  return run;
}

}  // namespace

void write_meta(const std::string& dir, const std::string& tier, double wall_time_s, bool passed,
                const PlumeRuns* runs) {
  std::string extra = "\"time_left_s\": 0";
  if (runs != nullptr) {
    extra += ", \"modes\": {";
    const char* sep = "";
    for (const PlumeRun* r : {&runs->twoway, &runs->f2p, &runs->p2f}) {
      fmt::format_to(std::back_inserter(extra),
                     "{}\"{}\": {{\"wall_s\": {:.3f}, \"wall_s_per_fluid_step\": {:.5f}, \"fluid_steps\": {}, "
                     "\"subcycles\": {}, \"setup_s\": {:.3f}, \"fluid_s\": {:.3f}, \"dem_s\": {:.3f}, "
                     "\"drag_s\": {:.3f}, \"coupling_s\": {:.3f}}}",
                     sep, r->mode, r->wall_s, r->wall_s_per_fluid_step(), r->steps, r->subcycles, r->setup_s,
                     r->fluid_s, r->dem_s, r->drag_s, r->coupling_s);
      sep = ", ";
    }
    extra += "}";
  }
  study::write_meta(dir, tier_study(tier), run_record(tier, wall_time_s, passed, "done", extra));
}

void write_progress_meta(const std::string& dir, const std::string& tier, const PlumeProgress& progress,
                         double study_wall_s, double study_time_left_s) {
  study::write_meta(
      dir, tier_study(tier),
      run_record(tier, study_wall_s, false, "running",
                 fmt::format("\"time_left_s\": {:.1f}, \"mode\": \"{}\", \"t_s\": {:.4f}, \"end_s\": {:.4f}, "
                             "\"fluid_steps_done\": {}, \"fluid_steps\": {}, \"wall_s_per_fluid_step\": {:.5f}, "
                             "\"mode_time_left_s\": {:.1f}",
                             study_time_left_s, progress.mode, progress.t_s, progress.end_s, progress.steps_done,
                             progress.steps_total, progress.wall_s_per_fluid_step, progress.time_left_s)));
}

}  // namespace fdem::plume

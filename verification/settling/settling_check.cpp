// Single-particle settling (paper Sect. 4.1, Table 1): the coupled solver
// against the GSL reference of the same model, the paper and the experiment.
//
// Per diameter: one-way (fluid_to_particle: still water) and two-way runs of
// settling.yaml; the GSL ODE (reference/settling_reference) with the porosity
// of the element along the path; the Brent terminal velocity; Stokes' law.
// A run ends at 1 s or when the particle centre is 3 cells (12 mm) above the
// bottom, whichever comes first, so the bottom wall never acts on it; its
// terminal velocity is the speed at that last sample (every diameter has then
// run for > 25 response times).
//
// Tiers (FDEM_FULL_TIER): fast = one-way, two-way and GSL for all six
// diameters, each two-way run repeated at twice and four times the fluid step
// (the numerical uncertainty of its terminal velocity, grid_convergence.hpp),
// mu = 1e-4 by GSL and one-way; full (nightly) adds two-way at mu = 1e-4 for
// 0.208 and 0.76 mm.
// Gates: every gated row of reference_data/settling.csv this check measures,
// with that row's tolerance (study_io.hpp), plus the sign claims below.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "coupling/simulation.hpp"
#include "io/atomic_file.hpp"
#include "reference/settling_reference.hpp"
#include "grid_convergence.hpp"
#include "scene/scene_loader.hpp"
#include "study_io.hpp"
#include "study_tier.hpp"

namespace fdem {
namespace {

using verification::full_tier;
const std::vector<std::string> diameter_labels{"0.208", "0.25", "0.29", "0.42", "0.59", "0.76"};
constexpr double stop_height_m = 0.012;  // 3 cells above the bottom

// ---- one coupled run ----------------------------------------------------------
struct Run {
  std::vector<double> t, v;   // settling speed, positive downward [m/s]
  double terminal = 0.0;      // speed at the last sample
  double porosity = 1.0;      // of the particle's element at the last sample
  double fluid_w_at_particle = 0.0;  // vertical fluid velocity interpolated at the particle, last sample [m/s]
  double lateral_drift_m = 0.0;      // largest horizontal distance from the start
  double momentum_imbalance = 0.0;   // last step
  double wall_s = 0.0;
};

constexpr const char* kSceneFile = "verification/settling/settling.yaml";
// Fluid steps of the refinement: the scene's (the paper's 0.01 s) and two
// coarser ones, ratio 2; the DEM step stays 1e-5 s.
constexpr double kStepCoarsening = 2.0;
// The fluid sees the previous step's drag (explicit exchange, Sect. 3): first
// order in the fluid step whatever the fluid scheme's own order.
constexpr double kCouplingLagOrder = 1.0;

Scene settling_scene(double d, CouplingMode mode, double mu, double fluid_step_factor = 1.0) {
  Scene s = load_scene(std::string(FDEM_SOURCE_DIR) + "/" + kSceneFile);
  s.particles.at(0).size.diameter = d;
  s.effects.coupling = mode;
  s.fluid.viscosity = mu;
  s.time.fluid_step *= fluid_step_factor;
  s.time.subcycles = 0;  // fluid_step / dem_step
  return s;
}

Run run_settling(const Scene& scene) {
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(scene);
  Run r;
  const Vec3 start = scene.particles.at(0).position;
  r.t.push_back(0.0);
  r.v.push_back(-sim.particles().vz[0]);
  while (!sim.finished() && sim.particles().z[0] > stop_height_m) {
    sim.step();
    const Particles& p = sim.particles();
    r.t.push_back(sim.time());
    r.v.push_back(-p.vz[0]);
    r.lateral_drift_m = std::max(r.lateral_drift_m, std::hypot(p.x[0] - start.x(), p.y[0] - start.y()));
  }
  const Particles& p = sim.particles();
  const BoxMesh& mesh = *sim.mesh();
  const Index e = sim.particle_elements()[0];
  r.terminal = r.v.back();
  r.porosity = sim.porosity()[static_cast<std::size_t>(e)];
  const Eigen::Vector4d lambda = mesh.volume_coordinates(e, Vec3(p.x[0], p.y[0], p.z[0]));
  const auto u = sim.fluid_velocity();
  for (std::size_t a = 0; a < 4; ++a)
    r.fluid_w_at_particle += lambda[static_cast<Eigen::Index>(a)] * u[3 * static_cast<std::size_t>(mesh.element_nodes(e)[a]) + 2];
  r.momentum_imbalance = sim.diagnostics().momentum_imbalance;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// ---- the GSL reference of the same model ----------------------------------------
SettlingModel reference_model(const Scene& s, const BoxMesh& mesh) {
  SettlingModel m;
  const double d = s.particles.at(0).size.diameter;
  m.diameter_m = d;
  m.particle_density = s.particles.at(0).density;
  m.fluid = {s.fluid.density, s.fluid.viscosity};
  m.gravity_z = s.gravity.z();
  m.buoyancy = s.effects.buoyancy;
  m.drag = s.effects.drag;
  // The centre scheme (Eq. 32) with this one particle: 1 - V_p / V_e of the
  // element holding the centre, floored like the solver.
  const double floor = s.coupling.porosity_floor;
  m.porosity = [&mesh, d, floor](const Vec3& x) {
    const Index e = mesh.locate_element(x);
    return std::max(floor, 1.0 - sphere_volume(d) / mesh.element_volume(e));
  };
  return m;
}

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); }

struct DiameterResult {
  std::string label;
  double d = 0.0;
  double vt_gsl = 0.0, vt_stokes = 0.0, vt_gsl_mu4 = 0.0;
  Run oneway, twoway, oneway_mu4, twoway_mu4;
  bool has_twoway = false, has_twoway_mu4 = false;
  double twoway_terminal_2dt = 0.0, twoway_terminal_4dt = 0.0;  // fluid step x 2, x 4
  study::RefinementUncertainty twoway_u;                        // from the three fluid steps
  std::vector<double> v_gsl;        // GSL at the one-way sample times
  double oneway_max_dev_pct = 0.0;  // max over t > 0 of |v - v_gsl| / v_gsl
  double twoway_gsl_at_end = 0.0;   // GSL speed at the two-way run's last sample time
};

// Distinct ctest names per tier: FastTier... (label verification), FullTier... (nightly).
#if FDEM_FULL_TIER
#define FDEM_SETTLING_TEST FullTier_SingleParticleMatchesGslReferencePaperAndExperiment
#else
#define FDEM_SETTLING_TEST FastTier_SingleParticleMatchesGslReferencePaperAndExperiment
#endif

TEST(Settling, FDEM_SETTLING_TEST) {
  // One particle: nothing to share among threads, and ctest runs tests in
  // parallel on a 2-core machine; an OpenMP team per DEM step costs more than
  // the step (measured: 1000 one-particle steps 15 s with 2 threads under
  // load, 0.01 s with 1).
  omp_set_num_threads(1);
  const auto wall0 = std::chrono::steady_clock::now();
  const auto rows = study::read_reference("settling");
  auto ref = [&rows](const std::string& id) { return study::reference(rows, id).value; };
  const Scene base = load_scene(std::string(FDEM_SOURCE_DIR) + "/" + kSceneFile);
  const BoxMesh mesh(base.domain.lower, base.domain.upper, base.cells);
  const double mu_water = base.fluid.viscosity, mu_typo = 1.0e-4;
  const Vec3 start = base.particles.at(0).position;

  std::vector<DiameterResult> results;
  for (const std::string& label : diameter_labels) {
    DiameterResult r;
    r.label = label;
    r.d = std::stod(label) * 1e-3;

    // GSL reference and Stokes for water.
    const Scene s_one = settling_scene(r.d, CouplingMode::fluid_to_particle, mu_water);
    const SettlingModel model = reference_model(s_one, mesh);
    r.vt_gsl = terminal_velocity(model, model.porosity(start));
    r.vt_stokes = stokes_terminal_velocity(model);

    // One-way: fluid at rest, the same equations as the ODE.
    r.oneway = run_settling(s_one);
    const auto gsl = integrate_settling(model, start, 0.0, r.oneway.t);
    for (std::size_t k = 0; k < gsl.size(); ++k) {
      r.v_gsl.push_back(-gsl[k].w_m_s);
      if (r.oneway.t[k] > 0.0)
        r.oneway_max_dev_pct = std::max(r.oneway_max_dev_pct, 100.0 * std::abs(r.oneway.v[k] + gsl[k].w_m_s) / -gsl[k].w_m_s);
    }

    // Two-way, and at two coarser fluid steps for its numerical uncertainty.
    r.twoway = run_settling(settling_scene(r.d, CouplingMode::two_way, mu_water));
    r.has_twoway = true;
    const std::vector<double> t_end{r.twoway.t.back()};
    r.twoway_gsl_at_end = -integrate_settling(model, start, 0.0, t_end).back().w_m_s;
    r.twoway_terminal_2dt =
        run_settling(settling_scene(r.d, CouplingMode::two_way, mu_water, kStepCoarsening)).terminal;
    r.twoway_terminal_4dt =
        run_settling(settling_scene(r.d, CouplingMode::two_way, mu_water, kStepCoarsening * kStepCoarsening)).terminal;
    r.twoway_u =
        study::refinement_uncertainty(r.twoway.terminal, r.twoway_terminal_2dt, r.twoway_terminal_4dt, kStepCoarsening,
                                      kCouplingLagOrder);

    // The stated viscosity, 1e-4 Pa s.
    const Scene s_typo = settling_scene(r.d, CouplingMode::fluid_to_particle, mu_typo);
    const SettlingModel model_typo = reference_model(s_typo, mesh);
    r.vt_gsl_mu4 = terminal_velocity(model_typo, model_typo.porosity(start));
    r.oneway_mu4 = run_settling(s_typo);
    if (full_tier && (label == "0.208" || label == "0.76")) {
      r.twoway_mu4 = run_settling(settling_scene(r.d, CouplingMode::two_way, mu_typo));
      r.has_twoway_mu4 = true;
    }
    results.push_back(std::move(r));
  }

  // ---- write results (the shared writer, study_io.hpp) -------------------------------
  const std::string dir = study::results_dir("settling");
  std::filesystem::create_directories(dir);
  study::clear_dir(dir);
  std::vector<std::pair<std::string, double>> values;
  std::string terminal =
      "d_m,vt_exp_mps,vt_paper_mps,vt_stokes_mps,vt_gsl_mps,vt_oneway_mps,vt_twoway_mps,vt_gsl_mu1e-4_mps,"
      "vt_oneway_mu1e-4_mps,vt_twoway_mu1e-4_mps,vt_twoway_2dt_mps,vt_twoway_4dt_mps,u_num_twoway_mps\n";
  const double nan = std::nan("");
  for (const auto& r : results) {
    const std::string key = fmt::format("d{}mm", r.label);
    const double vt2 = r.has_twoway ? r.twoway.terminal : nan;
    if (r.has_twoway) {
      // The same simulated value S is compared with the experiment (vt_exp)
      // and with the paper's two-way column (vt_paper); its numerical
      // uncertainty and observed order from the fluid-step refinement.
      for (const char* row : {"vt_exp", "vt_paper"}) {
        values.emplace_back(fmt::format("settling.{}.{}", row, key), vt2);
        values.emplace_back(fmt::format("settling.{}.{}.u_num", row, key), r.twoway_u.u_num);
      }
      values.emplace_back("settling.twoway_fluid_step_order." + key, r.twoway_u.observed_order);
    }
    values.emplace_back("settling.vt_stokes." + key, r.vt_stokes);
    values.emplace_back("settling.reynolds_paper." + key, base.fluid.density * ref("settling.vt_exp." + key) * r.d / mu_typo);
    // The brief's ODE values are for an isolated sphere (eps = 1).
    SettlingModel iso = reference_model(settling_scene(r.d, CouplingMode::fluid_to_particle, mu_water), mesh);
    values.emplace_back("settling.vt_ode_design." + key, terminal_velocity(iso, 1.0));
    values.emplace_back("settling.oneway_vs_gsl_max_dev." + key, r.oneway_max_dev_pct);
    if (r.has_twoway) {
      values.emplace_back("settling.twoway_vs_gsl_dev." + key, 100.0 * (vt2 - r.twoway_gsl_at_end) / r.twoway_gsl_at_end);
      values.emplace_back("settling.fluid_w_at_particle_twoway." + key, r.twoway.fluid_w_at_particle);
      values.emplace_back("settling.lateral_drift_twoway_m." + key, r.twoway.lateral_drift_m);
    }
    values.emplace_back("settling.vt_gsl." + key, r.vt_gsl);
    values.emplace_back("settling.vt_oneway." + key, r.oneway.terminal);
    values.emplace_back("settling.vt_gsl_mu1e-4." + key, r.vt_gsl_mu4);
    // The stated mu = 1e-4 against the paper's two-way column: gated by the
    // rows settling.mu1e-4_excess_over_paper.* (at least the band within which
    // mu = 1e-3 reproduces the column; the slower of the two 1e-4 runs).
    values.emplace_back("settling.mu1e-4_excess_over_paper." + key,
                        std::min(r.vt_gsl_mu4, r.oneway_mu4.terminal) / ref("settling.vt_paper." + key) - 1.0);
    terminal += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", num(r.d), num(ref("settling.vt_exp." + key)),
                            num(ref("settling.vt_paper." + key)), num(r.vt_stokes), num(r.vt_gsl),
                            num(r.oneway.terminal), num(vt2), num(r.vt_gsl_mu4), num(r.oneway_mu4.terminal),
                            num(r.has_twoway_mu4 ? r.twoway_mu4.terminal : nan), num(r.twoway_terminal_2dt),
                            num(r.twoway_terminal_4dt), num(r.twoway_u.u_num));
    std::string series = "# settling speed (positive downward); empty: that run had ended (3 cells above the bottom)\n"
                         "t_s,v_oneway_mps,v_twoway_mps,v_gsl_mps\n";
    for (std::size_t k = 0; k < r.oneway.t.size(); ++k) {
      const bool has2 = r.has_twoway && k < r.twoway.t.size();
      series += fmt::format("{},{},{},{}\n", num(r.oneway.t[k]), num(r.oneway.v[k]), has2 ? num(r.twoway.v[k]) : "",
                            num(r.v_gsl[k]));
    }
    write_file_atomically(fmt::format("{}/series_{}.csv", dir, key), series);
  }
  study::write_values(dir, values);
  write_file_atomically(dir + "/terminal.csv", terminal);

  // ---- the table -----------------------------------------------------------------
  std::printf("\nSingle-particle settling, terminal velocity [m/s] (mu = %g Pa s; paper Table 1)\n", mu_water);
  std::printf("%7s %7s %7s %7s %8s %8s %8s %7s %7s %7s | %8s %8s\n", "d[mm]", "exp", "paper", "Stokes", "GSL",
              "1-way", "2-way", "2w/GSL", "2w/exp", "pap/exp", "GSL1e-4", "1w1e-4");
  for (const auto& r : results) {
    const std::string key = fmt::format("d{}mm", r.label);
    const double ve = ref("settling.vt_exp." + key), vp = ref("settling.vt_paper." + key);
    const double v2 = r.has_twoway ? r.twoway.terminal : nan;
    std::printf("%7s %7.3f %7.3f %7.3f %8.5f %8.5f %8.5f %+6.2f%% %+6.1f%% %+6.1f%% | %8.4f %8.4f\n", r.label.c_str(),
                ve, vp, r.vt_stokes, r.vt_gsl, r.oneway.terminal, v2, 100.0 * (v2 / r.twoway_gsl_at_end - 1.0),
                100.0 * (v2 / ve - 1.0), 100.0 * (vp / ve - 1.0), r.vt_gsl_mu4, r.oneway_mu4.terminal);
  }
  std::printf("one-way max deviation from GSL over time [%%]:");
  for (const auto& r : results) std::printf(" %.3f", r.oneway_max_dev_pct);
  std::printf("\n");
  for (const auto& r : results)
    if (r.has_twoway)
      std::printf("two-way d = %s mm: fluid w at particle %.5f m/s, (v2 - vGSL) = %.5f m/s, drift %.2e m, "
                  "eps %.5f, momentum imbalance %.4f, wall %.1f s\n",
                  r.label.c_str(), r.twoway.fluid_w_at_particle, r.twoway.terminal - r.twoway_gsl_at_end,
                  r.twoway.lateral_drift_m, r.twoway.porosity, r.twoway.momentum_imbalance, r.twoway.wall_s);

  // ---- gates ----------------------------------------------------------------------
  // Every gated row of reference_data/settling.csv that this tier measured,
  // with the row's own tolerance (the reasons are in its provenance column).
  bool passed = true;
  auto gate = [&passed](bool ok) {
    passed = passed && ok;
    return ok;
  };
  int gated = 0;
  for (const std::string& failure : study::gate_failures(rows, values, &gated)) {
    gate(false);
    ADD_FAILURE() << failure;
  }
  EXPECT_GT(gated, 0) << "no gated row of reference_data/settling.csv measured";
  for (const auto& r : results) {
    const std::string key = fmt::format("d{}mm", r.label);
    if (r.has_twoway) {
      // The explanation of the two-way excess over GSL: the grain drags the
      // fluid around it downward, so with the same slip it falls faster.
      EXPECT_TRUE(gate(r.twoway.fluid_w_at_particle < 0.0 && r.twoway.terminal > r.twoway_gsl_at_end)) << key;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  study::RunRecord run;
  run.tier = verification::tier_name;
  run.scene_file = kSceneFile;
  run.parameters = {{"diameters_mm", "0.208 0.25 0.29 0.42 0.59 0.76"},
                    {"fluid_step_s", fmt::format("{} (two-way also x2, x4)", base.time.fluid_step)},
                    {"dem_step_s", fmt::format("{}", base.time.dem_step)},
                    {"viscosity_pa_s", fmt::format("{} and {}", mu_water, mu_typo)},
                    {"twoway_at_typo_viscosity", full_tier ? "0.208 0.76 mm" : "none"}};
  run.wall_time_s = wall;
  run.passed = passed;
  study::write_meta(dir, "settling", run);
}

}  // namespace
}  // namespace fdem

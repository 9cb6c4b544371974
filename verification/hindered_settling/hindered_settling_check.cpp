// Hindered settling: the mean settling velocity v of a monodisperse
// suspension at solid fraction phi = 1 - eps in a closed column, over the
// single grain's terminal velocity U_t, against Richardson & Zaki (1954)
//   v / U_t = eps^n,   n(Re_t) of Garside & Al-Dibouni (1977, Eq. 13):
//   (5.1 - n) / (n - 2.7) = 0.1 Re_t^0.9,
// and Richardson & Zaki's own steps for n (their Eq. 2-6, no wall term):
// 4.65 (Re_t < 0.2), 4.4 Re_t^-0.03 (< 1), 4.4 Re_t^-0.1 (< 500), 2.4.
// The volume-averaged fluid (model A, Eq. 18-19 with d(eps)/dt) and the
// paper's simplified model (Eq. 21-22) side by side, with Di Felice's
// (1994) drag (Eq. 11 form: drag_laws/di_felice.hpp), which was fitted to
// such data; U_t is that law's own at eps = 1 (Dallavalle's Cd).
//
// What each model predicts for a uniform suspension (closed column: the
// volume flux eps u + (1 - eps) v = 0, so the slip is u - v = -v / eps):
//   model A:    the fluid carries the suspended weight, -dp/dz = (1-eps)
//               (rho_p - rho_f) g, and each grain feels drag f plus
//               -V_p dp/dz: f = eps W_b (W_b the buoyant weight), so
//               V_p K(eps, v/eps) v/eps = eps W_b;
//   simplified: div u = 0 in a closed box leaves u = 0: no backflow, no
//               pressure-gradient force, V_p K(eps, v) v = W_b.
// Both closed forms use the law's own K (coupling/drag.hpp), so the
// measured v is checked against its model exactly (verification) and
// against Richardson-Zaki (validation).
//
// Measured: the mean vertical velocity of the grains that start in the
// column's band [0.45, 0.85] H, over the second half of the run. The
// suspension's top descends with the grains, so these stay below it; the
// run ends before the sediment growing from the floor can reach them
// (run_case: kinematics of the band and the sediment, at most 0.5 s).
//
// Tiers (FDEM_FULL_TIER): fast = hindered_settling.yaml,
// solid fractions 0.05, 0.1, 0.2, 0.3 paired with Re_t 100, 10, 1, 0.1;
// full (nightly) = hindered_settling_full.yaml (a 9 x 9 mm column), every
// solid fraction at Re_t 0.1, 1, 10 and 100.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "coupling/drag.hpp"
#include "coupling/simulation.hpp"
#include "reference/brent_root.hpp"
#include "scene/scene_loader.hpp"
#include "../support/study_io.hpp"
#include "../support/study_results.hpp"
#include "../support/study_tier.hpp"

namespace fdem {
namespace {

using verification::full_tier;
constexpr const char* kStudy = "hindered_settling";
[[maybe_unused]] const ::testing::Environment* const kResults = fdem::verification::register_study_results(kStudy);
const std::string kTier = verification::tier_name;
constexpr double kGravity = 9.81;

const char* scene_file() {
  return full_tier ? FDEM_SOURCE_DIR "/verification/hindered_settling/hindered_settling_full.yaml"
                   : FDEM_SOURCE_DIR "/verification/hindered_settling/hindered_settling.yaml";
}

struct Case {
  double phi, reynolds;
};
const std::vector<Case> kCases = [] {
  if (!full_tier) return std::vector<Case>{{0.05, 100.0}, {0.1, 10.0}, {0.2, 1.0}, {0.3, 0.1}};
  std::vector<Case> all;
  for (double phi : {0.05, 0.1, 0.2, 0.3})
    for (double re : {0.1, 1.0, 10.0, 100.0}) all.push_back({phi, re});
  return all;
}();

struct Grain {
  double d, rho_p;
  DragLawEntry law;
  FluidProperties fluid;
  double buoyant_weight() const { return sphere_volume(d) * (rho_p - fluid.density) * kGravity; }
  double drag(double eps, double slip) const { return sphere_volume(d) * force_coefficient(law, eps, slip, d, fluid) * slip; }
  double terminal_velocity() const {
    return brent_root([&](double v) { return drag(1.0, v) - buoyant_weight(); }, 1e-9, 10.0);
  }
  // Closed forms (header).
  double model_a_velocity(double eps) const {
    return eps * brent_root([&](double s) { return drag(eps, s) - eps * buoyant_weight(); }, 1e-12, 10.0);
  }
  double simplified_velocity(double eps) const {
    return brent_root([&](double v) { return drag(eps, v) - buoyant_weight(); }, 1e-12, 10.0);
  }
};

double garside_al_dibouni_n(double re_t) {
  const double x = 0.1 * std::pow(re_t, 0.9);
  return (5.1 + 2.7 * x) / (1.0 + x);
}
double richardson_zaki_n(double re_t) {
  if (re_t < 0.2) return 4.65;
  if (re_t < 1.0) return 4.4 * std::pow(re_t, -0.03);
  if (re_t < 500.0) return 4.4 * std::pow(re_t, -0.1);
  return 2.4;
}

struct Outcome {
  double mu = 0, u_t = 0, re_t = 0, n_ga = 0, n_rz = 0;
  double velocity = 0;       // measured mean settling speed [m/s] (> 0 downward)
  double backflow = 0;       // measured eps u over (1 - eps) v in the band (1: the volume flux closes)
  double model = 0;          // the model's closed form [m/s]
  long outside = 0;
  int grains = 0;
  double wall_s = 0;
};

Outcome run_case(const Scene& base, const Case& c, FluidModel model) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene scene = base;
  ParticleSet& set = scene.particles.at(0);
  Grain g{set.size.diameter, set.density, drag_law(scene.effects.drag), {scene.fluid.density, 1e-3}};
  Outcome o;
  // Viscosity for the target Re_t (Re_t falls monotonically with mu).
  o.mu = brent_root(
      [&](double mu) {
        g.fluid.viscosity = mu;
        const double ut = g.terminal_velocity();
        return std::log(g.fluid.density * ut * g.d / g.fluid.viscosity) - std::log(c.reynolds);
      },
      1e-5, 10.0);
  g.fluid.viscosity = o.mu;
  o.u_t = g.terminal_velocity();
  o.re_t = g.fluid.density * o.u_t * g.d / o.mu;
  o.n_ga = garside_al_dibouni_n(o.re_t);
  o.n_rz = richardson_zaki_n(o.re_t);
  const double eps = 1.0 - c.phi;
  o.model = model == FluidModel::simplified ? g.simplified_velocity(eps) : g.model_a_velocity(eps);
  scene.fluid.viscosity = o.mu;
  scene.fluid.model = model;
  scene.fluid.porosity_time_derivative = model != FluidModel::simplified;
  const Box& column = scene.domain;
  const double height = column.upper.z() - column.lower.z();
  const double volume = (column.upper.x() - column.lower.x()) * (column.upper.y() - column.lower.y()) * height;
  set.count = static_cast<int>(std::lround(c.phi * volume / sphere_volume(g.d)));
  o.grains = set.count;
  // Run length: the band's lowest grains (0.45 H) fall at v while the
  // sediment's top rises at v phi / (phi_s - phi) (volume balance, the
  // sediment at random close packing phi_s = 0.64, Scott & Kilgour 1969):
  // they meet when v t = 0.45 H (phi_s - phi) / phi_s. The run stops at 80 %
  // of that, at the faster of the model's and Richardson-Zaki's speed (the
  // slower one let the band of a fast, dense suspension fall into the
  // sediment: phi 0.2-0.3 at Re_t 10-100 read 0.09-0.74 of the speed), and
  // at most 0.5 s.
  constexpr double kSedimentSolidFraction = 0.64;
  const double v_fast = std::max(o.model, o.u_t * std::pow(eps, o.n_ga));
  const double travel = 0.8 * 0.45 * height * (kSedimentSolidFraction - c.phi) / kSedimentSolidFraction;
  scene.time.end_time = std::min(0.5, travel / v_fast);
  scene.time.end_time = std::ceil(scene.time.end_time / scene.time.fluid_step) * scene.time.fluid_step;
  Simulation sim(scene);
  const Particles& p = sim.particles();
  std::vector<std::size_t> band;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.z[i] >= 0.45 * height && p.z[i] <= 0.85 * height) band.push_back(i);
  const BoxMesh& mesh = *sim.mesh();
  double v_sum = 0.0, flux_sum = 0.0;
  long samples = 0;
  while (!sim.finished()) {
    sim.step();
    o.outside = std::max(o.outside, sim.diagnostics().particles_outside_mesh);
    if (2 * sim.step_index() <= sim.steps_to_end()) continue;
    double v = 0.0;
    for (std::size_t i : band) v += p.vz[i];
    v /= static_cast<double>(band.size());
    // Volume flux of the fluid in the middle half of the band's current
    // extent: the volume mean of eps u_z (element porosity times its nodes'
    // mean u_z) against what closes the column's flux, -(1 - eps) v.
    double flux = 0.0, vol = 0.0, zmin = 1e300, zmax = -1e300;
    for (std::size_t i : band) {
      zmin = std::min(zmin, p.z[i]);
      zmax = std::max(zmax, p.z[i]);
    }
    const auto u = sim.fluid_velocity();
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const double zc = mesh.element_centroid(e).z();
      double uz = 0.0;
      for (Index a : mesh.element_nodes(e)) uz += u[3 * static_cast<std::size_t>(a) + 2] / 4.0;
      if (zc < zmin + 0.25 * (zmax - zmin) || zc > zmax - 0.25 * (zmax - zmin)) continue;
      flux += mesh.element_volume(e) * sim.porosity()[static_cast<std::size_t>(e)] * uz;
      vol += mesh.element_volume(e);
    }
    v_sum += v;
    flux_sum += flux / vol / (-c.phi * v);  // eps u over -(1 - eps) v: 1 when the volume flux closes
    ++samples;
  }
  o.velocity = -v_sum / static_cast<double>(samples);
  o.backflow = flux_sum / static_cast<double>(samples);
  o.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return o;
}

void run_model(FluidModel model, const std::string& name) {
  omp_set_num_threads(1);
  const Scene base = load_scene(scene_file());
  verification::TierValues values(kStudy);
  double worst_ga = 1.0, worst_rz = 1.0, worst_model = 1.0, worst_backflow = 1.0;
  fmt::print("Hindered settling ({} tier, {}, drag {}):\n", kTier, name, base.effects.drag);
  fmt::print("  phi   Re_t    mu [Pa s]   U_t [m/s]  n_GA   grains  v/U_t    eps^n_GA eps^n_RZ  model    v/model  v/GA    flux  wall [s]\n");
  for (const Case& c : kCases) {
    const Outcome o = run_case(base, c, model);
    const double eps = 1.0 - c.phi, ratio = o.velocity / o.u_t, ga = std::pow(eps, o.n_ga), rz = std::pow(eps, o.n_rz);
    fmt::print("  {:.2f}  {:6.2f}  {:.4e}  {:.4e}  {:.3f}  {:5d}  {:.4f}   {:.4f}   {:.4f}   {:.4f}   {:.4f}   {:.4f}  {:.3f}  {:.1f}\n",
               c.phi, o.re_t, o.mu, o.u_t, o.n_ga, o.grains, ratio, ga, rz, o.model / o.u_t, o.velocity / o.model,
               ratio / ga, o.backflow, o.wall_s);
    EXPECT_EQ(o.outside, 0) << name << " phi " << c.phi;
    const std::string key = fmt::format("phi{}.re{}", c.phi, c.reynolds);
    values.add(fmt::format("{}.velocity_over_terminal.{}", name, key), ratio);
    values.add(fmt::format("{}.over_garside_al_dibouni.{}", name, key), ratio / ga);
    values.add(fmt::format("{}.over_richardson_zaki_1954.{}", name, key), ratio / rz);
    values.add(fmt::format("{}.over_closed_form.{}", name, key), o.velocity / o.model);
    values.add(fmt::format("{}.volume_flux_closure.{}", name, key), o.backflow);
    if (std::abs(ratio / ga - 1) > std::abs(worst_ga - 1)) worst_ga = ratio / ga;
    if (std::abs(ratio / rz - 1) > std::abs(worst_rz - 1)) worst_rz = ratio / rz;
    if (std::abs(o.velocity / o.model - 1) > std::abs(worst_model - 1)) worst_model = o.velocity / o.model;
    if (std::abs(o.backflow - 1) > std::abs(worst_backflow - 1)) worst_backflow = o.backflow;
    fdem::verification::record_series_row(
        kStudy, "settling.csv", fmt::format("{}_{}_{:.2f}_{:07.2f}", kTier, name, c.phi, c.reynolds),
        {"tier", "model", "solid_fraction", "reynolds_t", "viscosity_pa_s", "terminal_velocity_m_s", "grains",
         "settling_velocity_m_s", "velocity_over_terminal", "richardson_zaki_ga", "richardson_zaki_1954",
         "closed_form_over_terminal", "volume_flux_closure"},
        {kTier, name, fmt::format("{}", c.phi), fmt::format("{}", o.re_t), fmt::format("{}", o.mu),
         fmt::format("{}", o.u_t), fmt::format("{}", o.grains), fmt::format("{}", o.velocity), fmt::format("{}", ratio),
         fmt::format("{}", ga), fmt::format("{}", rz), fmt::format("{}", o.model / o.u_t),
         fmt::format("{}", o.backflow)});
  }
  values.add(name + ".over_garside_al_dibouni.worst", worst_ga);
  values.add(name + ".over_richardson_zaki_1954.worst", worst_rz);
  values.add(name + ".over_closed_form.worst", worst_model);
  values.add(name + ".volume_flux_closure.worst", worst_backflow);
  int gated = 0;
  for (const std::string& failure : study::gate_failures(study::read_reference(kStudy), values.list, &gated))
    ADD_FAILURE() << failure;
  EXPECT_GE(gated, 1) << "reference_data/" << kStudy << ".csv: gated rows not measured";
}

#if FDEM_FULL_TIER
#define FDEM_HS_TEST(name) FullTier_##name
#else
#define FDEM_HS_TEST(name) FastTier_##name
#endif

TEST(HinderedSettling, FDEM_HS_TEST(VansA_RichardsonZakiAndItsClosedForm)) { run_model(FluidModel::vans_a, "vans_a"); }
TEST(HinderedSettling, FDEM_HS_TEST(Simplified_ItsClosedFormWithoutBackflow)) {
  run_model(FluidModel::simplified, "simplified");
}

}  // namespace
}  // namespace fdem

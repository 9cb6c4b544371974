// Liquid-fluidized bed: pressure drop across a bed of glass beads in water
// against the superficial velocity, the inlet raised in stages from below to
// about 3 U_mf and back, with the volume-averaged fluid (model A, paper Eq.
// 18-19 as Zhou et al. 2010 set II) and the paper's simplified model (Eq.
// 21-22) on the same bed, settled first by the DEM alone.
//
// What is compared (N grains of volume V_p in a column of section A, bed
// height H = 2 <z> from the grains' mean centre height above the floor, bed
// porosity eps = 1 - N V_p / (A H)):
//   packed branch   Delta p against Ergun (1952) for the bed's measured
//                   porosity profile: Ergun's gradient
//                   150 (1-eps)^2 mu U / (eps^3 d^2) + 1.75 (1-eps) rho U^2 / (eps^3 d)
//                   summed over the cell layers, each at its exact porosity
//                   (the gated reading: Ergun is a local law and the bed is
//                   looser at the floor and part-fills its top cell); at the
//                   mean eps over H it is tabulated beside (README 'Packed branch');
//   plateau         Delta p against the bed's buoyant weight per area
//                   W / A = N V_p (rho_p - rho_f) g / A;
//   U_mf            where the packed branch's fit a U + b U^2 meets the
//                   plateau, against Ergun's onset for the last packed
//                   stage's profile (the layered Ergun = W / A; gated), for
//                   the mean eps (tabulated) and
//                   Wen & Yu's (1966) correlation Re_mf = sqrt(33.7^2 + 0.0408 Ar) - 33.7;
//   bed height      in the fluidized stages against Richardson & Zaki (1954)
//                   U = U_t eps^n, n of Garside & Al-Dibouni (1977), and
//                   against the drag law's own homogeneous expansion (Ergun's
//                   branch: (1 - eps)(rho_p - rho_f) g = Ergun(eps, U));
//   hysteresis      Delta p and H at the same U rising and falling.
// What each model predicts, before any run (fluidized_bed README):
//   model A: the grains feel drag and -V_p grad p, the fluid -eps grad p
//            and the drag; at steady state -dp/dz = (1-eps)(rho_p-rho_f) g,
//            so the plateau is W / A and the onset Ergun's;
//   simplified: div u = 0 keeps u = U in the bed and the grains feel drag
//            only: beta(U) U = (1-eps)(rho_p-rho_f) g at the onset, U_mf
//            higher by about 1 / eps^2 (viscous limit), and the paper's
//            source (F / eps) makes its plateau W / (eps A).
//
// The run and the closed forms: fluidized_bed_study.hpp.
//
// Tiers (FDEM_FULL_TIER): fast = fluidized_bed.yaml (400 grains,
// 3 x 3 x 15 cells); full (nightly) = fluidized_bed_full.yaml (3000 grains,
// 4 x 4 x 15 cells), more stages.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "../support/bed_pressure_gradient.hpp"
#include "../support/study_io.hpp"
#include "../support/study_results.hpp"
#include "../support/study_tier.hpp"
#include "fluidized_bed_study.hpp"

namespace fdem {
namespace {

using verification::full_tier;
constexpr const char* kStudy = "fluidized_bed";
[[maybe_unused]] const ::testing::Environment* const kResults = fdem::verification::register_study_results(kStudy);

const char* scene_file() {
  return full_tier ? FDEM_SOURCE_DIR "/verification/fluidized_bed/fluidized_bed_full.yaml"
                   : FDEM_SOURCE_DIR "/verification/fluidized_bed/fluidized_bed.yaml";
}
const std::string kTier = verification::tier_name;

// Stages as multiples of the Ergun U_mf of the settled bed, rising then
// falling. The packed stages stay below 0.8 U_mf (a bed whose porosity
// varies by a few % starts to lift locally near the onset).
const std::vector<double> kStageFactors =
    full_tier ? std::vector<double>{0.2, 0.4, 0.6, 0.8, 1.3, 1.7, 2.2, 3.0, 2.2, 1.7, 1.3, 0.8, 0.6, 0.4, 0.2}
              : std::vector<double>{0.3, 0.6, 1.5, 2.2, 3.0, 2.2, 1.5, 0.6, 0.3};
// Stage lengths [s]: a packed stage after a packed one only waits for the
// fluid (its response time rho / beta ~ 1e-4 s); a fluidized stage, or the
// first packed one after them, waits for the bed to expand or collapse:
// the bed surface moves at the hindered-settling speed (~1 cm/s) over the
// expansion (a few mm): ~0.3 s; the second half of each stage is averaged
// (README: the first and second quarter of that window differ by < 1 %).
constexpr double kPackedStage = 0.1;
constexpr double kMovingStage = full_tier ? 1.2 : 0.8;
// [s] the DEM alone, grains from rest in the column: falling ~30 (full: 40) mm and
// coming to rest (largest grain speed asserted below 1 mm/s; at 0.4 s the fast
// bed still rattled at 1.1 mm/s after the half-list DEM changed its last bits).
constexpr double kDrySettle = full_tier ? 0.8 : 0.5;

using namespace fluidized_bed;  // NOLINT: the study's own names

// One row per stage (report_figures.py draws them), with what its curves
// need: Ergun's drop a U + b U^2 at the settled bed's porosity and height,
// and Richardson-Zaki's H(U) = h_s / (1 - (U / U_t)^(1/n)), h_s = N V_p / A.
void record_stages(const BedRun& run, const Prepared& p) {
  const Bed& bed = p.bed;
  // E(U) = a U + b U^2: b = 2 (E(1) - 2 E(1/2)), a = E(1) - b.
  const double e1 = ergun_drop(bed, p.settled_porosity, 1.0, p.settled_height);
  const double e_half = ergun_drop(bed, p.settled_porosity, 0.5, p.settled_height);
  const double ergun_b = 2.0 * (e1 - 2.0 * e_half), ergun_lin = e1 - ergun_b;
  const double ut = terminal_velocity(bed), n = garside_al_dibouni_n(bed.rho_f * ut * bed.d / bed.mu);
  for (std::size_t k = 0; k < run.stages.size(); ++k) {
    const Stage& s = run.stages[k];
    fdem::verification::record_series_row(
        kStudy, "stages.csv", fmt::format("{}_{}_{:02d}", kTier, run.model, k),
        {"tier", "model", "stage", "direction", "superficial_velocity_m_s", "u_over_umf_ergun", "pressure_drop_pa",
         "pressure_drop_sd_pa", "buoyant_weight_per_area_pa", "bed_height_m", "bed_porosity", "drag_over_weight",
         "grain_pressure_over_weight", "fluid_pressure_over_weight", "solid_pressure_over_weight",
         "floor_load_over_weight", "ergun_a_pa_s_per_m", "ergun_b_pa_s2_per_m2", "terminal_velocity_m_s",
         "richardson_zaki_n", "solid_height_m"},
        {kTier, run.model, fmt::format("{}", k), s.rising ? "rising" : "falling", fmt::format("{}", s.velocity),
         fmt::format("{}", s.factor), fmt::format("{}", s.drop), fmt::format("{}", s.drop_sd),
         fmt::format("{}", bed.buoyant_weight_per_area()), fmt::format("{}", s.height), fmt::format("{}", s.porosity),
         fmt::format("{}", s.drag), fmt::format("{}", s.grain_pressure), fmt::format("{}", s.fluid_pressure),
         fmt::format("{}", s.solid_pressure), fmt::format("{}", s.floor_load), fmt::format("{}", ergun_lin),
         fmt::format("{}", ergun_b), fmt::format("{}", ut), fmt::format("{}", n),
         fmt::format("{}", bed.solid_volume() / bed.area)});
  }
}

Prepared prepare_tier(FluidModel model, SourceForm form, const std::string& tag) {
  return prepare(scene_file(), kDrySettle, model, form, Settings{}, kStageFactors, kTier + "_" + tag);
}

void check_gates(const verification::TierValues& v, int minimum) {
  int gated = 0;
  for (const std::string& failure : study::gate_failures(study::read_reference(kStudy), v.list, &gated))
    ADD_FAILURE() << failure;
  EXPECT_GE(gated, minimum) << "reference_data/" << kStudy << ".csv: gated rows not measured";
}

#if FDEM_FULL_TIER
#define FDEM_FB_TEST(name) FullTier_##name
#else
#define FDEM_FB_TEST(name) FastTier_##name
#endif

// Model A's run on the tier's bed with `settings` (none: the scene's), its
// values under "<model_key>.".
void check_vans_a(const std::string& model_key, const Settings& settings, int minimum_gated) {
  omp_set_num_threads(1);
  const Prepared p = prepare(scene_file(), kDrySettle, FluidModel::vans_a, SourceForm::conservative, settings,
                             kStageFactors, kTier + "_" + model_key);
  EXPECT_LT(p.settle_speed, 1e-3) << "the dry settle did not come to rest";
  const BedRun run = run_stages(p, model_key, kPackedStage, kMovingStage);
  record_stages(run, p);
  EXPECT_EQ(run.outside, 0) << "grains left the column";
  verification::TierValues v(kStudy);
  const Bed& b = p.bed;
  const double w = b.buoyant_weight_per_area();
  // Packed branch (rising): Delta p over Ergun for each stage's eps and U; the worst.
  double worst = 1.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double r = s.drop / ergun_drop(b, s.porosity, s.velocity, s.height);
    v.add(fmt::format("{}.packed_over_ergun.u{:.2f}", model_key, s.factor), r);
    if (std::abs(r - 1) > std::abs(worst - 1)) worst = r;
  }
  v.add(model_key + ".packed_over_ergun.worst", worst);
  // The same against Ergun over the cell layers' porosities, and the
  // branch's shape: the ratio's spread over the packed stages (Ergun's
  // viscous-to-inertial mix with U reproduced if the ratio is constant).
  double worst_layered = 1.0, lo = 1e300, hi = 0.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double r = s.drop / s.layered_ergun, re = s.drop / ergun_drop(b, s.porosity, s.velocity, s.height);
    v.add(fmt::format("{}.packed_over_layered_ergun.u{:.2f}", model_key, s.factor), r);
    if (std::abs(r - 1) > std::abs(worst_layered - 1)) worst_layered = r;
    lo = std::min(lo, re);
    hi = std::max(hi, re);
  }
  v.add(model_key + ".packed_over_layered_ergun.worst", worst_layered);
  v.add(model_key + ".packed_ratio_spread", hi / lo - 1.0);
  // The packed branch where Ergun's law is stated, a homogeneous bed: the
  // gradient between two taps in the bed's interior (a cell above the floor,
  // a cell below the top less 2 d; verification/packed_bed's random bed
  // likewise) against Ergun at the exact porosity between them (the grains'
  // sphere-slab volumes, whatever the porosity scheme). And what the bed's
  // ends cost at this cell size: Ergun over the cell layers' exact
  // porosities against Ergun at the bed's mean porosity, and the run against
  // the former.
  double worst_interior = 1.0, worst_ends = 1.0, worst_exact_layered = 1.0, worst_interior_scheme = 0.0;
  for (const Stage& s : select(run.stages, true, true)) {
    ASSERT_GE(s.band_planes, 2) << "the bed is too short for two taps inside it";
    const double ri = s.interior_gradient / verification::ergun_gradient(s.interior_porosity, s.velocity, b.d, b.rho_f, b.mu);
    const double re = s.exact_layered_ergun / ergun_drop(b, s.porosity, s.velocity, s.height);
    const double rx = s.drop / s.exact_layered_ergun;
    v.add(fmt::format("{}.interior_packed_over_ergun.u{:.2f}", model_key, s.factor), ri);
    v.add(fmt::format("{}.exact_layered_ergun_over_ergun.u{:.2f}", model_key, s.factor), re);
    v.add(fmt::format("{}.packed_over_exact_layered_ergun.u{:.2f}", model_key, s.factor), rx);
    if (std::abs(ri - 1) > std::abs(worst_interior - 1)) worst_interior = ri;
    if (std::abs(re - 1) > std::abs(worst_ends - 1)) worst_ends = re;
    if (std::abs(rx - 1) > std::abs(worst_exact_layered - 1)) worst_exact_layered = rx;
    const double excess = s.interior_scheme_porosity - s.interior_porosity;
    if (std::abs(excess) > std::abs(worst_interior_scheme)) worst_interior_scheme = excess;
  }
  v.add(model_key + ".interior_packed_over_ergun.worst", worst_interior);
  v.add(model_key + ".exact_layered_ergun_over_ergun.worst", worst_ends);
  v.add(model_key + ".packed_over_exact_layered_ergun.worst", worst_exact_layered);
  v.add(model_key + ".interior_scheme_porosity_excess.worst", worst_interior_scheme);
  v.add(model_key + ".interior_porosity", select(run.stages, true, true).front().interior_porosity);
  // The resolution of that profile: Ergun over slabs one grain thick
  // (exact porosities too) against Ergun over the cell layers. Below the
  // cell the porosity is no longer a continuum's (the floor's first grain
  // layer, the surface's single grains), so the cell layers are the profile
  // the reference takes; this says how far the finer one would move it.
  double worst_grain_scale = 1.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double r = s.grain_layered_ergun / s.exact_layered_ergun;
    if (std::abs(r - 1) > std::abs(worst_grain_scale - 1)) worst_grain_scale = r;
  }
  v.add(model_key + ".grain_layered_over_exact_layered_ergun.worst", worst_grain_scale);
  // Plateau: fluidized stages (rising and falling) over W / A; the worst.
  double worst_plateau = 1.0, plateau_sum = 0.0;
  int plateau_n = 0;
  for (const Stage& s : run.stages) {
    if (s.factor < 1.0) continue;
    const double r = s.drop / w;
    v.add(fmt::format("{}.plateau_over_weight.{}.u{:.2f}", model_key, s.rising ? "rising" : "falling", s.factor), r);
    if (std::abs(r - 1) > std::abs(worst_plateau - 1)) worst_plateau = r;
    plateau_sum += s.drop;
    ++plateau_n;
  }
  v.add(model_key + ".plateau_over_weight.worst", worst_plateau);
  // The same over the fully fluidized stages (>= 2 U_mf), where the floor
  // carries < 1 % of W (row floor_load_over_weight; at 1.3-1.5 U_mf the
  // floor layer, looser than the bed, is still partly at rest on it).
  double worst_fluidized = 1.0;
  for (const Stage& s : run.stages)
    if (s.factor >= 2.0 && std::abs(s.drop / w - 1) > std::abs(worst_fluidized - 1)) worst_fluidized = s.drop / w;
  v.add(model_key + ".plateau_over_weight.fluidized_worst", worst_fluidized);
  // The bed's momentum balance in the fully fluidized stages (>= 2 U_mf),
  // each term over W (fluidized_bed_study.cpp, balance()): what the floor
  // carries (gated: a fluidized bed hands no weight to it), the fluid's
  // int eps_h (-dp/dz) short of the drag it receives (a discrete term at the
  // bed's surface), and the grains' pressure force above
  // int (1 - eps_h)(-dp/dz), which model A's exchange makes zero
  // (coupling/fluid_stress_force.hpp).
  double worst_floor = 0.0, drop_top = 0.0, drop_second = 0.0, top = 0.0, second = 0.0;
  double worst_fluid = 0.0, worst_excess = 0.0;
  for (const Stage& s : run.stages) {
    if (s.factor < 2.0) continue;
    const std::string key = fmt::format("{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor);
    v.add(model_key + ".floor_load_over_weight." + key, s.floor_load);
    v.add(model_key + ".fluid_pressure_shortfall." + key, s.drag - s.fluid_pressure);
    v.add(model_key + ".grain_pressure_excess." + key, s.grain_pressure - s.solid_pressure);
    v.add(model_key + ".pressure_integral_over_plane_drop." + key, s.pressure_integral * w / s.drop);
    if (std::abs(s.floor_load) > std::abs(worst_floor)) worst_floor = s.floor_load;
    if (std::abs(s.drag - s.fluid_pressure) > std::abs(worst_fluid)) worst_fluid = s.drag - s.fluid_pressure;
    if (std::abs(s.grain_pressure - s.solid_pressure) > std::abs(worst_excess))
      worst_excess = s.grain_pressure - s.solid_pressure;
    if (s.rising && s.factor > top) {
      second = top;
      drop_second = drop_top;
      top = s.factor;
      drop_top = s.drop;
    } else if (s.rising && s.factor > second) {
      second = s.factor;
      drop_second = s.drop;
    }
  }
  v.add(model_key + ".floor_load_over_weight.worst", worst_floor);
  v.add(model_key + ".fluid_pressure_shortfall.worst", worst_fluid);
  v.add(model_key + ".grain_pressure_excess.worst", worst_excess);
  {
    double worst_nodal = 1.0;
    for (const Stage& s : run.stages)
      if (s.factor >= 2.0 && std::abs(s.drop_nodal / s.drop - 1) > std::abs(worst_nodal - 1)) worst_nodal = s.drop_nodal / s.drop;
    v.add(model_key + ".nodal_mean_drop_over_face_drop.worst", worst_nodal);
  }
  v.add(model_key + ".plateau_flatness", std::abs(drop_top / drop_second - 1.0));
  const double plateau = plateau_sum / plateau_n;
  // U_mf from the curve: the rising packed branch's Ergun-form fit meets the plateau.
  const double umf_curve = onset_velocity(select(run.stages, true, true), plateau);
  const Stage& first = run.stages.front();
  const double umf_pred = ergun_umf(b, first.porosity);
  v.add(model_key + ".umf_curve_over_ergun", umf_curve / umf_pred);
  // Ergun's onset for the measured porosity profile, as the packed branch is
  // compared against the profile: where Ergun summed over the cell layers'
  // exact porosities meets W / A. Ergun's U_mf is taken at eps_mf, the bed
  // at incipient fluidization (Kunii & Levenspiel 1991, Eq. 3.19); the
  // packed bed loosens as the flow unloads its contacts, so the last rising
  // packed stage's profile is the one nearest the onset, and the first
  // (densest, the settled bed's) is tabulated beside.
  const Stage onset_stage = select(run.stages, true, true).back();  // a copy: select returns a new list
  const double umf_profile = profile_ergun_umf(b, onset_stage.exact_layer_porosity, onset_stage.layer_height);
  const double umf_profile_first = profile_ergun_umf(b, first.exact_layer_porosity, first.layer_height);
  v.add(model_key + ".umf_profile_ergun_over_ergun", umf_profile / umf_pred);
  v.add(model_key + ".umf_profile_ergun_first_stage_over_ergun", umf_profile_first / umf_pred);
  v.add(model_key + ".umf_curve_over_profile_ergun", umf_curve / umf_profile);
  v.add(model_key + ".umf_curve_over_profile_ergun_first_stage", umf_curve / umf_profile_first);
  v.add(model_key + ".plateau_mean_over_weight", plateau / w);
  v.add(model_key + ".umf_curve_over_wen_yu", umf_curve / wen_yu_umf(b));
  v.add(model_key + ".umf_curve_m_s", umf_curve);
  v.add(model_key + ".packed_porosity", first.porosity);
  // Falling branch: its own U_mf and the packing it leaves (hysteresis).
  const auto falling_packed = select(run.stages, false, true);
  if (falling_packed.size() >= 2) {
    v.add(model_key + ".umf_falling_over_rising", onset_velocity(falling_packed, plateau) / umf_curve);
  }
  // Bed height in the fluidized stages against Richardson-Zaki (Garside &
  // Al-Dibouni's n, U_i = U_t: the model has no wall drag) and against the
  // drag law's own homogeneous expansion.
  const double ut = terminal_velocity(b), re_t = b.rho_f * ut * b.d / b.mu, n = garside_al_dibouni_n(re_t);
  v.add(model_key + ".terminal_velocity_m_s", ut);
  v.add(model_key + ".richardson_zaki_n", n);
  double worst_rz = 1.0, worst_model = 1.0;
  for (const Stage& s : run.stages) {
    if (s.factor < 1.0) continue;
    const double h_rz = b.solid_volume() / (b.area * (1.0 - std::pow(s.velocity / ut, 1.0 / n)));
    const double h_model = b.solid_volume() / (b.area * (1.0 - ergun_expansion_porosity(b, s.velocity)));
    const std::string key = fmt::format("{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor);
    v.add(model_key + ".height_over_richardson_zaki." + key, s.height / h_rz);
    v.add(model_key + ".height_over_ergun_expansion." + key, s.height / h_model);
    if (std::abs(s.height / h_rz - 1) > std::abs(worst_rz - 1)) worst_rz = s.height / h_rz;
    if (std::abs(s.height / h_model - 1) > std::abs(worst_model - 1)) worst_model = s.height / h_model;
  }
  v.add(model_key + ".height_over_richardson_zaki.worst", worst_rz);
  // The porosity the drag sees in the fluidized stages: the mean over the
  // grains of their element's, below the bed's where a grain's own solid
  // weighs in the element it sits in (its drag then that of a denser bed).
  double worst_seen = 0.0;
  for (const Stage& s : run.stages)
    if (s.factor >= 1.0 && std::abs(s.porosity - s.grain_porosity) > std::abs(worst_seen)) worst_seen = s.porosity - s.grain_porosity;
  v.add(model_key + ".fluidized_grain_porosity_deficit.worst", worst_seen);
  v.add(model_key + ".height_over_ergun_expansion.worst", worst_model);
  // Hysteresis: the same U on both branches.
  for (const Stage& up : run.stages) {
    if (!up.rising) continue;
    for (const Stage& down : run.stages)
      if (!down.rising && std::abs(down.factor - up.factor) < 1e-9) {
        v.add(fmt::format("{}.hysteresis_drop.u{:.2f}", model_key, up.factor), down.drop / up.drop - 1.0);
        v.add(fmt::format("{}.hysteresis_height.u{:.2f}", model_key, up.factor), down.height / up.height - 1.0);
      }
  }
  v.add(model_key + ".wall_time_s", run.wall_s);
  fmt::print("{}: packed/Ergun worst {:.4f}, plateau/(W/A) worst {:.4f}, U_mf curve {:.4e} m/s = {:.4f} Ergun, "
             "{:.4f} Wen-Yu; H/RZ worst {:.4f}, H/Ergun-expansion worst {:.4f}; wall {:.1f} s\n",
             model_key, worst, worst_plateau, umf_curve, umf_curve / umf_pred, umf_curve / wen_yu_umf(b), worst_rz, worst_model,
             run.wall_s);
  fmt::print("{}: against the measured porosity profile: packed / Ergun over the cell layers' exact eps worst {:.4f} "
             "(that Ergun / Ergun at the mean eps worst {:.4f}; one-grain slabs / cell layers worst {:.4f}); "
             "U_mf curve / profile Ergun's {:.4f} at the last packed stage's profile, {:.4f} at the first's (profile / "
             "mean-eps Ergun's {:.4f}, {:.4f}); mean plateau / (W / A) {:.4f}\n",
             model_key, worst_exact_layered, worst_ends, worst_grain_scale, umf_curve / umf_profile,
             umf_curve / umf_profile_first, umf_profile / umf_pred, umf_profile_first / umf_pred, plateau / w);
  check_gates(v, minimum_gated);
}

TEST(FluidizedBed, FDEM_FB_TEST(VansA_ErgunBranchPlateauAndOnset)) { check_vans_a("vans_a", Settings{}, 3); }

// The same bed and stages with the exact sphere-tetrahedron porosity
// (coupling/porosity.hpp, `intersection`): no solid past the bed's ends and
// none scattered between elements, so the packed branch follows Ergun over
// the bed's measured porosity profile and the onset is Ergun's for that
// profile (README 'Packed branch'), gated on both tiers; against Ergun at
// the bed's MEAN porosity only the fast bed, whose top nearly fills its
// cell, meets them. The full bed's run: 151 s wall, one thread, load ~1
// (2026-12-03; 987 s at load ~10 before grain_means reused the overlaps).
TEST(FluidizedBed, FDEM_FB_TEST(VansA_IntersectionPorosityMeetsErgunAndOnset)) {
  Settings exact;
  exact.set_porosity = true;
  exact.porosity = PorosityScheme::intersection;
  check_vans_a("vans_a_intersection", exact, full_tier ? 11 : 10);
}

TEST(FluidizedBed, FDEM_FB_TEST(Simplified_FollowsItsOwnClosedForms)) {
  omp_set_num_threads(1);
  const Prepared p = prepare_tier(FluidModel::simplified, SourceForm::paper, "simplified");
  const BedRun run = run_stages(p, "simplified", kPackedStage, kMovingStage, /*bed_stays_packed=*/true);
  record_stages(run, p);
  EXPECT_EQ(run.outside, 0) << "grains left the column";
  verification::TierValues v(kStudy);
  const Bed& b = p.bed;
  const double w = b.buoyant_weight_per_area();
  // Packed branch over Ergun, and over the simplified model's closed form
  // (u = U in the bed: Ergun's viscous term times eps, inertial times eps^2,
  // packed_bed_check.cpp).
  double worst = 1.0, worst_closed = 1.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double e = s.porosity;
    const double closed = s.height * verification::simplified_gradient(e, s.velocity, b.d, b.rho_f, b.mu);
    const double r = s.drop / ergun_drop(b, e, s.velocity, s.height), rc = s.drop / closed;
    v.add(fmt::format("simplified.packed_over_ergun.u{:.2f}", s.factor), r);
    v.add(fmt::format("simplified.packed_over_closed_form.u{:.2f}", s.factor), rc);
    if (std::abs(r - 1) > std::abs(worst - 1)) worst = r;
    if (std::abs(rc - 1) > std::abs(worst_closed - 1)) worst_closed = rc;
  }
  v.add("simplified.packed_over_ergun.worst", worst);
  v.add("simplified.packed_over_closed_form.worst", worst_closed);
  // Where the closed form at the bed's mean porosity is missed: the same
  // closed form over the cell layers' porosities (the solid the porosity
  // scheme spreads past the bed's ends, the looser floor layer), and the
  // exchange's own drop with the fluid at U everywhere against the drop it
  // gives (the flow avoiding the elements of large beta).
  double worst_layered = 1.0, worst_channel = 1.0, worst_plug = 1.0, worst_fluid = 1.0, worst_seen = 0.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double closed = s.height * verification::simplified_gradient(s.porosity, s.velocity, b.d, b.rho_f, b.mu);
    const double rl = s.drop / s.layered_simplified, rch = s.exchange_drop / s.exchange_plug_drop;
    const double rp = s.exchange_plug_drop / closed;
    v.add(fmt::format("simplified.packed_over_layered_closed_form.u{:.2f}", s.factor), rl);
    v.add(fmt::format("simplified.exchange_drop_over_plug.u{:.2f}", s.factor), rch);
    v.add(fmt::format("simplified.plug_over_closed_form.u{:.2f}", s.factor), rp);
    if (std::abs(rl - 1) > std::abs(worst_layered - 1)) worst_layered = rl;
    if (std::abs(rch - 1) > std::abs(worst_channel - 1)) worst_channel = rch;
    if (std::abs(rp - 1) > std::abs(worst_plug - 1)) worst_plug = rp;
    // Newton on the fluid: Delta p A is the force the exchange hands it.
    const double rf = s.drop / s.exchange_drop;
    v.add(fmt::format("simplified.packed_over_exchange_drop.u{:.2f}", s.factor), rf);
    if (std::abs(rf - 1) > std::abs(worst_fluid - 1)) worst_fluid = rf;
    worst_seen = std::max(worst_seen, s.grain_porosity - s.porosity);
    const double closed_seen = s.height * verification::simplified_gradient(s.grain_porosity, s.velocity, b.d, b.rho_f, b.mu);
    fmt::print("simplified {:.2f} U_mf: dp {:.4f} Pa, closed form {:.4f} (eps {:.4f} from H = 2 <z>), at the grains' mean "
               "element eps {:.4f}: {:.4f}; layered {:.4f}, exchange plug {:.4f}, exchange {:.4f}\n",
               s.factor, s.drop, closed, s.porosity, s.grain_porosity, closed_seen, s.layered_simplified,
               s.exchange_plug_drop, s.exchange_drop);
  }
  v.add("simplified.packed_over_layered_closed_form.worst", worst_layered);
  v.add("simplified.exchange_drop_over_plug.worst", worst_channel);
  v.add("simplified.plug_over_closed_form.worst", worst_plug);
  v.add("simplified.packed_over_exchange_drop.worst", worst_fluid);
  v.add("simplified.grain_porosity_over_bed_porosity_excess", worst_seen);
  const double eps0 = run.stages.front().porosity;
  v.add("simplified.umf_closed_form_over_ergun", simplified_umf(b, eps0) / ergun_umf(b, eps0));
  // Its highest stage against its own onset and against W / A.
  double top_drop = 0.0, top_factor = 0.0;
  for (const Stage& s : run.stages)
    if (s.factor > top_factor) {
      top_factor = s.factor;
      top_drop = s.drop;
    }
  v.add("simplified.top_stage_drop_over_weight", top_drop / w);
  // Its bed never lifts below its onset (closed form above: ~5 U_mf):
  // the largest relative change of H over the stages.
  double h_change = 0.0;
  for (const Stage& s : run.stages) h_change = std::max(h_change, std::abs(s.height / run.stages.front().height - 1.0));
  v.add("simplified.height_change", h_change);
  for (const Stage& s : run.stages)
    v.add(fmt::format("simplified.drop_over_weight.{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor), s.drop / w);
  v.add("simplified.wall_time_s", run.wall_s);
  fmt::print("simplified: packed/Ergun worst {:.4f}, packed/closed form worst {:.4f}, closed-form U_mf = {:.3f} Ergun's, "
             "top stage dp/(W/A) {:.4f}; wall {:.1f} s\n",
             worst, worst_closed, simplified_umf(b, eps0) / ergun_umf(b, eps0), top_drop / w, run.wall_s);
  check_gates(v, 1);
}

}  // namespace
}  // namespace fdem

// Liquid-fluidized bed: pressure drop across a bed of glass beads in water
// against the superficial velocity, the inlet raised in stages from below to
// about 3 U_mf and back, with the volume-averaged fluid (model A, paper Eq.
// 18-19 as Zhou et al. 2010 set II) and the paper's simplified model (Eq.
// 21-22) on the same bed, settled first by the DEM alone.
//
// What is compared (N grains of volume V_p in a column of section A, bed
// height H = 2 <z> from the grains' mean centre height above the floor, bed
// porosity eps = 1 - N V_p / (A H)):
//   packed branch   Delta p against Ergun (1952) for eps and U:
//                   Delta p_E = H [150 (1-eps)^2 mu U / (eps^3 d^2) + 1.75 (1-eps) rho U^2 / (eps^3 d)];
//   plateau         Delta p against the bed's buoyant weight per area
//                   W / A = N V_p (rho_p - rho_f) g / A;
//   U_mf            where the packed branch's fit a U + b U^2 meets the
//                   plateau, against Ergun's U_mf for eps (Ergun = W / A) and
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
// Tiers (FDEM_FLUIDIZED_BED_FULL): fast = fluidized_bed.yaml (400 grains,
// 3 x 3 x 15 cells); full (nightly) = fluidized_bed_full.yaml (2000 grains,
// 5 x 5 x 20 cells), more stages.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "coupling/simulation.hpp"
#include "drag_laws/ergun_wen_yu.hpp"
#include "scene/scene_loader.hpp"
#include "../support/study_io.hpp"
#include "../support/study_results.hpp"

#ifndef FDEM_FLUIDIZED_BED_FULL
#define FDEM_FLUIDIZED_BED_FULL 0
#endif

namespace fdem {
namespace {

constexpr bool full_tier = FDEM_FLUIDIZED_BED_FULL != 0;
constexpr const char* kStudy = "fluidized_bed";
[[maybe_unused]] const ::testing::Environment* const kResults = fdem::verification::register_study_results(kStudy);

const char* scene_file() {
  return full_tier ? FDEM_SOURCE_DIR "/verification/fluidized_bed/fluidized_bed_full.yaml"
                   : FDEM_SOURCE_DIR "/verification/fluidized_bed/fluidized_bed.yaml";
}
const std::string kTier = full_tier ? "full" : "fast";

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

constexpr double kGravity = 9.81;

struct Bed {
  double d = 0, rho_p = 0, rho_f = 0, mu = 0, area = 0;
  double count = 0;
  double solid_volume() const { return count * pi / 6.0 * d * d * d; }
  double buoyant_weight_per_area() const { return solid_volume() * (rho_p - rho_f) * kGravity / area; }
  double porosity(double height) const { return 1.0 - solid_volume() / (area * height); }
};

// Ergun (1952) for the whole bed [Pa].
double ergun_drop(const Bed& b, double eps, double U, double height) {
  return height * (150.0 * (1 - eps) * (1 - eps) * b.mu * U / (eps * eps * eps * b.d * b.d) +
                   1.75 * (1 - eps) * b.rho_f * U * U / (eps * eps * eps * b.d));
}

template <class F>
double bisect(F f, double lo, double hi) {
  double flo = f(lo);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi), fm = f(mid);
    if ((fm > 0) == (flo > 0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

// Ergun's U_mf for porosity eps: Ergun's gradient = (1 - eps)(rho_p - rho_f) g.
double ergun_umf(const Bed& b, double eps) {
  const double w = (1 - eps) * (b.rho_p - b.rho_f) * kGravity;
  return bisect([&](double U) { return ergun_drop(b, eps, U, 1.0) - w; }, 1e-9, 10.0);
}
// Wen & Yu (1966), AIChE Chem. Eng. Prog. Symp. Ser. 62, 100-111.
double wen_yu_umf(const Bed& b) {
  const double ar = b.rho_f * (b.rho_p - b.rho_f) * kGravity * b.d * b.d * b.d / (b.mu * b.mu);
  return (std::sqrt(33.7 * 33.7 + 0.0408 * ar) - 33.7) * b.mu / (b.rho_f * b.d);
}
// The simplified model's onset: beta(eps, U) U = (1 - eps)(rho_p - rho_f) g
// with Ergun's beta (Eq. 12) at the superficial slip: Ergun's gradient with
// its viscous term times eps and its inertial term times eps^2 equals the weight.
double simplified_umf(const Bed& b, double eps) {
  const double w = (1 - eps) * (b.rho_p - b.rho_f) * kGravity;
  return bisect(
      [&](double U) {
        return 150.0 * (1 - eps) * (1 - eps) * b.mu * U / (eps * b.d * b.d) + 1.75 * (1 - eps) * b.rho_f * U * U / b.d -
               w;
      },
      1e-9, 10.0);
}
// Single-grain terminal velocity with the drag law's isolated-sphere Cd
// (Rowe & Henwood, Eq. 14: Wen & Yu at eps = 1).
double terminal_velocity(const Bed& b) {
  return bisect(
      [&](double v) {
        const double re = b.rho_f * v * b.d / b.mu;
        return 0.5 * rowe_henwood_drag_coefficient(re) * b.rho_f * v * v * pi * b.d * b.d / 4.0 -
               pi / 6.0 * b.d * b.d * b.d * (b.rho_p - b.rho_f) * kGravity;
      },
      1e-9, 10.0);
}
// Garside & Al-Dibouni (1977), Ind. Eng. Chem. Process Des. Dev. 16(2), 206-214, Eq. 13.
double garside_al_dibouni_n(double re_t) {
  const double x = 0.1 * std::pow(re_t, 0.9);
  return (5.1 + 2.7 * x) / (1.0 + x);
}
// The drag law's homogeneous expansion (Ergun's branch, eps < 0.8):
// (1 - eps)(rho_p - rho_f) g = Ergun(eps, U).
double ergun_expansion_porosity(const Bed& b, double U) {
  return bisect([&](double e) { return ergun_drop(b, e, U, 1.0) - (1 - e) * (b.rho_p - b.rho_f) * kGravity; }, 0.2,
                0.7999);
}

struct Stage {
  double factor = 0, velocity = 0;
  bool rising = true;
  double drop = 0, drop_sd = 0;      // Delta p [Pa], mean and standard deviation over the window
  double drop_first = 0, drop_second = 0;  // window's first and second halves (steadiness)
  double height = 0;                 // H = 2 <z> [m], mean over the window
  double porosity = 0;
  double layered_ergun = 0;          // Ergun summed over the cell layers' porosities at the stage's end [Pa]
  double resting_weight = 0;         // buoyant weight of the grains touching the floor at the stage's end, per area [Pa]
};

struct BedRun {
  std::string model;
  std::vector<Stage> stages;
  long outside = 0;  // grains outside the mesh at any sample
  double wall_s = 0;
};

// Dry settle: the scene's grains from their random start under gravity, the
// DEM alone, written as a particle CSV the coupled runs load (both fluid
// models start from the same bed).
std::string settle_dry(const Scene& base, const std::string& csv_path, double* max_speed) {
  Scene dry = base;
  dry.effects.fluid = false;
  dry.effects.coupling = CouplingMode::off;
  dry.effects.buoyancy = false;
  dry.time.end_time = kDrySettle;
  Simulation sim(dry);
  while (!sim.finished()) sim.step();
  const Particles& p = sim.particles();
  std::ofstream out(csv_path);
  out << "id,d,rho,x,y,z\n";
  double vmax = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    out << fmt::format("{},{},{},{},{},{}\n", i, p.diameter[i], base.particles.at(0).density, p.x[i], p.y[i], p.z[i]);
    vmax = std::max(vmax, std::sqrt(p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]));
  }
  *max_speed = vmax;
  return csv_path;
}

double mean_height(const Particles& p) {
  double s = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) s += p.z[i];
  return 2.0 * s / static_cast<double>(p.size());
}

// Ergun's drop summed over the mesh's cell layers, each at its own mean
// element porosity (volume-weighted): the bed's axial porosity profile
// (looser at the floor, a partly filled top layer), which H = 2 <z> averages.
double layered_ergun_drop(const Simulation& sim, const Bed& bed, double U) {
  const BoxMesh& mesh = *sim.mesh();
  const int nz = sim.scene().cells[2];
  const double dz = (sim.scene().domain.upper.z() - sim.scene().domain.lower.z()) / nz;
  std::vector<double> fluid(static_cast<std::size_t>(nz), 0.0), volume(static_cast<std::size_t>(nz), 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    double zc = 0.0;
    for (Index a : mesh.element_nodes(e)) zc += mesh.node(a).z() / 4.0;
    const auto layer = static_cast<std::size_t>(std::clamp(static_cast<int>(zc / dz), 0, nz - 1));
    fluid[layer] += mesh.element_volume(e) * sim.porosity()[static_cast<std::size_t>(e)];
    volume[layer] += mesh.element_volume(e);
  }
  double drop = 0.0;
  for (std::size_t k = 0; k < fluid.size(); ++k) drop += ergun_drop(bed, fluid[k] / volume[k], U, dz);
  return drop;
}

// Grains in contact with the floor (overlap > 0) carry their buoyant weight
// to it, not to the fluid (a resting grain still feels some drag: this is an
// upper bound of what the floor takes).
double resting_weight_per_area(const Particles& p, const Bed& bed) {
  int resting = 0;
  for (std::size_t i = 0; i < p.size(); ++i) resting += p.z[i] < 0.5 * p.diameter[i] ? 1 : 0;
  return resting * pi / 6.0 * bed.d * bed.d * bed.d * (bed.rho_p - bed.rho_f) * kGravity / bed.area;
}

BedRun run_stages(const Scene& scene, const Bed& bed, const std::vector<double>& velocities, const std::string& model,
                  bool bed_stays_packed = false) {
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(scene);
  const BoxMesh& mesh = *sim.mesh();
  std::vector<Index> bottom, top;
  const double ztop = scene.domain.upper.z();
  for (Index a = 0; a < mesh.num_nodes(); ++a) {
    if (mesh.node(a).z() < 1e-12) bottom.push_back(a);
    if (mesh.node(a).z() > ztop - 1e-12) top.push_back(a);
  }
  auto plane_mean = [&](const std::vector<Index>& nodes) {
    const auto p = sim.fluid_pressure();
    double s = 0.0;
    for (Index a : nodes) s += p[static_cast<std::size_t>(a)];
    return s / static_cast<double>(nodes.size());
  };
  BedRun run;
  run.model = model;
  bool previous_packed = true;
  for (std::size_t k = 0; k < velocities.size(); ++k) {
    Stage st;
    st.factor = kStageFactors[k];
    st.velocity = velocities[k];
    st.rising = k == 0 || velocities[k] > velocities[k - 1];
    sim.set_inlet_velocity(BoxFace::z_min, Vec3(0, 0, st.velocity));
    const bool packed = st.factor < 1.0;
    // A bed that never lifts (the simplified model below its onset) waits only for the fluid.
    const double length = (packed && previous_packed) || bed_stays_packed ? kPackedStage : kMovingStage;
    previous_packed = packed;
    const long steps = std::lround(length / sim.step_size());
    std::vector<double> drops, heights;
    for (long s = 0; s < steps; ++s) {
      sim.step();
      run.outside = std::max(run.outside, sim.diagnostics().particles_outside_mesh);
      if (2 * s >= steps) {
        drops.push_back(plane_mean(bottom) - plane_mean(top));
        heights.push_back(mean_height(sim.particles()));
      }
    }
    const auto n = static_cast<double>(drops.size());
    double sum = 0, sq = 0, first = 0, second = 0, h = 0;
    for (std::size_t i = 0; i < drops.size(); ++i) {
      sum += drops[i];
      (2 * i < drops.size() ? first : second) += drops[i];
      h += heights[i];
    }
    st.drop = sum / n;
    for (double x : drops) sq += (x - st.drop) * (x - st.drop);
    st.drop_sd = std::sqrt(sq / n);
    st.drop_first = first / std::floor(n / 2 + 0.5);
    st.drop_second = second / (n - std::floor(n / 2 + 0.5));
    st.height = h / n;
    st.porosity = bed.porosity(st.height);
    st.layered_ergun = layered_ergun_drop(sim, bed, st.velocity);
    st.resting_weight = resting_weight_per_area(sim.particles(), bed);
    run.stages.push_back(st);
    fmt::print("  {:10s} U = {:.4e} m/s ({:.2f} U_mf) {:7s} dp = {:9.4f} Pa (sd {:.4f}, halves {:.4f} {:.4f}) "
               "H = {:.3f} mm eps = {:.4f} layered Ergun {:.4f} Pa resting {:.4f} Pa\n",
               model, st.velocity, st.factor, st.rising ? "rising" : "falling", st.drop, st.drop_sd, st.drop_first,
               st.drop_second, st.height * 1e3, st.porosity, st.layered_ergun, st.resting_weight);
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

// Least-squares fit of Delta p = a U + b U^2 (Ergun's form, through the
// origin) to the given stages.
std::pair<double, double> fit_packed(const std::vector<Stage>& s) {
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (const Stage& x : s) {
    const double u = x.velocity, u2 = u * u;
    s11 += u * u;
    s12 += u * u2;
    s22 += u2 * u2;
    r1 += u * x.drop;
    r2 += u2 * x.drop;
  }
  const double det = s11 * s22 - s12 * s12;
  return {(r1 * s22 - r2 * s12) / det, (s11 * r2 - s12 * r1) / det};
}

struct Values {
  std::vector<std::pair<std::string, double>> list;
  void add(const std::string& quantity, double v) {
    const std::string id = fmt::format("{}.{}.{}", kStudy, kTier, quantity);
    list.emplace_back(id, v);
    fdem::verification::record_value(id, v);
  }
};

void record_stages(const BedRun& run, const Bed& bed) {
  for (std::size_t k = 0; k < run.stages.size(); ++k) {
    const Stage& s = run.stages[k];
    fdem::verification::record_series_row(
        kStudy, "stages.csv", fmt::format("{}_{}_{:02d}", kTier, run.model, k),
        {"tier", "model", "stage", "direction", "superficial_velocity_m_s", "u_over_umf_ergun", "pressure_drop_pa",
         "pressure_drop_sd_pa", "buoyant_weight_per_area_pa", "bed_height_m", "bed_porosity"},
        {kTier, run.model, fmt::format("{}", k), s.rising ? "rising" : "falling", fmt::format("{}", s.velocity),
         fmt::format("{}", s.factor), fmt::format("{}", s.drop), fmt::format("{}", s.drop_sd),
         fmt::format("{}", bed.buoyant_weight_per_area()), fmt::format("{}", s.height), fmt::format("{}", s.porosity)});
  }
}

struct Prepared {
  Scene scene;
  Bed bed;
  double settled_height = 0, settled_porosity = 0, umf_ergun = 0, settle_speed = 0;
  std::vector<double> velocities;
};

Prepared prepare(FluidModel model, SourceForm form, const std::string& tag) {
  Prepared p;
  const Scene base = load_scene(scene_file());
  p.bed.d = base.particles.at(0).size.diameter;
  p.bed.rho_p = base.particles.at(0).density;
  p.bed.rho_f = base.fluid.density;
  p.bed.mu = base.fluid.viscosity;
  p.bed.count = base.particles.at(0).count;
  p.bed.area = (base.domain.upper.x() - base.domain.lower.x()) * (base.domain.upper.y() - base.domain.lower.y());
  const std::string dir = study::results_dir(kStudy);
  std::filesystem::create_directories(dir);
  const std::string csv = settle_dry(base, fmt::format("{}/settled_bed_{}_{}.csv", dir, kTier, tag), &p.settle_speed);
  p.scene = base;
  ParticleSet& set = p.scene.particles.at(0);
  set.placement = PlacementKind::csv;
  set.csv_file = csv;
  p.scene.fluid.model = model;
  p.scene.coupling.source_form = form;
  p.scene.coupling.exchange = MomentumExchange::semi_implicit;
  {
    Scene probe = p.scene;
    probe.effects.fluid = false;
    probe.effects.coupling = CouplingMode::off;
    const Simulation s(probe);
    p.settled_height = mean_height(s.particles());
  }
  p.settled_porosity = p.bed.porosity(p.settled_height);
  p.umf_ergun = ergun_umf(p.bed, p.settled_porosity);
  for (double f : kStageFactors) p.velocities.push_back(f * p.umf_ergun);
  fmt::print("Fluidized bed ({} tier, {}): {} grains of d = {} mm, settled H = {:.3f} mm, eps = {:.4f}, "
             "Ergun U_mf = {:.4e} m/s, Wen-Yu U_mf = {:.4e} m/s, W/A = {:.4f} Pa (dry settle: max speed {:.2e} m/s)\n",
             kTier, tag, p.bed.count, p.bed.d * 1e3, p.settled_height * 1e3, p.settled_porosity, p.umf_ergun,
             wen_yu_umf(p.bed), p.bed.buoyant_weight_per_area(), p.settle_speed);
  return p;
}

std::vector<Stage> select(const std::vector<Stage>& s, bool rising, bool packed) {
  std::vector<Stage> out;
  for (const Stage& x : s)
    if (x.rising == rising && (x.factor < 1.0) == packed) out.push_back(x);
  return out;
}

void check_gates(const Values& v, int minimum) {
  int gated = 0;
  for (const std::string& failure : study::gate_failures(study::read_reference(kStudy), v.list, &gated))
    ADD_FAILURE() << failure;
  EXPECT_GE(gated, minimum) << "reference_data/" << kStudy << ".csv: gated rows not measured";
}

#if FDEM_FLUIDIZED_BED_FULL
#define FDEM_FB_TEST(name) FullTier_##name
#else
#define FDEM_FB_TEST(name) FastTier_##name
#endif

TEST(FluidizedBed, FDEM_FB_TEST(VansA_ErgunBranchPlateauAndOnset)) {
  omp_set_num_threads(1);
  const Prepared p = prepare(FluidModel::vans_a, SourceForm::conservative, "vans_a");
  EXPECT_LT(p.settle_speed, 1e-3) << "the dry settle did not come to rest";
  const BedRun run = run_stages(p.scene, p.bed, p.velocities, "vans_a");
  record_stages(run, p.bed);
  EXPECT_EQ(run.outside, 0) << "grains left the column";
  Values v;
  const Bed& b = p.bed;
  const double w = b.buoyant_weight_per_area();
  // Packed branch (rising): Delta p over Ergun for each stage's eps and U; the worst.
  double worst = 1.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double r = s.drop / ergun_drop(b, s.porosity, s.velocity, s.height);
    v.add(fmt::format("vans_a.packed_over_ergun.u{:.2f}", s.factor), r);
    if (std::abs(r - 1) > std::abs(worst - 1)) worst = r;
  }
  v.add("vans_a.packed_over_ergun.worst", worst);
  // The same against Ergun over the cell layers' porosities, and the
  // branch's shape: the ratio's spread over the packed stages (Ergun's
  // viscous-to-inertial mix with U reproduced if the ratio is constant).
  double worst_layered = 1.0, lo = 1e300, hi = 0.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double r = s.drop / s.layered_ergun, re = s.drop / ergun_drop(b, s.porosity, s.velocity, s.height);
    v.add(fmt::format("vans_a.packed_over_layered_ergun.u{:.2f}", s.factor), r);
    if (std::abs(r - 1) > std::abs(worst_layered - 1)) worst_layered = r;
    lo = std::min(lo, re);
    hi = std::max(hi, re);
  }
  v.add("vans_a.packed_over_layered_ergun.worst", worst_layered);
  v.add("vans_a.packed_ratio_spread", hi / lo - 1.0);
  // Plateau: fluidized stages (rising and falling) over W / A; the worst.
  double worst_plateau = 1.0, plateau_sum = 0.0;
  int plateau_n = 0;
  for (const Stage& s : run.stages) {
    if (s.factor < 1.0) continue;
    const double r = s.drop / w;
    v.add(fmt::format("vans_a.plateau_over_weight.{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor), r);
    if (std::abs(r - 1) > std::abs(worst_plateau - 1)) worst_plateau = r;
    plateau_sum += s.drop;
    ++plateau_n;
  }
  v.add("vans_a.plateau_over_weight.worst", worst_plateau);
  // The fluid carries what the floor does not: Delta p plus the resting
  // grains' weight, in the fully fluidized stages (>= 2 U_mf).
  double worst_carried = 1.0, drop_top = 0.0, drop_second = 0.0, top = 0.0, second = 0.0;
  for (const Stage& s : run.stages) {
    if (s.factor < 2.0) continue;
    const double r = (s.drop + s.resting_weight) / w;
    v.add(fmt::format("vans_a.plateau_plus_resting_over_weight.{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor), r);
    if (std::abs(r - 1) > std::abs(worst_carried - 1)) worst_carried = r;
    v.add(fmt::format("vans_a.resting_weight_over_weight.{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor),
          s.resting_weight / w);
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
  v.add("vans_a.plateau_plus_resting_over_weight.worst", worst_carried);
  v.add("vans_a.plateau_flatness", std::abs(drop_top / drop_second - 1.0));
  const double plateau = plateau_sum / plateau_n;
  // U_mf from the curve: the rising packed branch's Ergun-form fit meets the plateau.
  const auto [a, bq] = fit_packed(select(run.stages, true, true));
  const double umf_curve = (-a + std::sqrt(a * a + 4 * bq * plateau)) / (2 * bq);
  const Stage& first = run.stages.front();
  const double umf_pred = ergun_umf(b, first.porosity);
  v.add("vans_a.umf_curve_over_ergun", umf_curve / umf_pred);
  v.add("vans_a.umf_curve_over_wen_yu", umf_curve / wen_yu_umf(b));
  v.add("vans_a.umf_curve_m_s", umf_curve);
  v.add("vans_a.packed_porosity", first.porosity);
  // Falling branch: its own U_mf and the packing it leaves (hysteresis).
  const auto falling_packed = select(run.stages, false, true);
  if (falling_packed.size() >= 2) {
    const auto [af, bf] = fit_packed(falling_packed);
    v.add("vans_a.umf_falling_over_rising", (-af + std::sqrt(af * af + 4 * bf * plateau)) / (2 * bf) / umf_curve);
  }
  // Bed height in the fluidized stages against Richardson-Zaki (Garside &
  // Al-Dibouni's n, U_i = U_t: the model has no wall drag) and against the
  // drag law's own homogeneous expansion.
  const double ut = terminal_velocity(b), re_t = b.rho_f * ut * b.d / b.mu, n = garside_al_dibouni_n(re_t);
  v.add("vans_a.terminal_velocity_m_s", ut);
  v.add("vans_a.richardson_zaki_n", n);
  double worst_rz = 1.0, worst_model = 1.0;
  for (const Stage& s : run.stages) {
    if (s.factor < 1.0) continue;
    const double h_rz = b.solid_volume() / (b.area * (1.0 - std::pow(s.velocity / ut, 1.0 / n)));
    const double h_model = b.solid_volume() / (b.area * (1.0 - ergun_expansion_porosity(b, s.velocity)));
    const std::string key = fmt::format("{}.u{:.2f}", s.rising ? "rising" : "falling", s.factor);
    v.add("vans_a.height_over_richardson_zaki." + key, s.height / h_rz);
    v.add("vans_a.height_over_ergun_expansion." + key, s.height / h_model);
    if (std::abs(s.height / h_rz - 1) > std::abs(worst_rz - 1)) worst_rz = s.height / h_rz;
    if (std::abs(s.height / h_model - 1) > std::abs(worst_model - 1)) worst_model = s.height / h_model;
  }
  v.add("vans_a.height_over_richardson_zaki.worst", worst_rz);
  v.add("vans_a.height_over_ergun_expansion.worst", worst_model);
  // Hysteresis: the same U on both branches.
  for (const Stage& up : run.stages) {
    if (!up.rising) continue;
    for (const Stage& down : run.stages)
      if (!down.rising && std::abs(down.factor - up.factor) < 1e-9) {
        v.add(fmt::format("vans_a.hysteresis_drop.u{:.2f}", up.factor), down.drop / up.drop - 1.0);
        v.add(fmt::format("vans_a.hysteresis_height.u{:.2f}", up.factor), down.height / up.height - 1.0);
      }
  }
  v.add("vans_a.wall_time_s", run.wall_s);
  fmt::print("vans_a: packed/Ergun worst {:.4f}, plateau/(W/A) worst {:.4f}, U_mf curve {:.4e} m/s = {:.4f} Ergun, "
             "{:.4f} Wen-Yu; H/RZ worst {:.4f}, H/Ergun-expansion worst {:.4f}; wall {:.1f} s\n",
             worst, worst_plateau, umf_curve, umf_curve / umf_pred, umf_curve / wen_yu_umf(b), worst_rz, worst_model,
             run.wall_s);
  check_gates(v, 3);
}

TEST(FluidizedBed, FDEM_FB_TEST(Simplified_FollowsItsOwnClosedForms)) {
  omp_set_num_threads(1);
  const Prepared p = prepare(FluidModel::simplified, SourceForm::paper, "simplified");
  const BedRun run = run_stages(p.scene, p.bed, p.velocities, "simplified", /*bed_stays_packed=*/true);
  record_stages(run, p.bed);
  EXPECT_EQ(run.outside, 0) << "grains left the column";
  Values v;
  const Bed& b = p.bed;
  const double w = b.buoyant_weight_per_area();
  // Packed branch over Ergun, and over the simplified model's closed form
  // (u = U in the bed: Ergun's viscous term times eps, inertial times eps^2,
  // packed_bed_check.cpp).
  double worst = 1.0, worst_closed = 1.0;
  for (const Stage& s : select(run.stages, true, true)) {
    const double e = s.porosity;
    const double closed = s.height * (150.0 * (1 - e) * (1 - e) * b.mu * s.velocity / (e * e * b.d * b.d) +
                                      1.75 * (1 - e) * b.rho_f * s.velocity * s.velocity / (e * b.d));
    const double r = s.drop / ergun_drop(b, e, s.velocity, s.height), rc = s.drop / closed;
    v.add(fmt::format("simplified.packed_over_ergun.u{:.2f}", s.factor), r);
    v.add(fmt::format("simplified.packed_over_closed_form.u{:.2f}", s.factor), rc);
    if (std::abs(r - 1) > std::abs(worst - 1)) worst = r;
    if (std::abs(rc - 1) > std::abs(worst_closed - 1)) worst_closed = rc;
  }
  v.add("simplified.packed_over_ergun.worst", worst);
  v.add("simplified.packed_over_closed_form.worst", worst_closed);
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

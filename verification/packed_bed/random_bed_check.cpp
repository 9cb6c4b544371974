// Random packed bed: spheres poured into a duct and settled by our DEM
// (random_bed.yaml), then held fixed while water flows through them; the
// pressure gradient against Ergun (1952) for the superficial velocity at the
// bed's own porosity, with the volume-averaged models and the simplified one
// beside them (packed_bed_run.hpp says what is measured; README.md the
// results). Beside the lattice bed (packed_bed_check.cpp), this is the bed
// whose porosity is not known in closed form and varies from element to
// element, as in a real bed: the porosity comes from the exact sphere-
// tetrahedron volumes (coupling.porosity: intersection).
//
// Tiers (FDEM_FULL_TIER): fast = random_bed.yaml (720 grains, 6 x 6 mm
// duct, 3 mm cells); full (nightly) = random_bed_full.yaml (larger bed).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <omp.h>

#include "dem/dem_engine.hpp"
#include "io/atomic_file.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"
#include "../support/study_results.hpp"
#include "../support/study_tier.hpp"
#include "packed_bed_run.hpp"

namespace fdem {
namespace {

using verification::full_tier;
[[maybe_unused]] const ::testing::Environment* const kResults =
    fdem::verification::register_study_results("packed_bed");
using fdem::verification::record_value;

const char* scene_file() {
  return full_tier ? FDEM_SOURCE_DIR "/verification/packed_bed/random_bed_full.yaml"
                   : FDEM_SOURCE_DIR "/verification/packed_bed/random_bed.yaml";
}

// Pour time: the grains fall at most the duct's height (36 mm fast: 0.09 s
// in free fall; 56 mm full: 0.11 s) and their rebounds die within ~0.1 s at
// restitution 0.3; the taller full bed takes longer to come to rest (at
// 0.25 s its grains still moved at 1.02 mm/s rms).
constexpr double kSettle_s = full_tier ? 0.4 : 0.25;
// Clear fluid below the bed (3 cells): the inlet's uniform profile relaxes
// before the bed; and above it up to the outlet.
constexpr double kClearCells = 3.0;

struct SettledBed {
  Scene flow;               // the flow scene (csv placement of the settled grains)
  double bottom = 0.0, top = 0.0;  // bed extent in the flow scene [m]
  double kinetic_energy_j = 0.0, max_overlap_over_d = 0.0;
  std::size_t grains = 0;
  double settle_wall_s = 0.0;
};

SettledBed settle(const Scene& base) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene dry = base;
  dry.effects.fluid = false;
  dry.effects.coupling = CouplingMode::off;
  dry.time.fluid_step = 0.0;
  dry.time.subcycles = 0;
  DemEngine dem(generate_particles(dry), dry);
  dem.run(static_cast<std::size_t>(std::lround(kSettle_s / dry.time.dem_step)));
  const Particles& p = dem.particles();
  SettledBed out;
  out.kinetic_energy_j = dem.diagnostics().kinetic_energy_j;
  out.max_overlap_over_d = dem.diagnostics().max_overlap_over_diameter;
  out.grains = p.size();
  const double h = base.domain.upper.z() / base.cells[2];
  const double lift = kClearCells * h;
  double top = 0.0;
  std::string csv = "id,d,rho,x,y,z\n";  // scene/particle_csv.hpp's format
  for (std::size_t i = 0; i < p.size(); ++i) {
    top = std::max(top, p.z[i] + 0.5 * p.diameter[i]);
    csv += fmt::format("{},{},{},{},{},{}\n", i + 1, p.diameter[i], base.particles.at(0).density, p.x[i], p.y[i],
                       p.z[i] + lift);
  }
  const std::string path = fmt::format("{}/verification/packed_bed/random_bed_{}.csv", FDEM_BINARY_DIR,
                                       verification::tier_name);
  write_file_atomically(path, csv);
  Scene flow = base;
  flow.effects.gravity = false;
  flow.effects.normal_contact = false;
  flow.effects.tangential_contact = false;
  flow.effects.rotation = false;
  flow.particles.at(0).placement = PlacementKind::csv;
  flow.particles.at(0).csv_file = path;
  const int cells_z = static_cast<int>(std::ceil((top + lift) / h - 1e-9) + kClearCells);
  flow.cells[2] = cells_z;
  flow.domain.upper.z() = cells_z * h;
  out.flow = flow;
  out.bottom = lift;
  out.top = top + lift;
  out.settle_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

const double kReynolds[] = {0.1, 3.0, 50.0};  // Re_p = rho U d / mu

#if FDEM_FULL_TIER
#define FDEM_RANDOM_BED_TEST FullTier_VansMatchesErgunAtTheBedsPorosity
#else
#define FDEM_RANDOM_BED_TEST FastTier_VansMatchesErgunAtTheBedsPorosity
#endif

TEST(RandomPackedBed, FDEM_RANDOM_BED_TEST) {
  omp_set_num_threads(1);
  const Scene base = load_scene(scene_file());
  const SettledBed bed = settle(base);
  const double d = base.particles.at(0).size.diameter, rho = base.fluid.density, mu = base.fluid.viscosity;
  const double h = base.domain.upper.z() / base.cells[2];
  // Interior band: one cell in from the bed's bottom, and from its top less
  // the loose top layer (two diameters: the pour leaves a rough surface).
  const double z0 = bed.bottom + h, z1 = bed.top - 2.0 * d - h;
  const std::string tier = verification::tier_name;
  fmt::print("Random packed bed ({} tier): {} grains settled in {:.2f} s wall (kinetic energy {:.2e} J, "
             "max overlap {:.2e} d), bed {:.2f}-{:.2f} mm, band {:.2f}-{:.2f} mm\n",
             tier, bed.grains, bed.settle_wall_s, bed.kinetic_energy_j, bed.max_overlap_over_d, bed.bottom * 1e3,
             bed.top * 1e3, z0 * 1e3, z1 * 1e3);
  ASSERT_GT(z1 - z0, 2.0 * h) << "the bed is too short for an interior band";
  // Settled: no grain moving faster than ~1 mm/s (kinetic energy below
  // N m (1e-3)^2 / 2); overlaps small against d: Kn was chosen for 0.2 % under
  // the bed's weight, the DEM's largest overlap (measured 1.2 % fast) stays
  // below 2 %: the lens two grains share at 2 % overlap is under 0.1 % of a
  // grain's volume, counted twice by the porosity (eps off by < 1e-3 even
  // with every grain so pressed).
  EXPECT_LT(bed.kinetic_energy_j, 0.5 * static_cast<double>(bed.grains) * 1.31e-6 * 1e-6);
  EXPECT_LT(bed.max_overlap_over_d, 0.02);
  double vans_a_ratio = 0.0;  // the same Re_p's model-A run (kModels lists vans_a before vans_b)
  packed_bed::run_models(bed.flow, kReynolds, z0, z1, [&](const packed_bed::ModelRun& mr) {
      const packed_bed::ModelSpec& m = *mr.model;
      const packed_bed::BedRun& r = mr.run;
      const double re = mr.reynolds, U = mr.superficial_velocity, ergun = mr.ergun, ratio = mr.ratio;
      record_value(fmt::format("packed_bed.random_{}.{}.re{}.gradient_over_ergun", tier, m.name, re), ratio);
      if (m.model == FluidModel::simplified && re == kReynolds[0])
        record_value(fmt::format("packed_bed.random_{}.porosity", tier), r.porosity);
      // Steady: the last step changed -dp/dz by < 5e-4 of it (measured at
      // most 1.1e-4, simplified at Re_p 0.1; the change decays step by step,
      // so what is left moves the ratio by well under a 5 % gate).
      EXPECT_LT(r.gradient_change, 5e-4) << m.name << " Re " << re;
      // A poured bed of monodisperse spheres with friction: between random
      // close (0.36) and random loose packing (0.44), plus the duct walls'
      // looser layer (D / d = 6): 0.36-0.48.
      EXPECT_GT(r.porosity, 0.36);
      EXPECT_LT(r.porosity, 0.48);
      if (m.model == FluidModel::simplified) {
        const double expected = packed_bed::simplified_gradient(r.porosity, U, d, rho, mu) / ergun;
        record_value(fmt::format("packed_bed.random_{}.simplified.re{}.closed_form_ratio", tier, re), expected);
      } else if (m.model == FluidModel::vans_a) {
        vans_a_ratio = ratio;
        EXPECT_NEAR(ratio, 1.0, 0.05) << m.name << " Re " << re;  // the project's target
      } else {
        // Model B divides each grain's drag by eps_e, the porosity of the
        // element holding its centre. On small elements (cell / d 2-3) eps_e
        // varies from element to element and is lowest where the centres
        // crowd, so the grains' mean 1 / eps_e exceeds 1 / eps of the band:
        // F = eps <1 / eps_e> = 1.078 on the full bed (cell / d 2), 1.035 on
        // the fast one (cell / d 3), measured from the field, no flow. That
        // factor is model B's whole excess over model A: vans_b / (vans_a F)
        // measured 0.997-1.020 (both tiers, README), gated 3 %; and model B
        // meets Ergun's 5 % once F is taken out (measured 1.026-1.049 full,
        // 0.984-1.002 fast). Raw vans_b / Ergun, 1.107-1.131 full, misses the
        // 5 % target at cell / d 2: a known deviation (README).
        const double factor = r.grain_inverse_porosity;
        record_value(fmt::format("packed_bed.random_{}.grain_inverse_porosity", tier), factor);
        // Tabulated: the same factor with eps over each grain's own volume
        // (1.039 full, 1.022 fast): model B with its 1 / eps taken so read
        // vans_a times it to 0.8 % (tried 2026-12-03, not adopted: README).
        record_value(fmt::format("packed_bed.random_{}.grain_volume_inverse_porosity", tier),
                     r.grain_volume_inverse_porosity);
        record_value(fmt::format("packed_bed.random_{}.vans_b.re{}.over_vans_a_times_factor", tier, re),
                     ratio / (vans_a_ratio * factor));
        EXPECT_NEAR(ratio / (vans_a_ratio * factor), 1.0, 0.03) << m.name << " Re " << re;
        EXPECT_NEAR(ratio / factor, 1.0, 0.05) << m.name << " Re " << re;  // the project's target, F taken out
      }
  });
}

}  // namespace
}  // namespace fdem

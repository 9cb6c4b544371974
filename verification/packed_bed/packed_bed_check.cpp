// Fixed packed bed: the pressure gradient through a bed of fixed spheres
// against Ergun (1952) for the superficial velocity, with the volume-averaged
// fluid models (paper Eq. 18-19; fluid.model vans_a / vans_b) and the paper's
// simplified model (Eq. 21-22) beside them.
//
//   Ergun:  -dp/dz = 150 (1-eps)^2 mu U / (eps^3 d^2) + 1.75 (1-eps) rho U^2 / (eps^3 d)
//
// The drag law's beta (Eq. 12) is Ergun's with the interstitial velocity
// u = U / eps: beta u / eps = Ergun. What each model makes of it, in the bed
// interior (uniform eps, u along z, fixed grains):
//   model A  (conservative source: the fluid gets -sum f / V_e = -beta u):
//            eps dp/dz = -beta u, and div(eps u) = 0 makes u = U / eps: Ergun;
//   model B  (grains f_d / eps, the fluid exactly minus it): dp/dz = -beta u / eps, u = U / eps: Ergun;
//   simplified (paper source): div u = 0 keeps u = U inside the bed, so
//            -dp/dz = beta(U) U / eps: Ergun's viscous term times eps and its
//            inertial term times eps^2 (closed form, gated at 1 %).
// dp/dz is the least-squares slope of the nodal pressure over the bed's
// interior (two cells in from each end: the bed's faces are smeared over a
// cell by the porosity scheme); eps is the element porosity there.
//
// Tiers (FDEM_FULL_TIER): fast = packed_bed.yaml (2 x 2 x 16 cells of
// 3 mm, 1080 grains); full (nightly) = packed_bed_full.yaml (4 x 4 x 30 cells
// of 2 mm, 2560 grains, a bed 40 diameters long).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "coupling/simulation.hpp"
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
using packed_bed::ModelRun;
using packed_bed::simplified_gradient;

const char* scene_file() {
  return full_tier ? FDEM_SOURCE_DIR "/verification/packed_bed/packed_bed_full.yaml"
                   : FDEM_SOURCE_DIR "/verification/packed_bed/packed_bed.yaml";
}

// Superficial velocities for Re_p = rho U d / mu = 0.1, 3, 50 (water, d = 1 mm).
const double kReynolds[] = {0.1, 3.0, 50.0};

#if FDEM_FULL_TIER
#define FDEM_PACKED_BED_TEST FullTier_VansMatchesErgunSimplifiedFollowsItsClosedForm
#else
#define FDEM_PACKED_BED_TEST FastTier_VansMatchesErgunSimplifiedFollowsItsClosedForm
#endif

TEST(PackedBed, FDEM_PACKED_BED_TEST) {
  omp_set_num_threads(1);  // a small mesh: an OpenMP team costs more than it saves on the shared machine
  const Scene base = load_scene(scene_file());
  const double d = base.particles.at(0).size.diameter, rho = base.fluid.density, mu = base.fluid.viscosity;
  const std::string tier = verification::tier_name;
  fmt::print("Packed bed ({} tier), d = {} mm: -dp/dz over Ergun's for the superficial velocity\n", tier, d * 1e3);
  const ParticleSet& bed = base.particles.at(0);
  const double cell = base.domain.upper.z() / base.cells[2];
  packed_bed::run_models(base, kReynolds, bed.region.lower.z() + 2 * cell, bed.region.upper.z() - 2 * cell,
                         [&](const ModelRun& mr) {
      const packed_bed::ModelSpec& m = *mr.model;
      const packed_bed::BedRun& r = mr.run;
      const double re = mr.reynolds, U = mr.superficial_velocity, ergun = mr.ergun, ratio = mr.ratio;
      const double speed_ratio = r.interstitial / (U / r.porosity);
      const std::string id = fmt::format("packed_bed.{}.re{}.gradient_over_ergun", m.name, re);
      record_value(id, ratio);
      fdem::verification::record_series_row(
          "packed_bed", "gradient.csv", fmt::format("{}_{:06.1f}_{}", tier, re, m.name),
          {"tier", "re_p", "superficial_velocity_m_s", "porosity", "model", "gradient_pa_m", "ergun_pa_m",
           "ratio", "interstitial_over_u_eps"},
          {tier, fmt::format("{}", re), fmt::format("{}", U), fmt::format("{}", r.porosity), m.name,
           fmt::format("{}", r.gradient), fmt::format("{}", ergun), fmt::format("{}", ratio),
           fmt::format("{}", speed_ratio)});
      // Steady: the last step changed the gradient by < 1e-4 of it (a 1e-4
      // drift cannot move a 5 % gate).
      EXPECT_LT(r.gradient_change, 1e-4) << m.name << " Re " << re;
      // The lattice repeats with the mesh (3 mm = 3 spacings), so the
      // shape-function scheme (solid volume conserved) gives the interior
      // band exactly the lattice's porosity 1 - pi/6, to round-off, as its
      // volume mean; the central and corner tetrahedra differ (spread reported).
      EXPECT_NEAR(r.porosity, 1.0 - pi / 6.0, 1e-9);
      if (m.model == FluidModel::simplified && re == kReynolds[0]) record_value("packed_bed.porosity", r.porosity);
      record_value(fmt::format("packed_bed.{}.re{}.porosity_spread", m.name, re), r.porosity_spread);
      if (m.model == FluidModel::simplified) {
        // Not Ergun: its own closed form (header). What separates them is
        // common to every model: the grains' elements differ in porosity
        // (central and corner tetrahedra, spread recorded) and the drag is
        // convex in eps, so the mean drag exceeds the drag at the mean eps;
        // measured 0.1-0.3 % at cell / d = 3 (fast), 1.2 % at cell / d = 2
        // (full; model A 2.8 %, model B 1.2 % above Ergun there): 3 %.
        const double expected = simplified_gradient(r.porosity, U, d, rho, mu) / ergun;
        record_value(fmt::format("packed_bed.simplified.re{}.closed_form_ratio", re), expected);
        EXPECT_NEAR(ratio / expected, 1.0, 0.03) << "Re " << re;
        EXPECT_NEAR(speed_ratio, r.porosity, 0.02 * r.porosity);  // u = U: the fluid does not speed up
      } else {
        // The project's target: 5 % of Ergun for the superficial velocity.
        EXPECT_NEAR(ratio, 1.0, 0.05) << m.name << " Re " << re;
        // The fluid speeds up to U / eps in the bed: div(eps u) = 0 holds the
        // flux eps u, and the volume mean of u departs from U / eps_bed only
        // by the correlation of u with the tetrahedra's alternating porosity
        // (spread 0.017), measured up to 1.4 % at Re_p 50: 2 %.
        EXPECT_NEAR(speed_ratio, 1.0, 0.02) << m.name;
      }
  });
}

}  // namespace
}  // namespace fdem

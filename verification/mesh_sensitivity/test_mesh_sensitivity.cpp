// Mesh-size sensitivity (paper Sect. 4.2, Table 2): gates and result files.
//
// One process runs the tier's set of cases once (main, below), writes the
// result files the report reads, then checks the gates on those numbers:
//   --tier=fast  (ctest label verification) 0.45 s of fall, the paper's
//                centre scheme at every ratio and start, the shape-function
//                and diffused schemes offset at ratio 3.
//   --tier=full  (ctest label nightly) the paper's 1 s, the three schemes at
//                every ratio and start, and a wider column to show the walls are far.
// Reference numbers and tolerances come from reference_data/mesh_sensitivity.csv.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "mesh_sensitivity_case.hpp"
#include "reference/settling_reference.hpp"
#include "scene/scene_loader.hpp"
#include "study_io.hpp"
#include "study_main.hpp"

namespace fdem::mesh_sensitivity {
namespace {

const std::vector<double> kRatios{3, 4, 5, 7, 10};
const std::string kStudy = "mesh_sensitivity";

std::string ratio_label(double r) { return fmt::format("r{:g}", r); }

struct StudyRun {
  std::string tier;
  std::vector<CaseResult> cases;
  std::optional<CaseResult> wide;  // full tier: offset, centre scheme, ratio 3, 7 cells wide
  double wall_time_s = 0.0;

  const CaseResult& get(double ratio, Start start, PorosityScheme scheme) const {
    for (const CaseResult& c : cases)
      if (c.spec.ratio == ratio && c.spec.start == start && c.spec.scheme == scheme) return c;
    throw std::runtime_error(fmt::format("case r{} {} {} was not run", ratio, start_name(start), scheme_name(scheme)));
  }
  bool has(double ratio, Start start, PorosityScheme scheme) const {
    for (const CaseResult& c : cases)
      if (c.spec.ratio == ratio && c.spec.start == start && c.spec.scheme == scheme) return true;
    return false;
  }
};

// Set once in main before the tests run; read-only afterwards.
const StudyRun* g_run = nullptr;
const StudyRun& run() { return *g_run; }

StudyRun run_study(const std::string& tier) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene base = load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/mesh_sensitivity/mesh_sensitivity.yaml");
  const bool full = tier == "full";
  const double end_time = full ? 1.0 : 0.45;  // fast: >= 2 porosity periods (2 h / v_t = 0.13 s at ratio 10) after 0.15 s
  StudyRun out;
  out.tier = tier;
  std::vector<CaseSpec> specs;
  for (PorosityScheme scheme : {PorosityScheme::centre, PorosityScheme::shape_function, PorosityScheme::diffused})
    for (double r : kRatios)
      for (Start start : {Start::offset, Start::centred}) {
        const bool wanted = scheme == PorosityScheme::centre || full || (r == 3.0 && start == Start::offset);
        if (wanted) specs.push_back(CaseSpec{r, start, scheme, end_time, 5});
      }
  for (const CaseSpec& spec : specs) {
    out.cases.push_back(run_case(base, spec));
    const CaseResult& c = out.cases.back();
    std::printf(
        "r %4g %-7s %-13s vt %.5f m/s  porosity amp %7.4f %% (mean %.5f)  velocity amp %7.4f %%  drift %.4f cells  "
        "%6.2f s wall %6.2f s CPU\n",
        spec.ratio, start_name(spec.start).c_str(), scheme_name(spec.scheme).c_str(), c.vt_mps, c.porosity_amp_pct,
        c.porosity_mean, c.velocity_amp_pct, c.lateral_drift_over_cell, c.wall_time_s, c.cpu_time_s);
    std::fflush(stdout);
  }
  if (full) {
    out.wide = run_case(base, CaseSpec{3.0, Start::offset, PorosityScheme::centre, end_time, 7});
    std::printf("r 3 offset centre, 7 cells wide: vt %.5f m/s velocity amp %.4f %%\n", out.wide->vt_mps,
                out.wide->velocity_amp_pct);
  }
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void write_results(const StudyRun& r) {
  const auto ref = study::read_reference(kStudy);
  const std::string dir = study::results_dir(kStudy);
  std::filesystem::create_directories(dir);
  study::clear_dir(dir);
  std::vector<std::vector<double>> amp_rows;
  std::vector<std::string> amp_text;
  for (const CaseResult& c : r.cases) {
    std::vector<std::vector<double>> rows;
    for (std::size_t i = 0; i < c.t_s.size(); ++i) rows.push_back({c.t_s[i], c.porosity[i], c.v_mps[i]});
    const std::string name = fmt::format("series_{}_{}_{}.csv", ratio_label(c.spec.ratio), start_name(c.spec.start),
                                         scheme_name(c.spec.scheme));
    study::write_numeric_csv(dir + "/" + name, {"t_s", "porosity", "v_mps"}, rows,
                             {fmt::format("mesh sensitivity, ratio {:g}, {} start, {} porosity scheme, tier {}",
                                          c.spec.ratio, start_name(c.spec.start), scheme_name(c.spec.scheme), r.tier),
                              "porosity of the element holding the grain; v = settling speed, downward positive"});
    // amplitudes.csv: the paper's and the closed-form columns on offset rows only.
    std::string paper_por, paper_vel, closed;
    if (c.spec.start == Start::offset) {
      const std::string rl = ratio_label(c.spec.ratio);
      paper_por = fmt::format("{}", study::reference(ref, "mesh_sensitivity.porosity_amp_paper." + rl).value);
      paper_vel = fmt::format("{}", study::reference(ref, "mesh_sensitivity.velocity_amp_paper." + rl).value);
      closed = fmt::format("{}", study::reference(ref, "mesh_sensitivity.porosity_amp_closed." + rl).value);
    }
    amp_text.push_back(fmt::format("{:g},{},{},{},{},{},{},{},{},{}", c.spec.ratio, start_name(c.spec.start),
                                   scheme_name(c.spec.scheme), c.porosity_amp_pct, c.velocity_amp_pct, c.vt_mps,
                                   c.wall_time_s, paper_por, paper_vel, closed));
  }
  std::string amp = fmt::format("# mesh sensitivity amplitudes, tier {}; peak-to-peak over the mean on t >= {} s, %\n",
                                r.tier, kPlateauStart_s);
  amp += "ratio,start,scheme,porosity_amp_pct,velocity_amp_pct,vt_mps,wall_time_s,porosity_amp_paper_pct,"
         "velocity_amp_paper_pct,porosity_amp_closed_form_pct\n";
  for (const std::string& line : amp_text) amp += line + "\n";
  write_file_atomically(dir + "/amplitudes.csv", amp);

  std::vector<std::pair<std::string, double>> values;
  for (double ratio : kRatios) {
    const std::string rl = ratio_label(ratio);
    const CaseResult& off = r.get(ratio, Start::offset, PorosityScheme::centre);
    const CaseResult& cen = r.get(ratio, Start::centred, PorosityScheme::centre);
    values.emplace_back("mesh_sensitivity.porosity_amp_closed." + rl, off.porosity_amp_pct);
    values.emplace_back("mesh_sensitivity.porosity_amp_paper." + rl, off.porosity_amp_pct);
    values.emplace_back("mesh_sensitivity.velocity_amp_paper." + rl, off.velocity_amp_pct);
    values.emplace_back("mesh_sensitivity.porosity_amp_centred." + rl, cen.porosity_amp_pct);
    values.emplace_back("mesh_sensitivity.vt_centred." + rl, cen.vt_mps);
    for (PorosityScheme scheme : {PorosityScheme::shape_function, PorosityScheme::diffused})
      for (Start start : {Start::offset, Start::centred})
        if (r.has(ratio, start, scheme)) {
          const CaseResult& s = r.get(ratio, start, scheme);
          const std::string prefix = "mesh_sensitivity." + scheme_name(scheme);
          values.emplace_back(fmt::format("{}.porosity_amp_{}.{}", prefix, start_name(start), rl), s.porosity_amp_pct);
          values.emplace_back(fmt::format("{}.velocity_amp_{}.{}", prefix, start_name(start), rl), s.velocity_amp_pct);
          values.emplace_back(fmt::format("{}.vt_{}.{}", prefix, start_name(start), rl), s.vt_mps);
        }
    values.emplace_back("mesh_sensitivity.centre.vt_offset." + rl, off.vt_mps);
    if (ratio == 3.0) {
      const CaseResult& d = r.get(ratio, Start::offset, PorosityScheme::diffused);
      values.emplace_back("mesh_sensitivity.diffused.porosity_amp_offset_below_centre_r10.r3", d.porosity_amp_pct);
      values.emplace_back("mesh_sensitivity.diffused.velocity_amp_offset_below_paper_r10.r3", d.velocity_amp_pct);
    }
  }
  study::write_values(dir, values);
}

// --- Gates ---------------------------------------------------------------

TEST(MeshSensitivity, OffsetStart_CentreScheme_PorosityAmplitudeMatchesClosedFormOfFiveTetSplit) {
  const auto ref = study::read_reference(kStudy);
  for (double ratio : kRatios) {
    const CaseResult& c = run().get(ratio, Start::offset, PorosityScheme::centre);
    const study::ReferenceRow& row = study::reference(ref, "mesh_sensitivity.porosity_amp_closed." + ratio_label(ratio));
    // Tolerance from reference_data (rel 1 %: the 2 significant digits the paper prints).
    EXPECT_TRUE(study::within_tolerance(row, c.porosity_amp_pct))
        << "ratio " << ratio << ": ours " << c.porosity_amp_pct << " %, closed form " << row.value << " %";
    // The closed form assumes the grain visits the central and a corner
    // tetrahedron only, in equal shares: check that it did.
    long central = 0, corner = 0, outside = 0;
    for (std::size_t i = 0; i < c.t_s.size(); ++i)
      if (c.t_s[i] >= kPlateauStart_s) (c.element_local[i] == 0 ? central : c.element_local[i] > 0 ? corner : outside)++;
    EXPECT_EQ(outside, 0) << "ratio " << ratio;
    EXPECT_GT(central, 0) << "ratio " << ratio;
    EXPECT_GT(corner, 0) << "ratio " << ratio;
  }
}

TEST(MeshSensitivity, CentredStart_CentreScheme_GrainStaysInCentralTetrahedraAndPorosityIsConstant) {
  const auto ref = study::read_reference(kStudy);
  for (double ratio : kRatios) {
    const CaseResult& c = run().get(ratio, Start::centred, PorosityScheme::centre);
    for (std::size_t i = 0; i < c.t_s.size(); ++i)
      ASSERT_EQ(c.element_local[i], 0) << "ratio " << ratio << " left the central tetrahedron at t = " << c.t_s[i];
    const study::ReferenceRow& row = study::reference(ref, "mesh_sensitivity.porosity_amp_centred." + ratio_label(ratio));
    EXPECT_TRUE(study::within_tolerance(row, c.porosity_amp_pct)) << "ratio " << ratio << ": " << c.porosity_amp_pct;
  }
}

TEST(MeshSensitivity, OffsetStart_CentreScheme_VelocityAmplitudeFallsMonotonicallyWithRatio) {
  const auto ref = study::read_reference(kStudy);
  std::printf("ratio  porosity amp %% (ours / closed / paper)   velocity amp %% (ours / paper)\n");
  double previous = INFINITY;
  for (double ratio : kRatios) {
    const CaseResult& c = run().get(ratio, Start::offset, PorosityScheme::centre);
    const std::string rl = ratio_label(ratio);
    std::printf("%5g  %8.4f / %6.4f / %5.2f              %7.4f / %5.2f\n", ratio, c.porosity_amp_pct,
                study::reference(ref, "mesh_sensitivity.porosity_amp_closed." + rl).value,
                study::reference(ref, "mesh_sensitivity.porosity_amp_paper." + rl).value, c.velocity_amp_pct,
                study::reference(ref, "mesh_sensitivity.velocity_amp_paper." + rl).value);
    EXPECT_LT(c.velocity_amp_pct, previous) << "ratio " << ratio;
    EXPECT_GT(c.velocity_amp_pct, 0.0) << "ratio " << ratio << ": an offset grain must feel the porosity jumps";
    previous = c.velocity_amp_pct;
  }
}

// The paper finds ratios of 5 or more acceptable (Sect. 4.2). The smoother
// scheme must make ratio 3 acceptable by that criterion: both amplitudes of
// the offset grain at ratio 3 below those of the paper's scheme at ratio 5.
TEST(MeshSensitivity, ShapeFunctionScheme_AtRatio3_OscillatesLessThanCentreSchemeAtRatio5) {
  const CaseResult& smooth = run().get(3.0, Start::offset, PorosityScheme::shape_function);
  const CaseResult& paper5 = run().get(5.0, Start::offset, PorosityScheme::centre);
  const CaseResult& paper3 = run().get(3.0, Start::offset, PorosityScheme::centre);
  const CaseResult& paper10 = run().get(10.0, Start::offset, PorosityScheme::centre);
  std::printf("offset, ratio 3: shape_function porosity %.4f %% velocity %.4f %% (%.2f s, porosity phase %.3f s)\n",
              smooth.porosity_amp_pct, smooth.velocity_amp_pct, smooth.wall_time_s, smooth.porosity_seconds);
  std::printf("offset, ratio 3: centre         porosity %.4f %% velocity %.4f %% (%.2f s, porosity phase %.3f s)\n",
              paper3.porosity_amp_pct, paper3.velocity_amp_pct, paper3.wall_time_s, paper3.porosity_seconds);
  std::printf("offset, ratio 10: centre        porosity %.4f %% velocity %.4f %%\n", paper10.porosity_amp_pct,
              paper10.velocity_amp_pct);
  EXPECT_LT(smooth.porosity_amp_pct, paper5.porosity_amp_pct);
  EXPECT_LT(smooth.velocity_amp_pct, paper5.velocity_amp_pct);
}

// The smoothest scheme must make ratio 3 better than the paper's scheme at
// its finest ratio: both amplitudes of the offset grain at ratio 3 below the
// centre scheme's at ratio 10, in the same run (same sampling, same plateau).
// Tolerance: the comparison is required with a factor 2 of margin, far
// outside what the measurement moves, so neither sampling nor tier can flip
// it: the porosity the drag uses is piecewise constant per fluid step and
// these are its samples, so the sampled peak-to-peak is the one the grain
// felt; the period at ratio 3 (h / v_t = 19 ms) against the 10 ms sampling
// walks the phase over the 15+ periods of the plateau, so the peak is caught
// to 1 - cos(pi / 15) = 2 %; fast (0.3 s plateau) and full (0.85 s) tiers
// agree to 1.5 % (porosity) and 6 % (velocity). Measured margins 3.6x and 7x
// (README).
TEST(MeshSensitivity, DiffusedScheme_AtRatio3_OscillatesLessThanCentreSchemeAtRatio10) {
  const CaseResult& smooth = run().get(3.0, Start::offset, PorosityScheme::diffused);
  const CaseResult& shape = run().get(3.0, Start::offset, PorosityScheme::shape_function);
  const CaseResult& paper3 = run().get(3.0, Start::offset, PorosityScheme::centre);
  const CaseResult& paper10 = run().get(10.0, Start::offset, PorosityScheme::centre);
  for (const CaseResult* c : {&paper3, &shape, &smooth})
    std::printf("offset, ratio 3: %-13s porosity %.4f %% velocity %.4f %% (wall %.2f s, CPU %.2f s, coupling phase %.3f s)\n",
                scheme_name(c->spec.scheme).c_str(), c->porosity_amp_pct, c->velocity_amp_pct, c->wall_time_s,
                c->cpu_time_s, c->porosity_seconds);
  std::printf("offset, ratio 10: centre       porosity %.4f %% velocity %.4f %% (wall %.2f s, CPU %.2f s)\n",
              paper10.porosity_amp_pct, paper10.velocity_amp_pct, paper10.wall_time_s, paper10.cpu_time_s);
  EXPECT_LT(2.0 * smooth.porosity_amp_pct, paper10.porosity_amp_pct);
  EXPECT_LT(2.0 * smooth.velocity_amp_pct, paper10.velocity_amp_pct);
  // The same claim against reference_data (closed form and paper at ratio 10).
  const auto ref = study::read_reference(kStudy);
  for (const auto& [id, ours] :
       {std::pair{std::string("mesh_sensitivity.diffused.porosity_amp_offset_below_centre_r10.r3"), smooth.porosity_amp_pct},
        std::pair{std::string("mesh_sensitivity.diffused.velocity_amp_offset_below_paper_r10.r3"), smooth.velocity_amp_pct}})
    EXPECT_TRUE(study::within_tolerance(study::reference(ref, id), ours)) << id << ": " << ours << " %";
}

// What each scheme does to the terminal velocity, against the GSL terminal
// velocity of the same drag law for an isolated sphere (eps = 1,
// reference/settling_reference) and for the plateau-mean porosity the grain
// saw (how much of the error is the mapped porosity); printed for the README.
// The claim checked: the smoother the scheme, the wider the grain's solid is
// spread, so the porosity deficit it sees in its own element shrinks
// strictly: centre > shape_function > diffused, wherever all three ran.
TEST(MeshSensitivity, SmootherSchemeGrainSeesPorosityNearerOne_TerminalVelocityAgainstGsl) {
  const Scene base = load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/mesh_sensitivity/mesh_sensitivity.yaml");
  SettlingModel model;
  model.diameter_m = base.particles[0].size.diameter;
  model.particle_density = base.particles[0].density;
  model.fluid = FluidProperties{base.fluid.density, base.fluid.viscosity};
  const double vt_isolated = terminal_velocity(model, 1.0);
  std::printf("GSL isolated-sphere terminal velocity %.5f m/s\n", vt_isolated);
  std::printf("ratio start   scheme         vt m/s    err vs GSL %%  1-eps seen   GSL vt(eps seen) err %%\n");
  for (const CaseResult& c : run().cases) {
    const double vt_eps = terminal_velocity(model, c.porosity_mean);
    std::printf("%5g %-7s %-13s %.5f  %+8.3f     %.2e    %+8.3f\n", c.spec.ratio, start_name(c.spec.start).c_str(),
                scheme_name(c.spec.scheme).c_str(), c.vt_mps, 100 * (c.vt_mps / vt_isolated - 1),
                1 - c.porosity_mean, 100 * (vt_eps / vt_isolated - 1));
  }
  long compared = 0;
  for (double ratio : kRatios)
    for (Start start : {Start::offset, Start::centred})
      if (run().has(ratio, start, PorosityScheme::shape_function) && run().has(ratio, start, PorosityScheme::diffused)) {
        const double centre = run().get(ratio, start, PorosityScheme::centre).porosity_mean;
        const double shape = run().get(ratio, start, PorosityScheme::shape_function).porosity_mean;
        const double diffused = run().get(ratio, start, PorosityScheme::diffused).porosity_mean;
        EXPECT_LT(centre, shape) << "ratio " << ratio << " " << start_name(start);
        EXPECT_LT(shape, diffused) << "ratio " << ratio << " " << start_name(start);
        ++compared;
      }
  EXPECT_GT(compared, 0);
}

// Full tier: a column 7 cells wide instead of 5 moves the terminal velocity at
// ratio 3 (walls nearest in diameters) by less than 0.2 %, below the smallest
// velocity amplitude tabulated (0.21 % at ratio 10): the walls cannot pose as
// an oscillation or a mesh effect. Measured 5 -> 9 cells: 0.08 %.
TEST(MeshSensitivity, WallsFarEnough_WiderColumnChangesTerminalVelocityBelowSmallestAmplitude) {
  if (!run().wide) GTEST_SKIP() << "full tier only";
  const CaseResult& five = run().get(3.0, Start::offset, PorosityScheme::centre);
  const double rel = std::abs(run().wide->vt_mps - five.vt_mps) / five.vt_mps;
  std::printf("ratio 3 offset: vt 5 cells %.5f, 7 cells %.5f m/s (%.3f %%)\n", five.vt_mps, run().wide->vt_mps,
              100 * rel);
  EXPECT_LT(rel, 0.002);
}

}  // namespace
}  // namespace fdem::mesh_sensitivity

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const std::string tier = fdem::study::tier_argument(argc, argv, {"fast", "full"});
  if (tier.empty()) return 2;
  using namespace fdem::mesh_sensitivity;
  StudyRun study_run;
  return fdem::study::run_tier_then_gates(
      kStudy,
      [&] {
        study_run = run_study(tier);
        write_results(study_run);
        g_run = &study_run;
      },
      // What defines a run of this study (meta.json, reports/FORMATS.md); the
      // tier's cases (ratios, schemes, end time) are listed in the header comment.
      [&](double wall_s, bool passed, const std::string& status) {
        return fdem::study::RunRecord{.tier = tier,
                                      .scene_file = "verification/mesh_sensitivity/mesh_sensitivity.yaml",
                                      .parameters = {},
                                      .wall_time_s = wall_s,
                                      .passed = passed,
                                      .status = status,
                                      .extra_json = ""};
      });
}

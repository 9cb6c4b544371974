// The shared study writer's provenance, the grid convergence index and the
// uniform-bed pressure gradients, on cases whose answers
// are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bed_pressure_gradient.hpp"
#include "coupling/drag.hpp"
#include "grid_convergence.hpp"
#include "study_io.hpp"

namespace fdem::study {
namespace {

// Ergun's gradient is what the paper's drag law (Eq. 12, Ergun branch below
// eps 0.8) hands a volume-averaged fluid through a bed at rest:
// -eps dp/dz = (1 - eps) K(eps, U / eps) U / eps.
TEST(BedPressureGradient, ErgunIsTheDragLawsUniformBedAndTheSimplifiedOneSeesU) {
  const FluidProperties water{1000.0, 1e-3};
  const DragLawEntry& law = drag_law("ergun_wen_yu");
  for (const double eps : {0.36, 0.42, 0.6, 0.79})
    for (const double U : {1e-4, 1e-2, 0.2}) {
      const double d = 1e-3, slip = U / eps;
      const double drag_per_volume = (1 - eps) * force_coefficient(law, eps, slip, d, water) * slip;
      EXPECT_NEAR(verification::ergun_gradient(eps, U, d, water.density, water.viscosity), drag_per_volume / eps,
                  1e-12 * drag_per_volume / eps);
      const double simplified = (1 - eps) * force_coefficient(law, eps, U, d, water) * U / eps;
      EXPECT_NEAR(verification::simplified_gradient(eps, U, d, water.density, water.viscosity), simplified,
                  1e-12 * simplified);
    }
}

// f(h) = 1 + h^2 sampled at h = 0.4, 0.2, 0.1: observed order exactly 2 and
// the GCI from Roache's formula, 1.25 |f2 - f1| / (2^2 - 1).
TEST(GridConvergence, SecondOrderSequenceHasOrderTwoAndRoachesIndex) {
  const auto u = refinement_uncertainty(1.01, 1.04, 1.16, 2.0, 2.0);
  EXPECT_EQ(u.kind, "monotone");
  EXPECT_NEAR(u.observed_order, 2.0, 1e-12);
  EXPECT_NEAR(u.gci_fine, 1.25 * 0.03 / 3.0, 1e-14);
  EXPECT_NEAR(u.u_num, u.gci_fine / 1.15, 1e-15);
  // The exact error of the finest value is 0.01; GCI_fine = 0.0125 bounds it.
  EXPECT_GT(u.gci_fine, 0.01);
}

// A fourth-order-looking sequence of a first-order scheme: the order used is
// the formal one (the observed 4 is not trusted beyond it).
TEST(GridConvergence, ObservedOrderAboveTheFormalOneIsCappedAtIt) {
  const auto u = refinement_uncertainty(1.0001, 1.0017, 1.0273, 2.0, 1.0);
  EXPECT_EQ(u.kind, "monotone");
  EXPECT_NEAR(u.observed_order, 4.0, 1e-9);
  EXPECT_NEAR(u.gci_fine, 1.25 * 0.0016 / (2.0 - 1.0), 1e-12);
}

// Differences that grow under refinement: no order, Fs = 3 at the formal order.
TEST(GridConvergence, DivergingDifferencesAreUnconfirmedWithSafetyFactorThree) {
  const auto u = refinement_uncertainty(1.0, 1.004, 1.005, 2.0, 1.0);
  EXPECT_EQ(u.kind, "unconfirmed");
  EXPECT_LT(u.observed_order, 0.0);
  EXPECT_NEAR(u.gci_fine, 3.0 * 0.004 / 1.0, 1e-12);
  EXPECT_GT(u.u_num, 0.0);
}

TEST(GridConvergence, OscillatingSequenceUsesHalfTheRange) {
  const auto u = refinement_uncertainty(1.00, 1.02, 0.99, 2.0, 2.0);
  EXPECT_EQ(u.kind, "oscillatory");
  EXPECT_TRUE(std::isnan(u.observed_order));
  EXPECT_NEAR(u.u_num, 0.015, 1e-15);
}

TEST(GridConvergence, IdenticalValuesHaveNoNumericalUncertainty) {
  const auto u = refinement_uncertainty(0.5, 0.5, 0.5, 2.0, 2.0);
  EXPECT_EQ(u.kind, "converged");
  EXPECT_EQ(u.u_num, 0.0);
}

TEST(StudyIo, OneSidedTolerancesBoundOnlyOneSide) {
  ReferenceRow at_least{"s.ratio", 1.01, 0.0, "at_least", true, "reproduction"};
  EXPECT_TRUE(within_tolerance(at_least, 1.01));
  EXPECT_TRUE(within_tolerance(at_least, 50.0));
  EXPECT_FALSE(within_tolerance(at_least, 1.0099));
  ReferenceRow at_most{"s.ratio", 1.0, 0.6, "at_most", true, "verification"};
  EXPECT_TRUE(within_tolerance(at_most, -3.0));
  EXPECT_TRUE(within_tolerance(at_most, 1.6));
  EXPECT_FALSE(within_tolerance(at_most, 1.61));
}

// The hash the report recomputes (reports/fdem_report/provenance.py) for
// "abc": FNV-1a 64 of the bytes 61 62 63 (published test vector).
TEST(StudyIo, FileHashIsFnv1a64OfTheBytes) {
  const auto path = std::filesystem::temp_directory_path() / "fdem_study_io_hash.txt";
  { std::ofstream(path) << "abc"; }
  EXPECT_EQ(file_hash(path.string()), "e71fa2190541574b");
  std::filesystem::remove(path);
  EXPECT_EQ(file_hash("/nonexistent/fdem/scene.yaml"), "");
}

TEST(StudyIo, MetaHoldsCommitSceneHashParametersAndThreads) {
  const auto dir = std::filesystem::temp_directory_path() / "fdem_study_io_meta";
  std::filesystem::create_directories(dir);
  RunRecord run;
  run.tier = "fast";
  run.scene_file = "verification/settling/settling.yaml";
  run.parameters = {{"fluid_step_s", "0.01"}, {"note", "quote \" and back\\slash"}};
  run.wall_time_s = 1.5;
  run.passed = true;
  write_meta(dir.string(), "settling", run);
  std::ifstream in(dir / "meta.json");
  std::stringstream text;
  text << in.rdbuf();
  const std::string m = text.str();
  EXPECT_NE(m.find("\"study\": \"settling\""), std::string::npos) << m;
  EXPECT_NE(m.find("\"file\": \"verification/settling/settling.yaml\""), std::string::npos) << m;
  EXPECT_NE(m.find("\"fnv1a64\": \"" + file_hash(std::string(FDEM_SOURCE_DIR) + "/" + run.scene_file) + "\""),
            std::string::npos) << m;
  EXPECT_NE(m.find("\"fluid_step_s\": \"0.01\""), std::string::npos) << m;
  EXPECT_NE(m.find("\"quote \\\" and back\\\\slash\""), std::string::npos) << m;
  EXPECT_NE(m.find("\"threads\": "), std::string::npos) << m;
  const SourceState src = source_state();
  EXPECT_NE(m.find("\"commit\": \"" + src.commit + "\""), std::string::npos) << m;
  std::filesystem::remove_all(dir);
}

// scripts/nightly.sh pins the commit it built; the writer reports that one.
TEST(StudyIo, PinnedCommitFromTheEnvironmentWins) {
  const std::string commit(40, 'a');
  ::setenv("FDEM_SOURCE_COMMIT", commit.c_str(), 1);
  ::setenv("FDEM_SOURCE_DIRTY", "1", 1);
  const SourceState s = source_state();
  ::unsetenv("FDEM_SOURCE_COMMIT");
  ::unsetenv("FDEM_SOURCE_DIRTY");
  EXPECT_EQ(s.commit, commit);
  EXPECT_TRUE(s.dirty);
  EXPECT_TRUE(s.known);
}

}  // namespace
}  // namespace fdem::study

// What accuracy costs on the fluidized bed: model A on the fast tier's bed
// (fluidized_bed.yaml, 400 grains, the same DEM-settled packing for every
// setting), the inlet raised through 0.3, 0.6, 1.5, 2.2, 3.0 U_mf, with one
// numerical setting changed at a time from the check's (cell / d 2,
// shape-function porosity, fluid step 2.5e-3 s, semi-implicit exchange):
//   cell_over_d       2, 3, 6 (the 6 mm column holds 3, 2 and 1 cells across)
//   porosity_scheme   shape_function, intersection, centre, diffused (L = 2 d)
//   dt_fluid          1.25e-3, 2.5e-3, 5e-3 s (DEM step kept: 50-200 subcycles)
//   exchange          semi_implicit, explicit_drag
// Errors of each run against the project's references (fluidized_bed_study.hpp):
//   plateau_error     worst |Delta p / (W / A) - 1| over the fluidized stages;
//   umf_error         |U_mf from the curve / Ergun's U_mf - 1|;
//   packed_error      worst |Delta p / Ergun(eps, U) - 1| over the packed stages;
// with the run's wall and CPU time (one thread). A run that fails (an
// unstable setting) is a row with nan errors and its reason printed.
// Rows: $FDEM_RESULTS_DIR/fluidized_bed/accuracy_cost.csv, drawn by
// report_figures.py as error against CPU time with the Pareto front.
// Label nightly (ten runs of about the fast tier's model-A test each).
#include <gtest/gtest.h>
#include <time.h>

#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "../support/study_results.hpp"
#include "fluidized_bed_study.hpp"

namespace fdem {
namespace {

using namespace fluidized_bed;  // NOLINT: the study's own names

[[maybe_unused]] const ::testing::Environment* const kResults =
    fdem::verification::register_study_results("fluidized_bed");

const std::vector<double> kFactors{0.3, 0.6, 1.5, 2.2, 3.0};
// As the fast tier (fluidized_bed_check.cpp): packed stages 0.1 s, the
// others 0.8 s; dry settle 0.5 s.
constexpr double kPackedStage = 0.1, kMovingStage = 0.8, kDrySettle = 0.5;

double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Point {
  std::string sweep, setting;
  Settings settings;
};

TEST(FluidizedBedCost, ErrorOfPlateauAndOnsetAgainstCellSchemeStepAndExchange) {
  omp_set_num_threads(1);
  Settings base;
  std::vector<Point> points;
  for (const double r : {2.0, 3.0, 6.0}) {
    Settings s = base;
    s.cell_size = r * 1e-3;
    points.push_back({"cell_over_d", fmt::format("{:g}", r), s});
  }
  const std::pair<const char*, PorosityScheme> schemes[] = {{"intersection", PorosityScheme::intersection},
                                                            {"centre", PorosityScheme::centre},
                                                            {"diffused", PorosityScheme::diffused}};
  for (const auto& [name, scheme] : schemes) {
    Settings s = base;
    s.set_porosity = true;
    s.porosity = scheme;
    points.push_back({"porosity_scheme", name, s});
  }
  for (const double dt : {1.25e-3, 5e-3}) {
    Settings s = base;
    s.fluid_step = dt;
    points.push_back({"dt_fluid", fmt::format("{:g} s", dt), s});
  }
  {
    Settings s = base;
    s.set_exchange = true;
    s.exchange = MomentumExchange::explicit_drag;
    points.push_back({"exchange", "explicit_drag", s});
  }
  int finished = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Point& pt = points[k];
    const double nan = std::numeric_limits<double>::quiet_NaN();
    double plateau = nan, umf = nan, packed = nan, wall = nan;
    const double cpu0 = thread_cpu_s();
    try {
      const Prepared p = prepare(FDEM_SOURCE_DIR "/verification/fluidized_bed/fluidized_bed.yaml", kDrySettle,
                                 FluidModel::vans_a, SourceForm::conservative, pt.settings, kFactors, "sweep");
      const BedRun run = run_stages(p, "vans_a", kPackedStage, kMovingStage);
      const Summary s = summarize(run, p.bed);
      plateau = std::abs(s.plateau_over_weight_worst - 1.0);
      umf = std::abs(s.umf_curve_over_ergun - 1.0);
      packed = std::abs(s.packed_over_ergun_worst - 1.0);
      wall = run.wall_s;
      ++finished;
    } catch (const std::exception& e) {
      fmt::print("  {} {}: run failed: {}\n", pt.sweep, pt.setting, e.what());
    }
    const double cpu = thread_cpu_s() - cpu0;
    fmt::print("{:16s} {:14s} plateau error {:.4f}  U_mf error {:.4f}  packed error {:.4f}  wall {:.1f} s  cpu {:.1f} s\n",
               pt.sweep, pt.setting, plateau, umf, packed, wall, cpu);
    // The base setting is every sweep's reference point: written once per sweep.
    std::vector<std::string> sweeps{pt.sweep};
    if (k == 0) sweeps = {"cell_over_d", "porosity_scheme", "dt_fluid", "exchange"};
    for (const std::string& sweep : sweeps) {
      const std::string setting = k == 0 ? (sweep == "cell_over_d"       ? std::string("2")
                                            : sweep == "porosity_scheme" ? std::string("shape_function")
                                            : sweep == "dt_fluid"        ? std::string("0.0025 s")
                                                                         : std::string("semi_implicit"))
                                         : pt.setting;
      fdem::verification::record_series_row(
          "fluidized_bed", "accuracy_cost.csv", fmt::format("{}_{}", sweep, setting),
          {"sweep", "setting", "plateau_error", "umf_error", "packed_error", "wall_time_s", "cpu_time_s"},
          {sweep, setting, fmt::format("{}", plateau), fmt::format("{}", umf), fmt::format("{}", packed),
           fmt::format("{}", wall), fmt::format("{}", cpu)});
    }
  }
  // The base setting and the sweeps' stable settings run to the end.
  EXPECT_GE(finished, static_cast<int>(points.size()) - 1);
}

// Cell / d 4, 5 and 8, which the fast bed's 6 mm column cannot hold: the
// same bed (grains per area, height) in an 8 mm column
// (fluidized_bed_wide.yaml, 711 grains; cell / d 2 beside them as that
// column's own base) and a 10 mm one (fluidized_bed_wide10.yaml, 1111
// grains). The bed is then 2.4, 1.9 and 1.2 cells tall at cell / d 4, 5, 8.
TEST(FluidizedBedCost, WideColumnCellSizes) {
  omp_set_num_threads(1);
  int finished = 0;
  const std::pair<const char*, double> cases[] = {{"fluidized_bed_wide.yaml", 2.0},
                                                  {"fluidized_bed_wide.yaml", 4.0},
                                                  {"fluidized_bed_wide10.yaml", 5.0},
                                                  {"fluidized_bed_wide.yaml", 8.0}};
  for (const auto& [file, r] : cases) {
    Settings s;
    s.cell_size = r * 1e-3;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    double plateau = nan, umf = nan, packed = nan, wall = nan;
    const double cpu0 = thread_cpu_s();
    try {
      const Prepared p = prepare(std::string(FDEM_SOURCE_DIR "/verification/fluidized_bed/") + file, kDrySettle,
                                 FluidModel::vans_a, SourceForm::conservative, s, kFactors, "sweep_wide");
      const BedRun run = run_stages(p, "vans_a", kPackedStage, kMovingStage);
      const Summary sum = summarize(run, p.bed);
      plateau = std::abs(sum.plateau_over_weight_worst - 1.0);
      umf = std::abs(sum.umf_curve_over_ergun - 1.0);
      packed = std::abs(sum.packed_over_ergun_worst - 1.0);
      wall = run.wall_s;
      ++finished;
    } catch (const std::exception& e) {
      fmt::print("  wide column, cell / d {:g}: run failed: {}\n", r, e.what());
    }
    const double cpu = thread_cpu_s() - cpu0;
    fmt::print("cell_over_d_wide {:14g} plateau error {:.4f}  U_mf error {:.4f}  packed error {:.4f}  wall {:.1f} s  cpu {:.1f} s\n",
               r, plateau, umf, packed, wall, cpu);
    fdem::verification::record_series_row(
        "fluidized_bed", "accuracy_cost.csv", fmt::format("cell_over_d_wide_{:g}", r),
        {"sweep", "setting", "plateau_error", "umf_error", "packed_error", "wall_time_s", "cpu_time_s"},
        {"cell_over_d_wide", fmt::format("{:g}", r), fmt::format("{}", plateau), fmt::format("{}", umf),
         fmt::format("{}", packed), fmt::format("{}", wall), fmt::format("{}", cpu)});
  }
  EXPECT_EQ(finished, 4);
}

}  // namespace
}  // namespace fdem

// `mpirun -n 2 fdem run` of a reduced salt plume against `fdem run`:
// verification/plume/plume_fast.yaml (4704 grains, 2160 tetrahedra,
// two-way drag, 60 DEM subcycles a fluid step) for its first 30 fluid
// steps, with two changes so grains cross the rank boundary: the block
// starts 20 mm lower (z 40-80 mm), across the cut at half height (the
// column is cut along z at 60 mm), and its grains are polydisperse (0.6 to
// 0.8 mm instead of 0.6 mm), so they settle at different speeds and the
// neighbour list is rebuilt (a rigid fall of the block needs no rebuild:
// the skin test is on relative displacement). Grains migrate at those
// rebuilds, in the middle of a fluid step's subcycles, carrying that step's
// drag state (DragCoupling::carried_state); the log's migration count
// confirms it happened.
//
// What is bitwise and what is not. Each grain's contact forces, its drag in
// every subcycle (given the same fluid velocity and porosity) and its mean
// drag are computed as one process computes them. The porosity, the source
// term and (semi-implicit) the exchange coefficients are sums over grains
// per element: each rank sums its own grains and the ranks' partial sums
// are added (parallel/grain_share.hpp), which regroups the sum in elements
// touched by grains of both ranks: a few ulp there. The fluid's linear
// solve is shared by the ranks (PETSc, a block Jacobi of two ILU(1) blocks
// against one process's one block) and stopped at the relative residual
// 1e-8 (fluid.linear_tolerance): the fluid differs by up to that much,
// relative, at every step, far above the ulp of the sums. The grains follow
// the fluid through the drag, so their velocities and positions agree to
// the linear tolerance and not bitwise; the grain count does bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <string>

#include "mpi_runs.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;
using hard::read_text;
using mpi_test::fdem_on;

// The largest difference between the two runs' probe columns over every row,
// relative to the column's largest magnitude in the one-process run.
double worst_relative(const hard::Csv& one, const hard::Csv& two, const std::string& column) {
  const int c = one.column(column);
  EXPECT_GE(c, 0) << column;
  if (c < 0) return 1.0;
  const auto k = static_cast<std::size_t>(c);
  double scale = 0.0, worst = 0.0;
  for (const auto& row : one.rows) scale = std::max(scale, std::abs(row[k]));
  for (std::size_t r = 0; r < one.rows.size(); ++r) worst = std::max(worst, std::abs(two.rows[r][k] - one.rows[r][k]));
  return scale > 0.0 ? worst / scale : worst;
}

// The plume to 0.06 s (30 fluid steps of 2 ms), one probe row a step;
// `exchange` the coupling.exchange key, `porosity` the coupling.porosity one
// (empty: the file's, centre).
void compare_plume(const std::string& name, const std::string& exchange, const std::string& porosity = "") {
  const fs::path dir = hard::scratch_dir(name);
  std::string scene = read_text(fs::path(FDEM_SOURCE_DIR) / "verification/plume/plume_fast.yaml");
  const auto end = scene.find("  end: 0.4");
  ASSERT_NE(end, std::string::npos) << "plume_fast.yaml's time.end moved";
  scene.replace(end, 10, "  end: 0.06");
  const auto output = scene.find("output:\n  directory: out/plume_fast");
  ASSERT_NE(output, std::string::npos) << "plume_fast.yaml's output moved";
  scene.replace(output, std::string::npos, "output: {directory: out, vtu_interval: 1.0, csv_interval: 2.0e-3}\n");
  const std::string block = "region: {lower: [0.020, 0.020, 0.060], upper: [0.040, 0.040, 0.100]}";
  const auto region = scene.find(block);
  ASSERT_NE(region, std::string::npos) << "plume_fast.yaml's block moved";
  scene.replace(region, block.size(), "region: {lower: [0.020, 0.020, 0.040], upper: [0.040, 0.040, 0.080]}");
  const std::string one_size = "size: 0.6e-3";
  const auto size = scene.find(one_size);
  ASSERT_NE(size, std::string::npos) << "plume_fast.yaml's grain size moved";
  scene.replace(size, one_size.size(), "size: {distribution: uniform, min: 0.6e-3, max: 0.8e-3}");
  if (!exchange.empty()) {
    const auto coupling = scene.find("coupling:\n");
    ASSERT_NE(coupling, std::string::npos);
    scene.insert(coupling + 10, "  exchange: " + exchange + "\n");
  }
  if (!porosity.empty()) {
    const std::string centre = "porosity: centre";
    const auto scheme = scene.find(centre);
    ASSERT_NE(scheme, std::string::npos) << "plume_fast.yaml's porosity moved";
    scene.replace(scheme, centre.size(), "porosity: " + porosity);
  }
  hard::write_text(dir / "plume.yaml", scene);
  const std::string yaml = (dir / "plume.yaml").string();
  ASSERT_EQ(fdem_on(1, fmt::format("run '{}' -o '{}' -q", yaml, (dir / "one").string()), dir / "one.log"), 0)
      << read_text(dir / "one.log");
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q", yaml, (dir / "two").string()), dir / "two.log"), 0)
      << read_text(dir / "two.log");
  const std::string two_log = read_text(dir / "two.log");
  EXPECT_NE(two_log.find("decomposed in 2 slabs along z"), std::string::npos) << two_log;
  // The load per rank is reported, and grains did move between the ranks.
  EXPECT_NE(two_log.find("grains per rank at the end"), std::string::npos) << two_log;
  const auto migrated = two_log.find(" grains migrated");
  ASSERT_NE(migrated, std::string::npos) << two_log;
  const auto number = two_log.rfind(' ', migrated - 1);
  EXPECT_GT(std::stod(two_log.substr(number + 1, migrated - number - 1)), 0.0) << two_log;

  const hard::Csv one = hard::read_csv(dir / "one/probes.csv"), two = hard::read_csv(dir / "two/probes.csv");
  ASSERT_TRUE(one.well_formed && two.well_formed);
  ASSERT_EQ(one.columns, two.columns);
  ASSERT_EQ(one.rows.size(), 31u);  // t = 0 and 30 steps
  ASSERT_EQ(two.rows.size(), one.rows.size());
  EXPECT_EQ(worst_relative(one, two, "count"), 0.0);
  const double vz = worst_relative(one, two, "mean_vz"), speed = worst_relative(one, two, "max_speed"),
               energy = worst_relative(one, two, "kinetic_energy"), z = worst_relative(one, two, "mean_z"),
               low = worst_relative(one, two, "min_z");
  fmt::print("{}: 2 ranks against 1: mean_vz {:.2e}, max_speed {:.2e}, kinetic energy {:.2e}, mean_z {:.2e}, "
             "min_z {:.2e} (relative to each column's largest value)\n",
             name, vz, speed, energy, z, low);
  // The linear tolerance 1e-8 (header comment): the fluid, and through the
  // drag the grains, agree to it (measured 3e-11 on the velocities, 1e-12 on
  // the heights, with 392 grains migrated in 3 redistributions). Drag state
  // that did not travel whole fails it: the x drag summed so far zeroed at
  // each redistribution gave mean_vz 5.2e-7, max_speed 2.6e-6.
  EXPECT_LE(vz, 1e-8);
  EXPECT_LE(speed, 1e-8);
  EXPECT_LE(energy, 2e-8);  // quadratic in the velocities: twice their relative difference
  EXPECT_LE(z, 1e-8);
  EXPECT_LE(low, 1e-8);
}

TEST(MpiPlume, TwoRanksGiveOneProcessAnswerWithinTheLinearTolerance) { compare_plume("mpi_plume", ""); }

// The nodal porosity schemes: each rank's grains' nodal solid completed on
// the corners of the elements it needs (shape_function), or on every node
// for the smoothing solve over the whole mesh (diffused: every rank solves
// the same system, from the same bits), by records of the touched nodes
// (parallel/element_sums.hpp). The nodal sums regroup as the element sums
// do (a few ulp), far below the fluid's linear tolerance, which bounds the
// difference as above (the diffused solve's own tolerance, 1e-10, too).
TEST(MpiPlume, ShapeFunctionPorosityOnTwoRanksGivesOneProcessAnswerWithinTheLinearTolerance) {
  compare_plume("mpi_plume_shape_function", "", "shape_function");
}
TEST(MpiPlume, DiffusedPorosityOnTwoRanksGivesOneProcessAnswerWithinTheLinearTolerance) {
  compare_plume("mpi_plume_diffused", "", "diffused");
}

// The semi-implicit exchange: each grain's frozen coefficient c_i travels with it too.
TEST(MpiPlume, SemiImplicitExchangeOnTwoRanksGivesOneProcessAnswerWithinTheLinearTolerance) {
  compare_plume("mpi_plume_semi_implicit", "semi_implicit");
}

}  // namespace
}  // namespace fdem

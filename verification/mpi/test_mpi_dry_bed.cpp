// `mpirun -n 2 fdem run` of a dry bed against `fdem run`: 448 beads dropped
// into a 40 x 12 x 30 mm box, cut along x into two slabs, so the bed lies
// across the rank boundary and grains migrate (Simulation decomposes a dry
// scene's grains over the ranks, parallel/grain_exchange.hpp).
//
// Each grain's force is summed in one process's order on its rank
// (verification/mpi/test_mpi_dem.cpp says why), so the grains are one
// process's bit for bit (the snapshot pieces: test_mpi_output.cpp); the
// contact counts are sums of integers. The probes are summed from each
// rank's own grains and added over the ranks (no gather a row): counts,
// extrema and diagnostics bit for bit, the sums of positions, velocities
// and energy to their rounding (mpi_runs.hpp, expect_probes_within_sum_rounding).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fmt/format.h>
#include <string>

#include "mpi_runs.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;
using hard::read_text;

using mpi_test::shell;
int run_shell(const std::string& command, const fs::path& log) { return shell(command, log); }

constexpr const char* kDryBed = R"(title: dry bed across two slabs
effects: {fluid: false, gravity: true, normal_contact: true, walls: true}
domain: {lower: [0, 0, 0], upper: [0.04, 0.012, 0.03]}
gravity: [0, 0, -9.81]
particles:
  - name: beads
    placement: lattice
    region: {lower: [0.0015, 0.0010, 0.0015], upper: [0.0385, 0.0110, 0.0215]}
    lattice: [14, 4, 8]
    size: {distribution: uniform, min: 1.6e-3, max: 2.4e-3}
    density: 2500
    seed: 5
contact: {kn: 200, restitution: 0.5}
time: {dem_step: 2.0e-5, subcycles: 50, end: 0.06}
output: {directory: out, vtu_interval: 1.0, csv_interval: 0.001}
)";

constexpr double kBeads = 448, kLargestCoordinate = 0.04;  // the lattice; the box's x extent [m]

TEST(MpiDryBed, TwoRanksWriteOneProcessProbesWithinTheirSumsRounding) {
  const fs::path dir = hard::scratch_dir("mpi_dry_bed");
  hard::write_text(dir / "dry_bed.yaml", kDryBed);
  const std::string fdem = FDEM_EXE, yaml = (dir / "dry_bed.yaml").string();
  ASSERT_EQ(run_shell(fmt::format("'{}' run '{}' -o '{}' -q -t 1", fdem, yaml, (dir / "one").string()), dir / "one.log"),
            0)
      << read_text(dir / "one.log");
  ASSERT_EQ(run_shell(fmt::format("OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n 2 '{}' run '{}' -o '{}' -q",
                                  FDEM_MPIEXEC, fdem, yaml, (dir / "two").string()),
                      dir / "two.log"),
            0)
      << read_text(dir / "two.log");
  const std::string two_log = read_text(dir / "two.log");
  EXPECT_NE(two_log.find("decomposed"), std::string::npos) << two_log;
  const hard::Csv one = hard::read_csv(dir / "one/probes.csv");
  ASSERT_TRUE(one.well_formed);
  ASSERT_EQ(one.rows.size(), 61u);  // t = 0 and 60 rows of 1 ms
  const int contacts = one.column("contacts");
  ASSERT_GE(contacts, 0);
  // Measured 225 contacts at the end: the lower layers have landed and touch.
  EXPECT_GT(one.rows.back()[static_cast<std::size_t>(contacts)], 150.0) << "the bed settled in contact";
  const double worst = mpi_test::expect_probes_within_sum_rounding(one, hard::read_csv(dir / "two/probes.csv"), kBeads,
                                                                   kLargestCoordinate);
  fmt::print("dry bed, 2 ranks against 1: probe sums within {:.3f} of their rounding bound\n", worst);
}

// The same bed with friction and rotation (Eq. 7-10): each contact's
// tangential spring is a state that must travel with the grains at every
// migration (the pair slips with the grain of their row, the wall slips
// with theirs; DemEngine::decompose). Each owned grain's row then holds one
// process's slips bit for bit, so the probes agree as above.
TEST(MpiDryBed, FrictionalBedOnTwoRanksWritesOneProcessProbesWithinTheirSumsRounding) {
  const fs::path dir = hard::scratch_dir("mpi_frictional_bed");
  std::string scene = kDryBed;
  const std::string effects = "normal_contact: true, walls: true}";
  const auto at = scene.find(effects);
  ASSERT_NE(at, std::string::npos);
  scene.replace(at, effects.size(), "normal_contact: true, tangential_contact: true, rotation: true, walls: true}");
  const std::string contact = "contact: {kn: 200, restitution: 0.5}";
  const auto law = scene.find(contact);
  ASSERT_NE(law, std::string::npos);
  scene.replace(law, contact.size(), "contact: {kn: 200, restitution: 0.5, kt: 100, friction: 0.4}");
  hard::write_text(dir / "bed.yaml", scene);
  const std::string fdem = FDEM_EXE, yaml = (dir / "bed.yaml").string();
  ASSERT_EQ(run_shell(fmt::format("'{}' run '{}' -o '{}' -q -t 1", fdem, yaml, (dir / "one").string()), dir / "one.log"),
            0)
      << read_text(dir / "one.log");
  ASSERT_EQ(run_shell(fmt::format("OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n 2 '{}' run '{}' -o '{}' -q",
                                  FDEM_MPIEXEC, fdem, yaml, (dir / "two").string()),
                      dir / "two.log"),
            0)
      << read_text(dir / "two.log");
  const std::string two_log = read_text(dir / "two.log");
  EXPECT_NE(two_log.find("the grains decomposed in 2 slabs"), std::string::npos) << two_log;
  // Friction holds this bed: no grain changes rank in 0.06 s here (mpi_dem's
  // frictional bed, 0.08 s from random velocities, migrates 24), but its
  // contacts across the face are ghost contacts, whose slips are routed by
  // id at each of its 9 redistributions (the ghosts re-sorted among the
  // owned grains change every local index). Dry, the rebuild test is the
  // grains' relative displacement, as in one process (17 with the coupled
  // runs' absolute test, DemEngine::decompose).
  EXPECT_NE(two_log.find(" 9 redistributions, 0 grains migrated, 64 ghosts held"), std::string::npos)
      << "the redistributions counted: " << two_log;
  const hard::Csv one = hard::read_csv(dir / "one/probes.csv");
  ASSERT_TRUE(one.well_formed);
  const int contacts = one.column("contacts");
  ASSERT_GE(contacts, 0);
  EXPECT_GT(one.rows.back()[static_cast<std::size_t>(contacts)], 150.0) << "the bed settled in contact";
  const double worst = mpi_test::expect_probes_within_sum_rounding(one, hard::read_csv(dir / "two/probes.csv"), kBeads,
                                                                   kLargestCoordinate);
  fmt::print("frictional bed, 2 ranks against 1: probe sums within {:.3f} of their rounding bound\n", worst);
}

// A checkpoint of the decomposed run holds the whole set in id order (the
// state one process writes), and a run resumed from it on 2 ranks
// redistributes it: the resumed run's grains are those of one process run
// straight through, bit for bit, its probes as above (the rows before the
// checkpoint carried from the first 2-rank run).
TEST(MpiDryBed, CheckpointWrittenOnTwoRanksResumesOnTwoRanksAsOneUninterruptedProcess) {
  const fs::path dir = hard::scratch_dir("mpi_dry_bed_resume");
  std::string scene = kDryBed;
  const auto output = scene.find("csv_interval: 0.001}");
  ASSERT_NE(output, std::string::npos);
  scene.replace(output, 20, "csv_interval: 0.001, checkpoint_interval: 0.03}");
  hard::write_text(dir / "first.yaml", scene);  // to 0.06 s, its last checkpoint there
  const auto end = scene.find("end: 0.06");
  ASSERT_NE(end, std::string::npos);
  scene.replace(end, 9, "end: 0.09");
  hard::write_text(dir / "longer.yaml", scene);
  const std::string fdem = FDEM_EXE, mpirun = fmt::format("OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n 2", FDEM_MPIEXEC);
  ASSERT_EQ(run_shell(fmt::format("'{}' run '{}' -o '{}' -q -t 1", fdem, (dir / "longer.yaml").string(),
                                  (dir / "straight").string()),
                      dir / "straight.log"),
            0)
      << read_text(dir / "straight.log");
  ASSERT_EQ(run_shell(fmt::format("{} '{}' run '{}' -o '{}' -q", mpirun, fdem, (dir / "first.yaml").string(),
                                  (dir / "first").string()),
                      dir / "first.log"),
            0)
      << read_text(dir / "first.log");
  ASSERT_EQ(run_shell(fmt::format("{} '{}' run '{}' -o '{}' -q --restart '{}'", mpirun, fdem,
                                  (dir / "longer.yaml").string(), (dir / "resumed").string(),
                                  (dir / "first/checkpoint.bin").string()),
                      dir / "resumed.log"),
            0)
      << read_text(dir / "resumed.log");
  const hard::Csv resumed = hard::read_csv(dir / "resumed/probes.csv");
  ASSERT_TRUE(resumed.well_formed);
  ASSERT_EQ(resumed.rows.size(), 91u);  // rows before the checkpoint carried, then 30 more
  const double worst = mpi_test::expect_probes_within_sum_rounding(hard::read_csv(dir / "straight/probes.csv"), resumed,
                                                                   kBeads, kLargestCoordinate);
  fmt::print("dry bed resumed on 2 ranks against one process straight through: probe sums within {:.3f} of their "
             "rounding bound\n", worst);
}

}  // namespace
}  // namespace fdem

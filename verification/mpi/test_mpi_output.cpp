// The output of `mpirun -n 2 fdem run` (verification/mpi/slab_drop.yaml: 384
// beads thrown across the slab boundary x = 20 mm, no fluid) against one
// process's. With no fluid every rank steps every grain bit for bit like one
// process (the DEM is bit-identical for any thread count, so for any rank
// count while the grains are replicated); each rank writes the grains whose
// centre lies in its slab as one piece of each snapshot, and the probes sum
// each rank's own grains over the ranks.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "mpi_runs.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;
using hard::read_csv;
using hard::read_text;
using mpi_test::fdem_on;
using mpi_test::occurrences;

const std::string kScene = std::string(FDEM_SOURCE_DIR) + "/verification/mpi/slab_drop.yaml";
constexpr double kSlabBoundary = 0.02;  // half the domain's x extent (parallel/slab_partition.hpp)
constexpr std::size_t kGrains = 384;

// What vtk_check.py (an XML + zlib reader written apart from fdem) reads
// from a .pvd: per dataset the files read, per file its arrays.
struct Snapshot {
  std::string file;                  // the .pvd's DataSet file
  std::vector<std::string> pieces;   // a .pvtu's Piece sources, in order
};
struct PvdRead {
  int status = -1;
  std::vector<Snapshot> snapshots;
  std::map<std::string, std::map<std::string, std::vector<double>>> arrays;  // file -> "section name" -> values
};

PvdRead read_pvd(const fs::path& pvd) {
  PvdRead r;
  const fs::path out = pvd.parent_path() / "vtk_check.out";
  r.status = mpi_test::shell(
      fmt::format("'{}' '{}/solver/io/tests/vtk_check.py' '{}'", FDEM_PYTHON, FDEM_SOURCE_DIR, pvd.string()), out);
  std::istringstream in(read_text(out));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "dataset") {
      std::string time, file;
      words >> time >> file;
      r.snapshots.push_back({file, {}});
    } else if (kind == "source" && !r.snapshots.empty()) {
      std::string pvtu, piece;
      words >> pvtu >> piece;
      r.snapshots.back().pieces.push_back(piece);
    } else if (kind == "array") {
      std::string file, section, name;
      int components = 0;
      words >> file >> section >> name >> components;
      std::vector<double>& values = r.arrays[fs::path(file).filename().string()][section + " " + name];
      for (double v; words >> v;) values.push_back(v);
    }
  }
  return r;
}

TEST(MpiOutput, PiecesOfTwoRanksHoldEveryGrainOnceInItsSlabAsOneProcessHasIt) {
  const fs::path dir = hard::scratch_dir("mpi_output_pieces");
  ASSERT_EQ(fdem_on(1, fmt::format("run '{}' -o '{}' -q", kScene, (dir / "one").string()), dir / "one.log"), 0)
      << read_text(dir / "one.log");
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q", kScene, (dir / "two").string()), dir / "two.log"), 0)
      << read_text(dir / "two.log");

  const PvdRead one = read_pvd(dir / "one/particles.pvd"), two = read_pvd(dir / "two/particles.pvd");
  ASSERT_EQ(one.status, 0) << read_text(dir / "one/vtk_check.out");
  ASSERT_EQ(two.status, 0) << read_text(dir / "two/vtk_check.out");  // every piece holds the arrays its .pvtu declares
  ASSERT_EQ(one.snapshots.size(), 5u);  // t = 0, 0.01, ..., 0.04
  ASSERT_EQ(two.snapshots.size(), one.snapshots.size());
  std::size_t crossed = 0;  // grains whose owner changed since t = 0
  std::map<std::int64_t, int> first_owner;
  for (std::size_t s = 0; s < two.snapshots.size(); ++s) {
    const Snapshot& snap = two.snapshots[s];
    EXPECT_EQ(snap.file, fmt::format("particles_{:06d}.pvtu", s));
    ASSERT_EQ(snap.pieces, (std::vector<std::string>{fmt::format("particles_{:06d}_rank0000.vtu", s),
                                                      fmt::format("particles_{:06d}_rank0001.vtu", s)}));
    // One process's snapshot: grain id -> its centre.
    const auto& whole = one.arrays.at(one.snapshots[s].file);
    const std::vector<double>& whole_id = whole.at("PointData id");
    const std::vector<double>& whole_xyz = whole.at("Points Points");
    ASSERT_EQ(whole_id.size(), kGrains);
    std::map<std::int64_t, std::size_t> at;
    for (std::size_t i = 0; i < whole_id.size(); ++i) at[static_cast<std::int64_t>(whole_id[i])] = i;

    std::map<std::int64_t, int> seen;  // id -> how many pieces hold it
    for (int rank = 0; rank < 2; ++rank) {
      const auto& piece = two.arrays.at(snap.pieces[static_cast<std::size_t>(rank)]);
      const std::vector<double>& ids = piece.at("PointData id");
      const std::vector<double>& xyz = piece.at("Points Points");
      ASSERT_EQ(xyz.size(), 3 * ids.size());
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const auto id = static_cast<std::int64_t>(ids[i]);
        ++seen[id];
        // In its rank's slab, and where one process has it, bit for bit.
        EXPECT_EQ(xyz[3 * i] >= kSlabBoundary, rank == 1) << "grain " << id << " at x = " << xyz[3 * i];
        ASSERT_TRUE(at.contains(id)) << "grain " << id << " is not in one process's snapshot " << s;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(xyz[3 * i + c], whole_xyz[3 * at[id] + c]) << "grain " << id;
        if (s == 0) first_owner[id] = rank;
        else if (first_owner.at(id) != rank) ++crossed;
      }
    }
    EXPECT_EQ(seen.size(), kGrains) << "snapshot " << s << ": every grain in some piece";
    for (const auto& [id, count] : seen) EXPECT_EQ(count, 1) << "snapshot " << s << ": grain " << id;
  }
  fmt::print("pieces: every grain exactly once over 5 snapshots; {} grain-snapshots in another slab than at t = 0\n",
             crossed);
  EXPECT_GT(crossed, 0u) << "the scene must move grains across the slab boundary";
}

TEST(MpiOutput, ProbesOfTwoRanksEqualOneProcessToTheRoundingOfTheirSums) {
  const fs::path dir = hard::scratch_dir("mpi_output_probes");
  // No snapshots: only the probes are compared here.
  std::string scene = read_text(kScene);
  const auto vtu = scene.find("vtu_interval: 0.01");
  ASSERT_NE(vtu, std::string::npos) << "slab_drop.yaml's output moved";
  scene.replace(vtu, 18, "vtu_interval: 0");
  hard::write_text(dir / "slab_drop.yaml", scene);
  const std::string yaml = (dir / "slab_drop.yaml").string();
  ASSERT_EQ(fdem_on(1, fmt::format("run '{}' -o '{}' -q", yaml, (dir / "one").string()), dir / "one.log"), 0)
      << read_text(dir / "one.log");
  // With the progress line (not -q): printed by rank 0 alone.
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}'", yaml, (dir / "two").string()), dir / "two.log"), 0)
      << read_text(dir / "two.log");
  const std::string log = read_text(dir / "two.log");
  EXPECT_EQ(occurrences(log, "fdem run: " + yaml + ": 384 particles"), 1) << log;
  EXPECT_EQ(occurrences(log, "t = 0.04 s of 0.04 s (100.0%)"), 1) << log;  // the final progress line
  EXPECT_EQ(occurrences(log, "fdem run: wall"), 1) << log;

  const hard::Csv a = read_csv(dir / "one/probes.csv"), b = read_csv(dir / "two/probes.csv");
  ASSERT_TRUE(a.well_formed && b.well_formed);
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows.size(), 41u);  // t = 0 and 40 steps
  ASSERT_EQ(b.rows.size(), a.rows.size());
  const auto column = [&](const char* name) {
    const int c = a.column(name);
    EXPECT_GE(c, 0) << name;
    return c;
  };
  // Order-free columns: counts, extrema, the diagnostics (each rank steps every grain).
  std::vector<int> exact{column("time"), column("step"), column("count"), column("max_speed"), column("min_z"),
                         column("max_z")};
  for (const char* d : {"contacts", "max_overlap_over_d", "particles_removed"}) exact.push_back(column(d));
  // Sums: two ranks add each slab's grains, then the two partial sums; one
  // process adds all 384 in index order. Any two orders of summing n terms
  // differ by at most 2 (n - 1) eps sum|x_i| (Higham, Accuracy and Stability
  // of Numerical Algorithms, 2002, eq. 4.4), so a mean by 2 (n - 1) eps
  // max|x_i| and the kinetic energy (positive terms) by 2 (n - 1) eps of itself.
  const double order_bound = 2.0 * (kGrains - 1) * DBL_EPSILON;
  const int speed = column("max_speed"), energy = column("kinetic_energy");
  double worst = 0.0;  // the largest difference in units of its bound
  for (std::size_t r = 0; r < a.rows.size(); ++r) {
    const std::vector<double>&x = a.rows[r], &y = b.rows[r];
    for (int c : exact) EXPECT_EQ(x[c], y[c]) << a.columns[c] << " at row " << r;
    const double upper_x = 0.04, upper_y = 0.01, upper_z = 0.02;  // the domain's far corner (positions >= 0)
    const std::vector<std::pair<int, double>> bounded{
        {column("mean_x"), order_bound * upper_x}, {column("mean_y"), order_bound * upper_y},
        {column("mean_z"), order_bound * upper_z}, {column("mean_vx"), order_bound * x[speed]},
        {column("mean_vy"), order_bound * x[speed]}, {column("mean_vz"), order_bound * x[speed]},
        {energy, order_bound * x[energy]}};
    for (const auto& [c, bound] : bounded) {
      EXPECT_LE(std::abs(x[c] - y[c]), bound) << a.columns[c] << " at row " << r;
      if (bound > 0.0) worst = std::max(worst, std::abs(x[c] - y[c]) / bound);
    }
  }
  fmt::print("probes, 2 ranks against 1: counts and extrema equal; sums within {:.3f} of the reordering bound\n", worst);
}

}  // namespace
}  // namespace fdem

// The output of `mpirun -n 2 fdem run` (verification/mpi/slab_drop.yaml: 384
// beads thrown across the slab boundary x = 20 mm, no fluid) against one
// process's. The 2-rank run's grains are one process's bit for bit (stepped
// by every rank, or decomposed in slabs and gathered after each step); each
// rank writes the grains whose centre lies in its slab as one piece of each
// snapshot, rank 0 the probes, summed from each rank's own grains (their
// sums' rounding against one process: mpi_probe_sums and below).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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
  // The grains decomposed, not only replicated: the pieces come from the gathered set.
  const std::string log = read_text(dir / "two.log");
  EXPECT_NE(log.find("the grains decomposed in 2 slabs along x"), std::string::npos) << log;
  EXPECT_NE(log.find("fdem run: grain exchange: "), std::string::npos) << log;

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
    std::array<double, 2> lowest{1.0, 1.0}, highest{-1.0, -1.0};  // x of each piece's grains
    for (int rank = 0; rank < 2; ++rank) {
      const auto& piece = two.arrays.at(snap.pieces[static_cast<std::size_t>(rank)]);
      const std::vector<double>& ids = piece.at("PointData id");
      const std::vector<double>& xyz = piece.at("Points Points");
      ASSERT_EQ(xyz.size(), 3 * ids.size());
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const auto id = static_cast<std::int64_t>(ids[i]);
        ++seen[id];
        // Where one process has it, bit for bit.
        lowest[static_cast<std::size_t>(rank)] = std::min(lowest[static_cast<std::size_t>(rank)], xyz[3 * i]);
        highest[static_cast<std::size_t>(rank)] = std::max(highest[static_cast<std::size_t>(rank)], xyz[3 * i]);
        ASSERT_TRUE(at.contains(id)) << "grain " << id << " is not in one process's snapshot " << s;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(xyz[3 * i + c], whole_xyz[3 * at[id] + c]) << "grain " << id;
        if (s == 0) first_owner[id] = rank;
        else if (first_owner.at(id) != rank) ++crossed;
      }
    }
    // Each piece is its rank's slab of the grains' cut (which follows the
    // grain count, so it need not be the box's half): rank 0's grains all
    // lie below rank 1's along x.
    EXPECT_LT(highest[0], lowest[1]) << "snapshot " << s << ": the pieces overlap along x";
    EXPECT_EQ(seen.size(), kGrains) << "snapshot " << s << ": every grain in some piece";
    for (const auto& [id, count] : seen) EXPECT_EQ(count, 1) << "snapshot " << s << ": grain " << id;
  }
  fmt::print("pieces: every grain exactly once over 5 snapshots; {} grain-snapshots in another slab than at t = 0\n",
             crossed);
  EXPECT_GT(crossed, 0u) << "the scene must move grains across the slab boundary";
}

TEST(MpiOutput, ProbesOfTwoRanksEqualOneProcessBitForBitAndProgressComesFromOneRank) {
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
  // The grains are those of one process bit for bit; the probes' sums are
  // summed per rank (mpi_runs.hpp says to what bound), the rest bit for bit.
  const double worst = mpi_test::expect_probes_within_sum_rounding(a, b, kGrains, 0.04);
  fmt::print("probes, 2 ranks against 1: sums within {:.3f} of their rounding bound, the rest bit for bit\n", worst);
}

}  // namespace
}  // namespace fdem

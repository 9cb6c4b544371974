// A snapshot written as pieces (one per MPI rank) and the probes summed over
// ranks, on one process: the grains a slab owns, the .pvtu naming the
// pieces read back by vtk_check.py (an XML + zlib reader written apart from
// fdem), and the probes of disjoint sets combined into the whole's.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/grain_ownership.hpp"
#include "io/probes.hpp"
#include "io/pvtu_writer.hpp"
#include "io/tests/scratch_files.hpp"
#include "io/vtu_writer.hpp"
#include "parallel/slab_partition.hpp"

// A namespace of its own: the executable compiles its files as one unit.
namespace fdem::pieces_test {
namespace {

namespace fs = std::filesystem;

// n grains in the lower half of a 0.1 x 0.1 x 0.4 m box (z in [0, 0.2)),
// spinning, numbered 0..n-1 as the DEM engine numbers them.
Particles spinning_grains(std::size_t n) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Particles p;
  for (std::size_t i = 0; i < n; ++i) {
    p.add(0.1 * unit(rng), 0.1 * unit(rng), 0.2 * unit(rng), 1e-3 * (1.0 + unit(rng)), 2500.0, unit(rng) - 0.5,
          unit(rng) - 0.5, -unit(rng));
    p.wx.push_back(unit(rng));
    p.wy.push_back(-unit(rng));
    p.wz.push_back(10.0 * unit(rng));
    p.id.push_back(static_cast<Index>(i));
  }
  return p;
}

// vtk_check.py's reading: its exit status, the pieces it opened in order,
// and per file "section name" -> values.
struct Read {
  int status = -1;
  std::vector<std::string> sources;
  std::map<std::string, std::map<std::string, std::vector<double>>> arrays;
};

Read vtk_check(const fs::path& file) {
  Read r;
  const fs::path out = file.parent_path() / "vtk_check.out";
  const std::string command = std::string(FDEM_PYTHON) + " " + FDEM_SOURCE_DIR + "/solver/io/tests/vtk_check.py " +
                              file.string() + " > " + out.string() + " 2>&1";
  r.status = std::system(command.c_str());
  std::ifstream in(out);
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    std::string kind, path, section, name;
    s >> kind;
    if (kind == "source") {
      s >> path >> name;
      r.sources.push_back(name);
    } else if (kind == "array") {
      int components = 0;
      s >> path >> section >> name >> components;
      auto& values = r.arrays[fs::path(path).filename().string()][section + " " + name];
      for (double v; s >> v;) values.push_back(v);
    }
  }
  return r;
}

TEST(GrainOwnership, EachGrainBelongsToTheSlabOfItsCentreAndTheSubsetKeepsItsArrays) {
  const Particles p = spinning_grains(500);
  const SlabPartition slabs(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.4), 4);  // z cut at 0.1, 0.2, 0.3
  std::vector<int> owners(p.size(), -1);
  std::size_t total = 0;
  for (int rank = 0; rank < 4; ++rank) {
    const std::vector<std::size_t> mine = owned_indices(p, slabs, rank);
    total += mine.size();
    EXPECT_TRUE(std::is_sorted(mine.begin(), mine.end()));
    for (std::size_t i : mine) {
      EXPECT_EQ(owners[i], -1) << "grain " << i << " owned twice";
      owners[i] = rank;
      EXPECT_GE(p.z[i], 0.1 * rank);
      EXPECT_LT(p.z[i], 0.1 * (rank + 1));
    }
    const Particles s = particle_subset(p, mine);
    ASSERT_EQ(s.size(), mine.size());
    ASSERT_EQ(s.wz.size(), mine.size());
    ASSERT_EQ(s.id.size(), mine.size());
    ASSERT_EQ(s.tx.size(), 0u);  // p holds no torques: none copied
    for (std::size_t k = 0; k < mine.size(); ++k) {
      EXPECT_EQ(s.x[k], p.x[mine[k]]);
      EXPECT_EQ(s.mass[k], p.mass[mine[k]]);
      EXPECT_EQ(s.wz[k], p.wz[mine[k]]);
      EXPECT_EQ(s.id[k], p.id[mine[k]]);
    }
  }
  EXPECT_EQ(total, p.size());
  EXPECT_TRUE(owned_indices(p, slabs, 3).empty());  // the grains fill z < 0.2 only
}

TEST(PvtuWriter, PiecesOfOneSnapshotReadBackAsTheWholeWithAnEmptyPieceAmongThem) {
  const fs::path dir = fresh_test_directory("test_pieces", "pvtu");
  const Particles p = spinning_grains(300);
  const SlabPartition slabs(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.4), 3);  // the last slab, z >= 0.267, holds none
  const ParticleArrays arrays = particle_arrays_of(p);
  ASSERT_TRUE(arrays.angular_velocity && arrays.id);
  std::vector<std::string> pieces;
  for (int rank = 0; rank < 3; ++rank) {
    const Particles mine = particle_subset(p, owned_indices(p, slabs, rank));
    pieces.push_back(piece_file_name("particles_000007", rank));
    // The snapshot's arrays, not the piece's own (the empty one has none).
    write_particles_vtu((dir / pieces.back()).string(), mine, 0.5, VtuEncoding::binary, arrays);
  }
  EXPECT_EQ(pieces[1], "particles_000007_rank0001.vtu");
  write_particles_pvtu((dir / "particles_000007.pvtu").string(), arrays, pieces);

  const Read r = vtk_check(dir / "particles_000007.pvtu");
  ASSERT_EQ(r.status, 0);  // every piece parses and holds the declared arrays
  EXPECT_EQ(r.sources, pieces);
  std::map<long, std::vector<double>> by_id;  // id -> x y z wx wy wz
  for (const std::string& piece : pieces) {
    const auto& a = r.arrays.at(piece);
    const auto &ids = a.at("PointData id"), &xyz = a.at("Points Points"), &w = a.at("PointData angular_velocity");
    for (std::size_t i = 0; i < ids.size(); ++i)
      by_id[static_cast<long>(ids[i])] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], w[3 * i], w[3 * i + 1], w[3 * i + 2]};
  }
  EXPECT_TRUE(r.arrays.at(pieces[2]).at("PointData id").empty());
  ASSERT_EQ(by_id.size(), p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    EXPECT_EQ(by_id.at(static_cast<long>(i)), (std::vector<double>{p.x[i], p.y[i], p.z[i], p.wx[i], p.wy[i], p.wz[i]}))
        << "grain " << i;
  fs::remove_all(dir);
}

TEST(VtkCheck, RejectsAPieceThatLacksAnArrayItsPvtuDeclares) {
  // The reader is what the MPI output tests trust: a piece written with its
  // own arrays (the empty one without angular_velocity) must fail it.
  const fs::path dir = fresh_test_directory("test_pieces", "pvtu_mismatch");
  const Particles p = spinning_grains(10);
  const std::vector<std::string> pieces{"a.vtu", "b.vtu"};
  write_particles_vtu((dir / "a.vtu").string(), p, 0.0);
  write_particles_vtu((dir / "b.vtu").string(), Particles{}, 0.0);  // its own arrays: none optional
  write_particles_pvtu((dir / "s.pvtu").string(), particle_arrays_of(p), pieces);
  EXPECT_NE(vtk_check(dir / "s.pvtu").status, 0);
  fs::remove((dir / "b.vtu"));
  EXPECT_NE(vtk_check(dir / "s.pvtu").status, 0) << "a missing piece";
  fs::remove_all(dir);
}

ProbeSums combined(const ProbeSums& a, const ProbeSums& b) {  // what sum_over_ranks does across ranks
  ProbeSums s;
  s.count = a.count + b.count;
  s.x = a.x + b.x;
  s.y = a.y + b.y;
  s.z = a.z + b.z;
  s.vx = a.vx + b.vx;
  s.vy = a.vy + b.vy;
  s.vz = a.vz + b.vz;
  s.kinetic_energy = a.kinetic_energy + b.kinetic_energy;
  s.max_speed_squared = std::max(a.max_speed_squared, b.max_speed_squared);
  s.min_z = std::min(a.min_z, b.min_z);
  s.max_z = std::max(a.max_z, b.max_z);
  return s;
}

TEST(Probes, SumsOfTwoDisjointSetsGiveTheWholeSetsValuesToTheRoundingOfTheSums) {
  const Particles p = spinning_grains(1000);
  const SlabPartition slabs(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.2), 2);
  const ProbeSums low = probe_sums(p, owned_indices(p, slabs, 0)), high = probe_sums(p, owned_indices(p, slabs, 1));
  ASSERT_GT(low.count, 0.0);
  ASSERT_GT(high.count, 0.0);
  const std::vector<std::string> all;  // every probe
  const std::vector<double> whole = probe_values(all, p), parts = probe_values(all, combined(low, high));
  // One process on one set gives what it always gave, and sum_over_ranks is the identity there.
  EXPECT_EQ(probe_values(all, sum_over_ranks(probe_sums(p))), whole);
  const std::vector<std::string> columns = probe_columns(all);
  ASSERT_EQ(whole.size(), columns.size());
  // Two orders of summing n terms differ by at most 2 (n - 1) eps sum|x_i|
  // (Higham 2002, eq. 4.4): a mean by 2 (n - 1) eps max|x_i|, and every
  // coordinate and velocity component of these grains lies in [-1, 1].
  const double bound = 2.0 * (1000 - 1) * DBL_EPSILON;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = columns[c];
    if (name == "count" || name == "max_speed" || name == "min_z" || name == "max_z")
      EXPECT_EQ(parts[c], whole[c]) << name;  // order-free
    else if (name == "kinetic_energy")
      EXPECT_LE(std::abs(parts[c] - whole[c]), bound * whole[c]) << name;
    else
      EXPECT_LE(std::abs(parts[c] - whole[c]), bound) << name;
  }
  // The closed forms on the whole set.
  double sum_z = 0.0, lowest = 1.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    sum_z += p.z[i];
    lowest = std::min(lowest, p.z[i]);
  }
  EXPECT_EQ(whole[0], 1000.0);
  EXPECT_EQ(whole[3], sum_z / 1000.0);  // mean_z, summed in index order
  EXPECT_EQ(whole[columns.size() - 2], lowest);
}

TEST(Probes, NoGrainsGiveACountOfZeroAndNaNMeansAndRange) {
  const std::vector<std::string> probes{"count", "mean_position", "z_range", "max_speed", "kinetic_energy"};
  const std::vector<double> v = probe_values(probes, sum_over_ranks(ProbeSums{}));
  ASSERT_EQ(v.size(), 8u);
  EXPECT_EQ(v[0], 0.0);
  for (std::size_t c : {1, 2, 3, 4, 5}) EXPECT_TRUE(std::isnan(v[c])) << c;
  EXPECT_EQ(v[6], 0.0);
  EXPECT_EQ(v[7], 0.0);
}

}  // namespace
}  // namespace fdem::pieces_test

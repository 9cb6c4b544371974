// The probes summed over MPI ranks (io/probes.hpp, sum_over_ranks): each of
// 2 ranks holds the grains of its own slab of one set, as a decomposed run
// whose ranks hold only their own grains does, and the combined probes must
// be the whole set's. Every rank runs every case (this is the MPI program,
// started by mpirun -n 2); the run fails when any rank fails.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cfloat>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/petsc_runtime.hpp"
#include "io/grain_ownership.hpp"
#include "io/probes.hpp"
#include "parallel/slab_partition.hpp"

namespace fdem {
namespace {

// 2000 grains in a 0.1 x 0.1 x 0.2 m box, drawn alike on every rank (fixed seed).
Particles grains() {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Particles p;
  for (int i = 0; i < 2000; ++i)
    p.add(0.1 * unit(rng), 0.1 * unit(rng), 0.2 * unit(rng), 1e-3 * (1.0 + unit(rng)), 2500.0, unit(rng) - 0.5,
          unit(rng) - 0.5, -unit(rng));
  return p;
}

TEST(ProbeSums, OfEachRanksOwnGrainsCombineToTheWholeSetsProbes) {
  ASSERT_EQ(mpi_ranks(), 2) << "run by mpirun -n 2";
  const Particles all = grains();
  const SlabPartition slabs(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.2), mpi_ranks());
  const Particles mine = particle_subset(all, owned_indices(all, slabs, mpi_rank()));
  ASSERT_GT(mine.size(), 0u);
  ASSERT_LT(mine.size(), all.size());
  const std::vector<std::string> every;  // all probes
  const std::vector<std::string> columns = probe_columns(every);
  const std::vector<double> whole = probe_values(every, all);
  const std::vector<double> combined = probe_values(every, sum_over_ranks(probe_sums(mine)));
  ASSERT_EQ(combined.size(), whole.size());
  // Two orders of summing n terms differ by at most 2 (n - 1) eps sum|x_i|
  // (Higham, Accuracy and Stability of Numerical Algorithms, 2002, eq. 4.4):
  // a mean by 2 (n - 1) eps max|x_i| (every coordinate and velocity
  // component here lies in [-1, 1]), the kinetic energy (positive terms) by
  // 2 (n - 1) eps of itself. Counts and extrema are order-free: equal.
  const double bound = 2.0 * (2000 - 1) * DBL_EPSILON;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = columns[c];
    if (name == "count" || name == "max_speed" || name == "min_z" || name == "max_z")
      EXPECT_EQ(combined[c], whole[c]) << name;
    else if (name == "kinetic_energy")
      EXPECT_LE(std::abs(combined[c] - whole[c]), bound * whole[c]) << name;
    else
      EXPECT_LE(std::abs(combined[c] - whole[c]), bound) << name;
  }
  EXPECT_EQ(combined[0], 2000.0);
}

TEST(ProbeSums, OfARankWithNoGrainsLeaveTheOthersUnchanged) {
  // Rank 1 holds none: the sums and extrema are rank 0's alone.
  const Particles all = grains();
  const Particles mine = mpi_rank() == 0 ? all : Particles{};
  const std::vector<std::string> every;
  EXPECT_EQ(probe_values(every, sum_over_ranks(probe_sums(mine))), probe_values(every, all));
}

}  // namespace
}  // namespace fdem

// Ghost exchange and migration (parallel/grain_exchange.hpp) against brute
// force, on the ranks mpirun gives (CI: 2). Every rank draws the same random
// grains, so each can compute by brute force which grains it must own and
// which it must hold as ghosts, and compare with what the exchange left it:
// by id, bit for bit (the exchange copies values, it computes none).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "core/petsc_runtime.hpp"
#include "parallel/grain_exchange.hpp"

namespace fdem {
namespace {

// N grains in a 1 x 0.2 x 0.2 m box (cut along x), ids 0..N-1.
Particles random_grains(std::size_t count, unsigned seed, bool rotation) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> along(0.0, 1.0), across(0.0, 0.2), size(0.005, 0.02), speed(-1.0, 1.0);
  Particles p;
  for (std::size_t i = 0; i < count; ++i) {
    p.add(along(random), across(random), across(random), size(random), 2500.0, speed(random), speed(random),
          speed(random));
    p.id.push_back(static_cast<Index>(i));
    if (rotation) {
      p.wx.push_back(speed(random));
      p.wy.push_back(speed(random));
      p.wz.push_back(speed(random));
      p.tx.push_back(0.0);
      p.ty.push_back(0.0);
      p.tz.push_back(0.0);
      p.inertia.push_back(0.1 * p.mass.back() * p.diameter.back() * p.diameter.back());
    }
  }
  return p;
}

struct Expected {
  std::set<Index> owned, ghosts;
};

// Brute force: owner by the slab of the centre; a ghost here when its owner
// is a neighbour and it lies within the cutoff of that owner's face towards us.
Expected brute_force(const Particles& all, const SlabPartition& slabs, int rank, double cutoff) {
  Expected e;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const int owner = slabs.owner(all.x[i], all.y[i], all.z[i]);
    if (owner == rank) {
      e.owned.insert(all.id[i]);
    } else if (owner == rank + 1 && all.x[i] - slabs.slab_lower(owner) < cutoff) {
      e.ghosts.insert(all.id[i]);
    } else if (owner == rank - 1 && slabs.slab_upper(owner) - all.x[i] < cutoff) {
      e.ghosts.insert(all.id[i]);
    }
  }
  return e;
}

// What this rank holds against the brute force, and every value against the
// whole set's grain of the same id.
void expect_matches(const Particles& local, const GrainExchange& exchange, const Particles& all, double cutoff) {
  const Expected e = brute_force(all, exchange.slabs(), exchange.rank(), cutoff);
  std::set<Index> owned, ghosts;
  ASSERT_EQ(exchange.ghost_mask().size(), local.size());
  for (std::size_t i = 0; i < local.size(); ++i) {
    if (i > 0) {
      ASSERT_LT(local.id[i - 1], local.id[i]) << "ascending ids, no duplicates";
    }
    (exchange.ghost_mask()[i] ? ghosts : owned).insert(local.id[i]);
    const auto k = static_cast<std::size_t>(local.id[i]);  // all holds id k at index k
    EXPECT_EQ(local.x[i], all.x[k]);
    EXPECT_EQ(local.y[i], all.y[k]);
    EXPECT_EQ(local.z[i], all.z[k]);
    EXPECT_EQ(local.vx[i], all.vx[k]);
    EXPECT_EQ(local.vz[i], all.vz[k]);
    EXPECT_EQ(local.diameter[i], all.diameter[k]);
    EXPECT_EQ(local.mass[i], all.mass[k]);
    if (!all.wx.empty()) {
      ASSERT_EQ(local.wx.size(), local.size());
      EXPECT_EQ(local.wy[i], all.wy[k]);
      EXPECT_EQ(local.inertia[i], all.inertia[k]);
    }
  }
  EXPECT_EQ(owned, e.owned) << "rank " << exchange.rank();
  EXPECT_EQ(ghosts, e.ghosts) << "rank " << exchange.rank();
  EXPECT_EQ(exchange.owned_count(), e.owned.size());
  EXPECT_EQ(exchange.ghost_count(), e.ghosts.size());
  double owned_total = static_cast<double>(owned.size());
  exchange.sum_over_ranks({&owned_total, 1});
  EXPECT_EQ(owned_total, static_cast<double>(all.size())) << "every grain owned once";
}

// A displacement of up to 0.02 m per axis (the cutoff: less than a slab),
// a function of the id, so every rank moves its copy of a grain alike.
void move(Particles& p, double phase) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double s = static_cast<double>(p.id[i]) + phase;
    p.x[i] += 0.02 * std::sin(1.7 * s);
    p.y[i] += 0.02 * std::cos(0.3 * s);
    p.vx[i] = std::sin(s);
    p.vz[i] = std::cos(s);
    if (!p.wx.empty()) p.wy[i] = std::sin(2.0 * s);
  }
}

class GrainExchangeTest : public ::testing::TestWithParam<bool> {};

TEST_P(GrainExchangeTest, GhostsAndMigrationMatchBruteForce) {
  const bool rotation = GetParam();
  const SlabPartition slabs(Vec3::Zero(), Vec3(1.0, 0.2, 0.2), mpi_ranks());
  const double cutoff = 0.06;  // ~ d_max + skin of a 2-6 mm grain at 1 m scale: many ghosts
  const Particles all0 = random_grains(3000, 42, rotation);
  Particles local = all0;
  GrainExchange exchange(slabs, rotation);
  exchange.set_cutoff(cutoff);
  exchange.redistribute(local);  // first call: this slab's share of the replicated set
  expect_matches(local, exchange, all0, cutoff);
  if (mpi_ranks() > 1) {
    EXPECT_GT(exchange.ghost_count(), 0u) << "the test must exercise ghosts";
  }

  // Moves, then a rebuild: migration and new ghosts (the whole set moved
  // the same way for the brute force).
  Particles all = all0;
  for (int round = 1; round <= 3; ++round) {
    move(all, round);
    move(local, round);
    exchange.redistribute(local);
    expect_matches(local, exchange, all, cutoff);
  }
  if (mpi_ranks() > 1) {
    double migrated = static_cast<double>(exchange.counters().migrated);
    exchange.sum_over_ranks({&migrated, 1});
    EXPECT_GT(migrated, 0.0) << "the test must exercise migration";
  }

  // A step between rebuilds: owned grains move, the ghosts take their
  // owners' new position and velocity from update_ghosts alone.
  for (std::size_t i = 0; i < local.size(); ++i)
    if (exchange.ghost_mask()[i] == 0) {
      const double s = static_cast<double>(local.id[i]);
      local.x[i] += 1e-4 * std::cos(s);
      local.vy[i] = -std::sin(s);
      if (rotation) local.wz[i] = std::cos(3.0 * s);
    } else {
      local.x[i] = -1.0;  // a ghost's own drift, to be overwritten
      local.vy[i] = 7.0;
      if (rotation) local.wz[i] = 7.0;
    }
  exchange.update_ghosts(local);
  for (std::size_t i = 0; i < local.size(); ++i) {
    const auto k = static_cast<std::size_t>(local.id[i]);
    const double s = static_cast<double>(local.id[i]);
    EXPECT_EQ(local.x[i], all.x[k] + 1e-4 * std::cos(s));
    EXPECT_EQ(local.vy[i], -std::sin(s));
    if (rotation) {
      EXPECT_EQ(local.wz[i], std::cos(3.0 * s));
    }
  }

  // gather_owned: the whole set, each grain once, in ascending id.
  const Particles gathered = exchange.gather_owned(local);
  ASSERT_EQ(gathered.size(), all.size());
  for (std::size_t k = 0; k < gathered.size(); ++k) {
    ASSERT_EQ(gathered.id[k], static_cast<Index>(k));
    EXPECT_EQ(gathered.y[k], all.y[k]);
    EXPECT_EQ(gathered.diameter[k], all.diameter[k]);
  }
}

INSTANTIATE_TEST_SUITE_P(Rotation, GrainExchangeTest, ::testing::Values(false, true));

TEST(GrainExchange, RefusesSlabsThinnerThanTheCutoff) {
  const SlabPartition slabs(Vec3::Zero(), Vec3(1.0, 0.2, 0.2), mpi_ranks());
  GrainExchange exchange(slabs, false);
  if (mpi_ranks() > 1) {
    EXPECT_THROW(exchange.set_cutoff(1.0 / mpi_ranks() + 1e-3), std::invalid_argument);
  }
  EXPECT_NO_THROW(exchange.set_cutoff(0.5 / mpi_ranks()));
}

// Scene P's case: every grain in the lower 0.4 of the box along the cut
// axis, which slabs of equal length give to the lower ranks alone.
// rebalance() moves the cut to the grains' quantiles; ownership and ghosts
// then follow the new boundaries (brute force on exchange.slabs()).
TEST(GrainExchange, RebalanceGivesABlockInOnePartEqualShares) {
  const int ranks = mpi_ranks();
  const SlabPartition slabs(Vec3::Zero(), Vec3(1.0, 0.2, 0.2), ranks);
  const double cutoff = 0.06;
  Particles all = random_grains(3000, 7, false);
  for (double& x : all.x) x *= 0.4;
  Particles local = all;
  GrainExchange exchange(slabs, false);
  exchange.set_cutoff(cutoff);
  // Distributed by the equal lengths first, then rebalanced over the ranks
  // (the histogram summed): each round moves every boundary at most into
  // its old neighbours, so ranks rounds reach the quantiles from any start.
  exchange.redistribute(local);
  expect_matches(local, exchange, all, cutoff);
  const double share = static_cast<double>(all.size()) / ranks;
  for (int round = 0; round < ranks; ++round) {
    exchange.rebalance(local);
    exchange.redistribute(local);
    expect_matches(local, exchange, all, cutoff);
  }
  double counts_most = static_cast<double>(exchange.owned_count());
  exchange.max_over_ranks({&counts_most, 1});
  // 2048 bins over 1 m, the grains spread evenly over 0.4 m: ~3 grains a
  // bin at a cut, interpolated within it; 3 % leaves the random spread room
  // (equal lengths give 3000 on rank 0 of 2: +100 %).
  EXPECT_LE(counts_most, share * 1.03) << "largest load of " << ranks << " ranks";
  // Balanced within the tolerance: the next rebuild keeps the cut (the
  // hysteresis), the grains stay where they are.
  const std::size_t migrated = exchange.counters().migrated;
  EXPECT_FALSE(exchange.rebalance(local));
  exchange.redistribute(local);
  EXPECT_EQ(exchange.counters().migrated, migrated);
  // Moves of up to 0.02 m (less than the cutoff) between rebuilds, with a
  // rebalance before each: ownership by the boundaries in force, every grain once.
  for (int round = 1; round <= 3; ++round) {
    move(all, round);
    move(local, round);
    exchange.rebalance(local);
    exchange.redistribute(local);
    expect_matches(local, exchange, all, cutoff);
  }
  if (ranks > 1) {
    double rebalances = static_cast<double>(exchange.counters().rebalances);
    exchange.max_over_ranks({&rebalances, 1});
    EXPECT_GE(rebalances, 1.0);
  }
}

// A lone grain cannot be split: one rank holds it whatever the cut, so
// rebalance() leaves the boundaries (no migration back and forth).
TEST(GrainExchange, RebalanceLeavesALoneGrainsCut) {
  const SlabPartition slabs(Vec3::Zero(), Vec3(1.0, 0.2, 0.2), mpi_ranks());
  Particles local = random_grains(1, 3, false);
  GrainExchange exchange(slabs, false);
  exchange.set_cutoff(0.06);
  EXPECT_FALSE(exchange.rebalance(local));
  exchange.redistribute(local);
  EXPECT_FALSE(exchange.rebalance(local));
  for (int b = 0; b <= mpi_ranks(); ++b) EXPECT_EQ(exchange.slabs().boundary(b), slabs.boundary(b));
}

}  // namespace
}  // namespace fdem

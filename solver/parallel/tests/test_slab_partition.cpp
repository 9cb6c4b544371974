#include "parallel/slab_partition.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace fdem {
namespace {

TEST(SlabPartition, CutsTheLongestAxisIntoEqualSlabs) {
  const SlabPartition slabs(Vec3(0.0, -0.1, 0.0), Vec3(0.1, 0.1, 0.25), 4);  // z longest
  EXPECT_EQ(slabs.axis(), 2);
  EXPECT_EQ(slabs.ranks(), 4);
  EXPECT_EQ(slabs.boundary(0), 0.0);
  EXPECT_EQ(slabs.boundary(4), 0.25);
  for (int r = 0; r < 4; ++r) EXPECT_NEAR(slabs.slab_upper(r) - slabs.slab_lower(r), 0.0625, 1e-15);
  EXPECT_EQ(SlabPartition(Vec3::Zero(), Vec3(1.0, 2.0, 1.0), 2).axis(), 1);
  EXPECT_EQ(SlabPartition(Vec3::Zero(), Vec3(1.0, 1.0, 1.0), 2).axis(), 0);  // ties: the first axis
}

TEST(SlabPartition, OwnerAgreesWithTheBoundariesItReports) {
  const SlabPartition slabs(Vec3(-0.3, 0.0, 0.0), Vec3(0.7, 0.1, 0.1), 3);  // x, boundaries not exact in binary
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> u(-0.4, 0.8);
  for (int k = 0; k < 10000; ++k) {
    const double c = u(random);
    const int r = slabs.owner(c, 0.05, 0.05);
    ASSERT_GE(r, 0);
    ASSERT_LT(r, 3);
    if (r > 0) {
      EXPECT_GE(c, slabs.slab_lower(r)) << c;
    }
    if (r < 2) {
      EXPECT_LT(c, slabs.slab_upper(r)) << c;
    }
  }
  // A point on an inner boundary belongs to the slab above it; the box's
  // ends and beyond to the first and last slab.
  for (int b = 1; b < 3; ++b) {
    EXPECT_EQ(slabs.owner_of_coordinate(slabs.boundary(b)), b);
    EXPECT_EQ(slabs.owner_of_coordinate(std::nextafter(slabs.boundary(b), -1.0)), b - 1);
  }
  EXPECT_EQ(slabs.owner_of_coordinate(-5.0), 0);
  EXPECT_EQ(slabs.owner_of_coordinate(0.7), 2);
  EXPECT_EQ(slabs.owner_of_coordinate(5.0), 2);
  EXPECT_EQ(slabs.owner(Vec3(0.1, 0.0, 0.0)), 1);
}

TEST(SlabPartition, NeighboursAreTheAdjacentSlabs) {
  const SlabPartition slabs(Vec3::Zero(), Vec3(1.0, 1.0, 3.0), 3);
  EXPECT_EQ(slabs.lower_neighbour(0), SlabPartition::kNoRank);
  EXPECT_EQ(slabs.upper_neighbour(0), 1);
  EXPECT_EQ(slabs.lower_neighbour(2), 1);
  EXPECT_EQ(slabs.upper_neighbour(2), SlabPartition::kNoRank);
  const SlabPartition one(Vec3::Zero(), Vec3(1.0, 1.0, 3.0), 1);
  EXPECT_EQ(one.owner(Vec3(0.5, 0.5, 2.0)), 0);
  EXPECT_EQ(one.lower_neighbour(0), SlabPartition::kNoRank);
  EXPECT_EQ(one.upper_neighbour(0), SlabPartition::kNoRank);
}

TEST(SlabPartition, RefusesNoRanksAndAFlatBox) {
  EXPECT_THROW(SlabPartition(Vec3::Zero(), Vec3::Ones(), 0), std::invalid_argument);
  EXPECT_THROW(SlabPartition(Vec3::Zero(), Vec3::Zero(), 2), std::invalid_argument);
}

// The histogram rebalanced() takes, of coordinates along the cut axis.
std::vector<double> histogram_of(const SlabPartition& slabs, const std::vector<double>& coordinates, int bins) {
  std::vector<double> h(static_cast<std::size_t>(bins), 0.0);
  for (double c : coordinates) h[static_cast<std::size_t>(slabs.bin_of_coordinate(c, bins))] += 1.0;
  return h;
}

// Scene P's case: a block of grains in the lower 0.1 m of a 0.25 m tall box
// (z cut), which equal lengths leave all on the lower slabs.
std::vector<double> block_in_lower_part(std::size_t count, double top) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> z(0.0, top);
  std::vector<double> c(count);
  for (double& v : c) v = z(random);
  return c;
}

TEST(SlabPartition, RebalancedCutsABlockIntoEqualShares) {
  const std::vector<double> block = block_in_lower_part(28224, 0.1);
  for (int ranks : {2, 3, 4}) {
    const SlabPartition equal(Vec3::Zero(), Vec3(0.1, 0.1, 0.25), ranks);
    const SlabPartition cut = equal.rebalanced(histogram_of(equal, block, 2048), 0.005, false);
    const std::vector<double> counts = cut.counts_of(block);
    const double share = static_cast<double>(block.size()) / ranks;
    // Uniform grains, 2048 bins: ~6 grains per bin at the cut over ~7000 per
    // slab, interpolated within the bin; 1 % leaves the random spread room.
    for (int r = 0; r < ranks; ++r) EXPECT_NEAR(counts[static_cast<std::size_t>(r)], share, 0.01 * share) << ranks;
    EXPECT_EQ(cut.boundary(0), 0.0);
    EXPECT_EQ(cut.boundary(ranks), 0.25);
    EXPECT_EQ(cut.axis(), 2);
    // The same input, the same boundaries (every rank computes them alone).
    const SlabPartition again = equal.rebalanced(histogram_of(equal, block, 2048), 0.005, false);
    for (int b = 0; b <= ranks; ++b) EXPECT_EQ(again.boundary(b), cut.boundary(b));
  }
}

TEST(SlabPartition, RebalancedKeepsSlabsThickAndBoundariesInsideTheirOldNeighbours) {
  // All grains in a 1 mm layer at the bottom: the quantiles lie within it,
  // thinner than the 20 mm minimum, so the slabs stack from the bottom at it.
  std::vector<double> layer(1000);
  for (std::size_t i = 0; i < layer.size(); ++i) layer[i] = 1e-6 * static_cast<double>(i);
  const double thick = 0.02;
  const SlabPartition equal(Vec3::Zero(), Vec3(0.1, 0.1, 0.25), 4);  // boundaries 0.0625, 0.125, 0.1875
  const SlabPartition free = equal.rebalanced(histogram_of(equal, layer, 2048), thick, false);
  for (int r = 0; r < 4; ++r) EXPECT_GE(free.slab_upper(r) - free.slab_lower(r), thick) << r;
  EXPECT_NEAR(free.boundary(1), thick, 1e-10);  // a hair over, for rounding
  EXPECT_NEAR(free.boundary(3), 3 * thick, 1e-10);
  // Within the old neighbours: boundary b in [old b-1 + thick, old b+1 - thick].
  const SlabPartition held = equal.rebalanced(histogram_of(equal, layer, 2048), thick, true);
  for (int b = 1; b < 4; ++b) {
    EXPECT_GE(held.boundary(b), equal.boundary(b - 1) + thick) << b;
    EXPECT_LE(held.boundary(b), equal.boundary(b + 1) - thick) << b;
    EXPECT_GE(held.boundary(b + 1) - held.boundary(b), thick) << b;
  }
  EXPECT_LT(held.boundary(2), equal.boundary(2));  // moved towards the grains
  // No grains: the boundaries stay.
  const SlabPartition empty = equal.rebalanced(std::vector<double>(64, 0.0), thick, true);
  for (int b = 0; b <= 4; ++b) EXPECT_EQ(empty.boundary(b), equal.boundary(b));
  EXPECT_THROW((void)equal.rebalanced(std::vector<double>(64, 1.0), 0.07, false), std::invalid_argument);  // 4 x 0.07 > 0.25
  EXPECT_THROW((void)equal.rebalanced({}, thick, false), std::invalid_argument);
}

// A checkpoint's cut (GrainExchange::restore_cut): the boundaries come back
// bit for bit, and a cut that does not fit the box or the rank count is refused.
TEST(SlabPartition, WithInnerBoundariesRestoresACutBitForBitAndRefusesOneThatDoesNotFit) {
  const SlabPartition equal(Vec3::Zero(), Vec3(0.1, 0.1, 0.25), 4);
  std::vector<double> layer(1000);
  for (std::size_t i = 0; i < layer.size(); ++i) layer[i] = 0.2 + 1e-5 * static_cast<double>(i);
  const SlabPartition cut = equal.rebalanced(histogram_of(equal, layer, 2048), 0.005, false);
  const std::vector<double> inner{cut.boundary(1), cut.boundary(2), cut.boundary(3)};
  const SlabPartition restored = equal.with_inner_boundaries(inner);
  for (int b = 0; b <= 4; ++b) EXPECT_EQ(restored.boundary(b), cut.boundary(b)) << b;
  EXPECT_EQ(restored.axis(), cut.axis());
  for (double z : {0.0, 0.201, 0.2049, 0.206, 0.25, 0.3}) EXPECT_EQ(restored.owner(0.0, 0.0, z), cut.owner(0.0, 0.0, z)) << z;
  EXPECT_THROW((void)equal.with_inner_boundaries(std::vector<double>{0.1, 0.2}), std::invalid_argument);  // 2 for 4 slabs
  EXPECT_THROW((void)equal.with_inner_boundaries(std::vector<double>{0.1, 0.1, 0.2}), std::invalid_argument);  // not ascending
  EXPECT_THROW((void)equal.with_inner_boundaries(std::vector<double>{0.1, 0.2, 0.25}), std::invalid_argument);  // on the face
  EXPECT_THROW((void)equal.with_inner_boundaries(std::vector<double>{0.0, 0.1, 0.2}), std::invalid_argument);
}

TEST(SlabPartition, BinsCoverTheBoxAndClampBeyondIt) {
  const SlabPartition slabs(Vec3::Zero(), Vec3(0.1, 0.1, 0.25), 2);
  EXPECT_EQ(slabs.bin_of_coordinate(0.0, 10), 0);
  EXPECT_EQ(slabs.bin_of_coordinate(0.024, 10), 0);
  EXPECT_EQ(slabs.bin_of_coordinate(0.026, 10), 1);
  EXPECT_EQ(slabs.bin_of_coordinate(0.25, 10), 9);
  EXPECT_EQ(slabs.bin_of_coordinate(-1.0, 10), 0);
  EXPECT_EQ(slabs.bin_of_coordinate(7.0, 10), 9);
  EXPECT_EQ(slabs.bin_of_coordinate(std::nan(""), 10), 0);
}

}  // namespace
}  // namespace fdem

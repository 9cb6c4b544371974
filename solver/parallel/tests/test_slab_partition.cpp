#include "parallel/slab_partition.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

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

}  // namespace
}  // namespace fdem

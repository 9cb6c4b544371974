// The O(N) Verlet list finds exactly the pairs of a brute-force O(N^2) search.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "dem/neighbour_list.hpp"

namespace fdem {
namespace {

std::vector<std::pair<Index, Index>> brute_force(const Particles& p, double skin) {
  std::vector<std::pair<Index, Index>> out;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (i == j) continue;
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], dz = p.z[j] - p.z[i];
      const double cut = 0.5 * (p.diameter[i] + p.diameter[j]) + skin;
      if (dx * dx + dy * dy + dz * dz < cut * cut) out.emplace_back(static_cast<Index>(i), static_cast<Index>(j));
    }
  return out;
}

Particles random_set(std::size_t n, double box, double d_min, double d_max, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, box), dia(d_min, d_max);
  Particles p;
  for (std::size_t i = 0; i < n; ++i) p.add(pos(rng), pos(rng), pos(rng), dia(rng), 2500.0);
  return p;
}

class NeighbourListVsBruteForce : public ::testing::TestWithParam<std::tuple<std::size_t, double, unsigned>> {};

TEST_P(NeighbourListVsBruteForce, SamePairsAsBruteForce) {
  const auto [n, box, seed] = GetParam();
  const Particles p = random_set(n, box, 1e-3, 3e-3, seed);
  const double skin = 0.5e-3;
  NeighbourList list;
  list.build(p, skin);
  std::vector<std::pair<Index, Index>> found;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (Index j : list.neighbours(i)) found.emplace_back(static_cast<Index>(i), j);
  auto expected = brute_force(p, skin);
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(found, expected);  // exact: same pairs, same order (i, ascending j)
  EXPECT_GT(expected.size(), 0u);
}

INSTANTIATE_TEST_SUITE_P(RandomSets, NeighbourListVsBruteForce,
                         ::testing::Values(std::make_tuple(std::size_t{500}, 0.03, 1u),    // dense
                                           std::make_tuple(std::size_t{2000}, 0.05, 2u),   // dense, larger
                                           std::make_tuple(std::size_t{600}, 0.05, 3u),    // sparse
                                           std::make_tuple(std::size_t{1000}, 0.02, 4u)));  // overlapping

TEST(NeighbourList, FarOutlierDoesNotBlowUpTheGrid) {
  Particles p = random_set(400, 0.02, 1e-3, 2e-3, 7);
  p.add(1e3, 1e3, 1e3, 1e-3, 2500.0);  // a lost grain a km away: grid coarsened, result still exact
  NeighbourList list;
  list.build(p, 0.5e-3);
  std::size_t count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) count += list.neighbours(i).size();
  EXPECT_EQ(count, brute_force(p, 0.5e-3).size());
}

TEST(NeighbourList, RebuildNeededOnlyPastHalfSkin) {
  Particles p = random_set(100, 0.02, 1e-3, 2e-3, 9);
  NeighbourList list;
  list.build(p, 1e-3);
  p.x[17] += 0.49e-3;
  EXPECT_FALSE(list.needs_rebuild(p));
  p.x[17] += 0.02e-3;
  EXPECT_TRUE(list.needs_rebuild(p));
}

}  // namespace
}  // namespace fdem

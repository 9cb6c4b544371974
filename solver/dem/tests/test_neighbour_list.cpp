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

// One grain moving alone closes its gaps by its own displacement: the list
// holds until that reaches the skin (the |d| < skin/2 test alone would
// rebuild at half of it).
TEST(NeighbourList, RebuildNeededOnlyWhenAGrainMovesASkinRelativeToTheRest) {
  Particles p = random_set(100, 0.02, 1e-3, 2e-3, 9);
  NeighbourList list;
  list.build(p, 1e-3);
  p.x[17] += 0.99e-3;
  EXPECT_FALSE(list.needs_rebuild(p));
  p.x[17] += 0.02e-3;
  EXPECT_TRUE(list.needs_rebuild(p));
}

// Two spheres just outside the list cutoff, carried by a common drift of
// several skins (which fails the |d| < skin/2 test) and closing on each
// other along x by 0.98 or 1.02 skins: the spread test must let the first go
// (they cannot touch: the gap left is 0.02 skin) and catch the second (they
// now overlap). A looser bound than sum_a spread_a^2 <= skin^2 fails here.
TEST(NeighbourList, SpreadTestIsExactAtTheSkin) {
  const double skin = 1e-3, ra = 1e-3, rb = 1.5e-3;
  for (const double closing : {0.98, 1.02}) {
    Particles p;
    p.add(0.0, 0.0, 0.0, 2 * ra, 2500.0);
    p.add(ra + rb + skin * (1.0 + 1e-9), 0.0, 0.0, 2 * rb, 2500.0);
    NeighbourList list;
    list.build(p, skin);
    ASSERT_EQ(list.entries(), 0u);
    const double drift[3] = {5 * skin, -3 * skin, 2 * skin};
    p.x[0] += drift[0] + 0.5 * closing * skin;
    p.x[1] += drift[0] - 0.5 * closing * skin;
    for (std::size_t i = 0; i < 2; ++i) {
      p.y[i] += drift[1];
      p.z[i] += drift[2];
    }
    const double gap = (p.x[1] - p.x[0]) - ra - rb;
    EXPECT_EQ(list.needs_rebuild(p), gap < 0.0) << "closing by " << closing << " skins, gap " << gap;
  }
}

// A cloud moving as one never needs a rebuild, however far it goes.
TEST(NeighbourList, UniformTranslationNeverNeedsRebuild) {
  Particles p = random_set(300, 0.02, 1e-3, 2e-3, 11);
  NeighbourList list;
  list.build(p, 0.5e-3);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] += 0.1;
    p.y[i] -= 0.03;
    p.z[i] += 0.2;
  }
  EXPECT_FALSE(list.needs_rebuild(p));
  p.z[5] += 0.5e-3;  // one grain moves a skin relative to the rest
  EXPECT_TRUE(list.needs_rebuild(p));
}

// Random drifts plus random relative jitter: whenever the list says it is
// still good, every pair in contact (or within skin - spread) is listed.
// The jitter half-width a is drawn per trial in [0.2, 0.36] skin, around
// the threshold 3 (2a)^2 = skin^2 (a = 0.289 skin), so about half the
// trials pass the spread test; the drift (1 to 4 skins per axis) fails the
// |d| < skin/2 test every time, so the spread test alone decides.
TEST(NeighbourList, ListStaysCompleteWhileTheSpreadTestPasses) {
  std::mt19937_64 rng(13);
  const double skin = 0.5e-3;
  std::uniform_real_distribution<double> drift(skin, 4 * skin), width(0.2 * skin, 0.36 * skin), unit(-1.0, 1.0);
  std::bernoulli_distribution sign(0.5);
  int kept = 0, rebuilt = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Particles p = random_set(800, 0.03, 1e-3, 3e-3, 100u + static_cast<unsigned>(trial));
    NeighbourList list;
    list.build(p, skin);
    double d[3];
    for (double& v : d) v = sign(rng) ? drift(rng) : -drift(rng);
    const double a = width(rng);
    for (std::size_t i = 0; i < p.size(); ++i) {
      p.x[i] += d[0] + a * unit(rng);
      p.y[i] += d[1] + a * unit(rng);
      p.z[i] += d[2] + a * unit(rng);
    }
    if (list.needs_rebuild(p)) {
      ++rebuilt;
      continue;
    }
    ++kept;
    for (const auto& [i, j] : brute_force(p, 0.0)) {  // every pair in contact now
      const auto row = list.neighbours(static_cast<std::size_t>(i));
      EXPECT_TRUE(std::binary_search(row.begin(), row.end(), j)) << "trial " << trial << ": pair " << i << "-" << j;
    }
  }
  EXPECT_GT(kept, 5);     // the spread test let lists live although every grain moved > skin/2 ...
  EXPECT_GT(rebuilt, 5);  // ... and refused others
}

}  // namespace
}  // namespace fdem

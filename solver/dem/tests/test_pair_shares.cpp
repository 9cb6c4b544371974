// The threaded pair pass's shares (pair_shares.hpp): the crossing pairs
// into a share are exactly the pairs of earlier rows that reach its grains,
// in pair order, and the cut balances the estimated work to within one
// row's. The pair pass's bits do not depend on either (test_dem_determinism
// checks that); its speed on two threads does, and a wrong crossing set
// would drop or double a force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "dem/pair_shares.hpp"

namespace fdem {
namespace {

// A half pair set over n rows: row i holds pairs (i, j) with j ascending
// in (i, i + reach], each kept with probability `density`.
struct HalfPairs {
  std::vector<Index> i, j, start;
  PairSet view() const { return {i.data(), j.data(), start.data(), i.size()}; }
};

HalfPairs random_pairs(Index n, Index reach, double density, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution keep(density);
  HalfPairs h;
  h.start.push_back(0);
  for (Index r = 0; r < n; ++r) {
    for (Index c = r + 1; c <= std::min(n - 1, r + reach); ++c)
      if (keep(rng)) {
        h.i.push_back(r);
        h.j.push_back(c);
      }
    h.start.push_back(static_cast<Index>(h.i.size()));
  }
  return h;
}

// Estimated work of share [begin, end): its pairs, contact_cost_in_pair_tests
// a touching pair of its rows, and its crossing pairs at the mean cost of a pair.
double share_work(const HalfPairs& h, const std::vector<Index>& touching_i, Index begin, Index end, double pair_cost) {
  double work = h.start[static_cast<std::size_t>(end)] - h.start[static_cast<std::size_t>(begin)];
  for (Index r : touching_i) work += (r >= begin && r < end) ? contact_cost_in_pair_tests : 0.0;
  for (std::size_t k = 0; k < h.i.size(); ++k) work += (h.i[k] < begin && h.j[k] >= begin && h.j[k] < end) ? pair_cost : 0.0;
  return work;
}

TEST(PairShares, CrossingPairsAreThePairsOfEarlierRowsIntoTheShareInPairOrder) {
  // Reaches from neighbours-only to a shuffled pack's (pairs spanning a third of the rows).
  for (const Index reach : {3, 40, 700}) {
    const HalfPairs h = random_pairs(2000, reach, 0.3, 7 + static_cast<unsigned>(reach));
    for (const std::size_t threads : {2u, 3u, 5u}) {
      PairShares shares;
      shares.cut(h.view(), 2000, threads, {});
      const auto rows = shares.first_rows();
      ASSERT_EQ(rows.size(), threads + 1);
      EXPECT_EQ(rows.front(), 0);
      EXPECT_EQ(rows.back(), 2000);
      for (std::size_t t = 0; t < threads; ++t) {
        const Index begin = rows[t], end = rows[t + 1];
        std::vector<Index> ci, cj, want_i, want_j;
        shares.crossing_pairs(h.view(), begin, end, ci, cj);
        for (std::size_t k = 0; k < h.i.size(); ++k)
          if (h.i[k] < begin && h.j[k] >= begin && h.j[k] < end) {
            want_i.push_back(h.i[k]);
            want_j.push_back(h.j[k]);
          }
        EXPECT_EQ(ci, want_i) << "reach " << reach << ", " << threads << " threads, share " << t;
        EXPECT_EQ(cj, want_j) << "reach " << reach << ", " << threads << " threads, share " << t;
        EXPECT_EQ(shares.count_crossing(h.view(), begin, end), want_i.size());
        if (t > 0 && reach >= 40) {
          EXPECT_GT(want_i.size(), 0u);  // the test exercises the walk
        }
      }
    }
  }
}

TEST(PairShares, CutBalancesPairsContactsAndCrossingPairsToWithinARow) {
  // Touching pairs crowd the first quarter of the rows (a bed's bottom): by
  // pairs alone the cut would sit at the middle; weighted, it moves down.
  const Index n = 4000;
  const HalfPairs h = random_pairs(n, 60, 0.2, 11);
  std::vector<Index> touching_i;
  for (std::size_t k = 0; k < h.i.size(); ++k)
    if (h.i[k] < n / 4 && k % 2 == 0) touching_i.push_back(h.i[k]);
  // The last pass's lists: two threads' touching rows, each ascending.
  std::vector<PairShareScratch> last(2);
  for (Index r : touching_i) last[r < n / 8 ? 0 : 1].touching_rows.push_back(r);
  const double total = static_cast<double>(h.i.size()) + contact_cost_in_pair_tests * static_cast<double>(touching_i.size());
  const double pair_cost = total / static_cast<double>(h.i.size());
  // The most work one row carries: the bound on how close a cut at rows can come.
  std::vector<double> row_work(static_cast<std::size_t>(n), 0.0);
  for (std::size_t k = 0; k < h.i.size(); ++k) row_work[static_cast<std::size_t>(h.i[k])] += 1.0;
  for (Index r : touching_i) row_work[static_cast<std::size_t>(r)] += contact_cost_in_pair_tests;
  const double row_max = *std::max_element(row_work.begin(), row_work.end());
  for (const std::size_t threads : {2u, 3u, 4u}) {
    PairShares shares;
    shares.cut(h.view(), static_cast<std::size_t>(n), threads, last);
    const auto rows = shares.first_rows();
    std::vector<double> work;
    for (std::size_t t = 0; t < threads; ++t) work.push_back(share_work(h, touching_i, rows[t], rows[t + 1], pair_cost));
    const auto [lo, hi] = std::minmax_element(work.begin(), work.end());
    // Two rounds of cuts: the crossing pairs are counted at the first
    // round's cut, so a share may also differ by the crossing pairs the
    // second round moved (a few rows' reach: another row's work or two).
    EXPECT_LT(*hi - *lo, 3.0 * row_max + 1.0) << threads << " threads: " << *lo << " .. " << *hi;
    EXPECT_LT(rows[1], n / 2 - 100) << "the contacts' weight moves the first cut below the middle";
  }
}

TEST(PairShares, BalancedOnlyWhileNoShareHoldsMoreThanOneAndAQuarterEqualBlocks) {
  const HalfPairs even = random_pairs(3000, 20, 0.3, 3);
  PairShares shares;
  shares.cut(even.view(), 3000, 2, {});
  EXPECT_TRUE(shares.balanced());
  // Every pair in the first tenth of the rows: share 1 takes ~95 % of the grains.
  const HalfPairs front = random_pairs(300, 20, 0.3, 3);
  HalfPairs padded = front;
  for (Index r = 300; r < 3000; ++r) padded.start.push_back(padded.start.back());
  shares.cut(padded.view(), 3000, 2, {});
  EXPECT_LT(shares.first_rows()[1], 300);
  EXPECT_FALSE(shares.balanced());
}

}  // namespace
}  // namespace fdem

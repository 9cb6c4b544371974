#pragma once
// The threaded pair pass's shares of a half pair set (DemEngine's
// half_pair_forces, dem_engine.cpp): the pairs (i, j > i) in row order are
// cut at grain rows into T contiguous shares, thread t taking the pairs of
// its rows and owning their grains: it alone writes their forces, so no
// thread waits for another and no force is summed in another order than
// on one thread. A pair (i, j) whose i lies in an earlier share and j in
// t's is a crossing pair: the earlier thread forms it for its i, and t
// forms it again for its j (its -F, in pair order).
//
// The cut balances estimated work, not rows: a pair tested counts one
// unit, a touching pair contact_cost_in_pair_tests more (the touching
// pairs counted in the last pass's rows: a bed's contacts change slowly),
// and a thread's crossing pairs, which it forms again, the mean cost of a
// pair. Where the cut falls moves work between threads, never a sum.
#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace fdem {

/// A touching pair's work counted in pair tests: its contact law and sums
/// against the distance test (callgrind, scene B: ~90 and ~25
/// instructions). The threaded pair pass splits its rows by this measure;
/// dem_steps and plume_dem_profile print it, and the benchmarks weigh pair
/// work by it (benchmarks/dem/plume_workload.py).
inline constexpr double contact_cost_in_pair_tests = 3.5;

/// Pairs (i, j > i) in row order (ascending (i, j)), and where each
/// grain's pairs start: start[i] .. start[i + 1], n + 1 values.
struct PairSet {
  const Index* i;
  const Index* j;
  const Index* start;
  std::size_t count;
  std::size_t size() const { return count; }
};

/// One thread's scratch in the pair pass, alone on its cache line: a
/// vector's end pointer is written at every push_back, and next to the
/// other threads' it would bounce between the cores (false sharing).
struct alignas(64) PairShareScratch {
  std::vector<Index> touching_rows;     // the i of each touching pair of its rows (ascending), for the next cut
  std::vector<Index> cross_i, cross_j;  // the crossing pairs into its grains, in pair order
};

class PairShares {
 public:
  /// Cuts the rows of `pairs` (over n grains) into `threads` shares of
  /// equal estimated work (header comment), the touching pairs counted
  /// from the first `threads` lists of `last_pass` (the pair pass before;
  /// none: the cut is by pairs alone). Cut once by each thread's own rows,
  /// then again with each share lightened by the crossing pairs it got.
  void cut(const PairSet& pairs, std::size_t n, std::size_t threads, std::span<const PairShareScratch> last_pass);

  /// first_rows()[t]: share t's first row; first_rows()[threads] = n.
  std::span<const Index> first_rows() const { return first_row_; }
  /// Whether no share holds more than 1.25 equal blocks of grains (the
  /// kick-drift may then take the shares as its blocks: DemEngine's grain_block).
  bool balanced() const { return balanced_; }

  /// visit(i, j) for the pairs of rows before `begin` whose j is in
  /// [begin, end), in pair order: the crossing pairs into the grains
  /// [begin, end). Walks back at most the cut set's largest j - i rows.
  template <class Visit>
  void for_each_crossing_pair(const PairSet& pairs, Index begin, Index end, Visit visit) const {
    for (auto r = static_cast<std::size_t>(std::max<Index>(0, begin - span_)); r < static_cast<std::size_t>(begin); ++r) {
      Index k = pairs.start[r + 1];
      if (k == pairs.start[r] || pairs.j[k - 1] < begin) continue;  // no pair of row r reaches these grains
      while (k > pairs.start[r] && pairs.j[k - 1] >= begin) --k;  // j ascends in a row: the run at its end
      for (; k < pairs.start[r + 1] && pairs.j[k] < end; ++k) visit(static_cast<Index>(r), pairs.j[k]);
    }
  }
  std::size_t count_crossing(const PairSet& pairs, Index begin, Index end) const;
  /// The crossing pairs into [begin, end) into (ci, cj), in pair order.
  void crossing_pairs(const PairSet& pairs, Index begin, Index end, std::vector<Index>& ci,
                      std::vector<Index>& cj) const;

 private:
  std::vector<Index> first_row_;
  Index span_ = 0;  // the cut set's largest j - i: a crossing pair's row lies at most that far before its share
  bool balanced_ = false;
};

}  // namespace fdem

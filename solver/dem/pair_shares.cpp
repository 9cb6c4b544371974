// The threaded pair pass's shares (see pair_shares.hpp).
#include "dem/pair_shares.hpp"

#include <algorithm>
#include <ranges>

namespace fdem {

void PairShares::cut(const PairSet& pairs, std::size_t n, std::size_t threads,
                     std::span<const PairShareScratch> last_pass) {
  first_row_.assign(threads + 1, 0);
  first_row_.back() = static_cast<Index>(n);
  const std::size_t lists = std::min(last_pass.size(), threads);
  // Touching pairs of the last pass with i below `row` (each list ascending).
  const auto touched_before = [&](Index row) {
    std::size_t count = 0;
    for (std::size_t s = 0; s < lists; ++s) {
      const std::vector<Index>& l = last_pass[s].touching_rows;
      count += static_cast<std::size_t>(std::lower_bound(l.begin(), l.end(), row) - l.begin());
    }
    return count;
  };
  const auto work_before = [&](std::size_t row) {
    return static_cast<double>(pairs.start[row]) +
           contact_cost_in_pair_tests * static_cast<double>(touched_before(static_cast<Index>(row)));
  };
  const double total = work_before(n);
  const double pair_cost = pairs.size() > 0 ? total / static_cast<double>(pairs.size()) : 1.0;
  Index span = 0;
#pragma omp simd reduction(max : span)
  for (std::size_t k = 0; k < pairs.size(); ++k) span = std::max(span, pairs.j[k] - pairs.i[k]);
  span_ = span;
  std::vector<double> crossing_work(threads, 0.0);
  const auto rows = std::views::iota(std::size_t{0}, n);
  for (int round = 0; round < 2; ++round) {
    double all_crossing = 0.0;
    for (double w : crossing_work) all_crossing += w;
    const double each = (total + all_crossing) / static_cast<double>(threads);
    double target = 0.0;
    for (std::size_t t = 1; t < threads; ++t) {
      target += each - crossing_work[t - 1];
      // The first row whose work before reaches the target (n if none).
      const auto first = std::ranges::partition_point(rows, [&](std::size_t r) { return work_before(r) < target; });
      first_row_[t] = std::max(static_cast<Index>(first - rows.begin()), first_row_[t - 1]);
    }
    if (round == 0)
      for (std::size_t t = 1; t < threads; ++t)
        crossing_work[t] = pair_cost * static_cast<double>(count_crossing(pairs, first_row_[t], first_row_[t + 1]));
  }
  balanced_ = true;
  for (std::size_t t = 0; t < threads; ++t)
    balanced_ &= 4 * static_cast<std::size_t>(first_row_[t + 1] - first_row_[t]) * threads <= 5 * n;
}

std::size_t PairShares::count_crossing(const PairSet& pairs, Index begin, Index end) const {
  std::size_t count = 0;
  for_each_crossing_pair(pairs, begin, end, [&count](Index, Index) { ++count; });
  return count;
}

void PairShares::crossing_pairs(const PairSet& pairs, Index begin, Index end, std::vector<Index>& ci,
                                std::vector<Index>& cj) const {
  ci.clear();
  cj.clear();
  for_each_crossing_pair(pairs, begin, end, [&](Index i, Index j) {
    ci.push_back(i);
    cj.push_back(j);
  });
}

}  // namespace fdem

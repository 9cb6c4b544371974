#include "parallel/slab_partition.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fdem {

SlabPartition::SlabPartition(const Vec3& lower_m, const Vec3& upper_m, int ranks) : ranks_(ranks) {
  if (ranks < 1) throw std::invalid_argument("SlabPartition: " + std::to_string(ranks) + " ranks (at least 1)");
  const Vec3 extent = upper_m - lower_m;
  axis_ = 0;
  for (int a = 1; a < 3; ++a)
    if (extent[a] > extent[axis_]) axis_ = a;
  const double lo = lower_m[axis_], hi = upper_m[axis_];
  if (!(hi > lo) || !std::isfinite(hi - lo))
    throw std::invalid_argument("SlabPartition: the box has no extent along its longest axis");
  boundaries_.resize(static_cast<std::size_t>(ranks) + 1);
  for (int b = 0; b <= ranks; ++b)
    boundaries_[static_cast<std::size_t>(b)] = lo + (hi - lo) * static_cast<double>(b) / static_cast<double>(ranks);
  boundaries_.back() = hi;  // exactly the box's face, whatever the rounding above
}

int SlabPartition::bin_of_coordinate(double c, int bins) const {
  const double lo = boundaries_.front(), hi = boundaries_.back();
  const double at = std::floor((c - lo) / (hi - lo) * static_cast<double>(bins));
  if (!(at >= 0.0)) return 0;  // below the box, or NaN
  return at >= static_cast<double>(bins) ? bins - 1 : static_cast<int>(at);
}

SlabPartition SlabPartition::rebalanced(std::span<const double> histogram, double min_thickness,
                                        bool within_neighbours) const {
  if (histogram.empty()) throw std::invalid_argument("SlabPartition::rebalanced: an empty histogram");
  const double lo = boundaries_.front(), hi = boundaries_.back();
  // A hair over min_thickness, so that slab_upper - slab_lower >= min_thickness
  // holds after the rounding of the sums below (GrainExchange::set_cutoff compares).
  const double thick = min_thickness * (1.0 + 1e-9);
  if (ranks_ > 1 && hi - lo < thick * static_cast<double>(ranks_))
    throw std::invalid_argument("SlabPartition::rebalanced: the box is shorter than ranks * min_thickness");
  SlabPartition out = *this;
  if (ranks_ == 1) return out;
  double total = 0.0;
  for (double n : histogram) total += n;
  const double width = (hi - lo) / static_cast<double>(histogram.size());
  std::size_t bin = 0;
  double below = 0.0;  // grains in the bins before `bin`
  for (int b = 1; b < ranks_; ++b) {
    double cut = boundaries_[static_cast<std::size_t>(b)];  // no grains: stay
    if (total > 0.0) {
      const double share = total * static_cast<double>(b) / static_cast<double>(ranks_);
      while (bin + 1 < histogram.size() && below + histogram[bin] < share) below += histogram[bin++];
      const double in_bin = histogram[bin];
      const double fraction = in_bin > 0.0 ? std::clamp((share - below) / in_bin, 0.0, 1.0) : 0.0;
      cut = lo + width * (static_cast<double>(bin) + fraction);
    }
    if (within_neighbours)
      cut = std::clamp(cut, boundaries_[static_cast<std::size_t>(b) - 1] + thick,
                       std::max(boundaries_[static_cast<std::size_t>(b) - 1] + thick,
                                boundaries_[static_cast<std::size_t>(b) + 1] - thick));
    // Room for this slab below and for the slabs still to come above.
    const double lowest = out.boundaries_[static_cast<std::size_t>(b) - 1] + thick;
    const double highest = hi - thick * static_cast<double>(ranks_ - b);
    out.boundaries_[static_cast<std::size_t>(b)] = std::clamp(cut, lowest, std::max(lowest, highest));
  }
  return out;
}

SlabPartition SlabPartition::with_inner_boundaries(std::span<const double> inner) const {
  if (inner.size() + 1 != static_cast<std::size_t>(ranks_))
    throw std::invalid_argument("SlabPartition: " + std::to_string(inner.size()) + " inner boundaries for " +
                                std::to_string(ranks_) + " slabs");
  SlabPartition out = *this;
  for (std::size_t b = 0; b < inner.size(); ++b) {
    if (!(inner[b] > out.boundaries_[b] && inner[b] < boundaries_.back()))
      throw std::invalid_argument("SlabPartition: inner boundary " + std::to_string(b + 1) +
                                  " is not above the one below it and inside the box");
    out.boundaries_[b + 1] = inner[b];
  }
  return out;
}

std::vector<double> SlabPartition::counts_of(std::span<const double> coordinates) const {
  std::vector<double> counts(static_cast<std::size_t>(ranks_), 0.0);
  for (double c : coordinates) counts[static_cast<std::size_t>(owner_of_coordinate(c))] += 1.0;
  return counts;
}

int SlabPartition::owner_of_coordinate(double c) const {
  // The number of inner boundaries at or below c: slab r is
  // [boundary(r), boundary(r+1)). A NaN compares below nothing and lands in
  // the last slab (the DEM stops on a non-finite grain anyway).
  const auto inner_begin = boundaries_.begin() + 1, inner_end = boundaries_.end() - 1;
  return static_cast<int>(std::upper_bound(inner_begin, inner_end, c) - inner_begin);
}

}  // namespace fdem

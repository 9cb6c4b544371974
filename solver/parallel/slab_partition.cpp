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

int SlabPartition::owner_of_coordinate(double c) const {
  // The number of inner boundaries at or below c: slab r is
  // [boundary(r), boundary(r+1)). A NaN compares below nothing and lands in
  // the last slab (the DEM stops on a non-finite grain anyway).
  const auto inner_begin = boundaries_.begin() + 1, inner_end = boundaries_.end() - 1;
  return static_cast<int>(std::upper_bound(inner_begin, inner_end, c) - inner_begin);
}

}  // namespace fdem

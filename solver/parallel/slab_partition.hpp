#pragma once
// The domain box cut into one slab per MPI rank along its longest axis
// (the simplest decomposition with only two neighbours per rank, as
// LIGGGHTS' `processors * * N` on a column): slab r holds the points whose
// coordinate c along the axis satisfies boundary(r) <= c < boundary(r+1),
// the first slab also every point below the box, the last also every point
// above it (a grain pushed past a wall by an overlap still has one owner).
//
// Pure geometry, no MPI: the DEM's ghost exchange and migration
// (parallel/grain_exchange.hpp) and the output's pieces ask it who owns a
// point; the same box and rank count give every rank the same answer, bit
// for bit (owner() compares against the boundaries it reports).
#include <vector>

#include "core/types.hpp"

namespace fdem {

class SlabPartition {
 public:
  /// No neighbour on that side (the box's end).
  static constexpr int kNoRank = -1;

  /// Throws std::invalid_argument for ranks < 1 or a box of no extent
  /// along its longest axis.
  SlabPartition(const Vec3& lower_m, const Vec3& upper_m, int ranks);

  int ranks() const { return ranks_; }
  /// The cut axis: 0 x, 1 y, 2 z (the longest; the first of equal ones).
  int axis() const { return axis_; }

  /// Coordinate of slab boundary b, 0 <= b <= ranks [m]: lower + b/ranks * length,
  /// the box's own lower and upper face for 0 and ranks.
  double boundary(int b) const { return boundaries_[static_cast<std::size_t>(b)]; }
  double slab_lower(int rank) const { return boundary(rank); }
  double slab_upper(int rank) const { return boundary(rank + 1); }

  /// The rank owning a point (its coordinate along axis() decides).
  int owner_of_coordinate(double c) const;
  int owner(double x, double y, double z) const { return owner_of_coordinate(axis_ == 0 ? x : axis_ == 1 ? y : z); }
  int owner(const Vec3& point) const { return owner_of_coordinate(point[axis_]); }

  /// The ranks of the slabs below and above `rank`, kNoRank at the box's ends.
  int lower_neighbour(int rank) const { return rank > 0 ? rank - 1 : kNoRank; }
  int upper_neighbour(int rank) const { return rank + 1 < ranks_ ? rank + 1 : kNoRank; }

 private:
  int ranks_ = 1;
  int axis_ = 0;
  std::vector<double> boundaries_;  // ranks + 1 values, ascending
};

}  // namespace fdem

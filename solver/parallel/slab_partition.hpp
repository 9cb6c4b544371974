#pragma once
// The domain box cut into one slab per MPI rank along its longest axis
// (the simplest decomposition with only two neighbours per rank, as
// LIGGGHTS' `processors * * N` on a column), at first into slabs of equal
// length, then (rebalanced()) at the quantiles of the grains' coordinate
// along the axis, so each slab holds about as many grains (a bed in the
// lower half of the box would otherwise leave the upper slabs empty, as
// LIGGGHTS' `balance` does for its cut planes): slab r holds the points whose
// coordinate c along the axis satisfies boundary(r) <= c < boundary(r+1),
// the first slab also every point below the box, the last also every point
// above it (a grain pushed past a wall by an overlap still has one owner).
//
// Only the grains follow these slabs: the fluid's rows are split by node
// index (PetscLinearSolver::owned_node_range), its velocity and pressure
// whole on every rank, and the coupling's per-element sums are completed in
// bands around each rank's slab and fluid layers that follow the cuts at
// every call (parallel/element_sums.hpp), so the cuts may move without the
// fluid noticing; the output's particle pieces are cut by a
// partition of equal lengths of their own (app/run_command.cpp), each grain
// in one piece whatever the DEM's cut.
//
// Pure geometry, no MPI: the DEM's ghost exchange and migration
// (parallel/grain_exchange.hpp) and the output's pieces ask it who owns a
// point; the same box and rank count give every rank the same answer, bit
// for bit (owner() compares against the boundaries it reports).
#include <span>
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

  /// Coordinate of slab boundary b, 0 <= b <= ranks [m]: lower + b/ranks * length
  /// as constructed, the box's own lower and upper face for 0 and ranks always.
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

  /// Bins of equal width over the box along axis() for rebalanced()'s
  /// histogram: the bin of coordinate c, points beyond the box in the end bins.
  int bin_of_coordinate(double c, int bins) const;

  /// The same box with its inner boundaries moved to the quantiles r/ranks
  /// of the grains counted in `histogram` (counts per bin of
  /// bin_of_coordinate(c, histogram.size()); within a bin the grains taken as
  /// spread evenly), then held so that every slab is at least
  /// `min_thickness` [m] thick and, with `within_neighbours`, every new
  /// boundary b lies at least min_thickness inside the old slabs b-1 and b
  /// (so a grain that moved less than min_thickness since it was placed by
  /// the old boundaries is owned by its old slab or a neighbour: migration
  /// stays between neighbours). The boundaries only approach the quantiles
  /// as far as these allow; a later call goes on. The same inputs give
  /// every rank the same boundaries, bit for bit. Throws
  /// std::invalid_argument for an empty histogram or a box shorter than
  /// ranks * min_thickness.
  SlabPartition rebalanced(std::span<const double> histogram, double min_thickness, bool within_neighbours) const;

  /// The same box with its inner boundaries 1..ranks-1 set to `inner` (a
  /// checkpoint's cut, as boundary() reported it: bit for bit). Throws
  /// std::invalid_argument unless there are ranks - 1 of them, ascending,
  /// inside the box.
  SlabPartition with_inner_boundaries(std::span<const double> inner) const;

  /// Grains per slab of `coordinates` (along axis()): the load a set of boundaries gives.
  std::vector<double> counts_of(std::span<const double> coordinates) const;

 private:
  int ranks_ = 1;
  int axis_ = 0;
  std::vector<double> boundaries_;  // ranks + 1 values, ascending
};

}  // namespace fdem

#pragma once
// Verlet neighbour list with a skin, built in O(N) from a compact cell grid
// over the particles' bounding box (cell_grid.hpp).
//
// Full list: particle i lists every j != i with |x_i - x_j| < r_i + r_j + skin,
// ascending in j. Each pair appears twice (i->j, j->i) so a thread owning i
// writes only i's force: no atomics, and the result does not depend on the
// number of threads.
//
// Rebuild test: a pair not listed was at least skin apart (surface to
// surface) at the build, so the list stays complete while no pair's
// *relative* displacement exceeds the skin. Two sufficient bounds, either
// one enough: every particle moved less than skin/2 (the LAMMPS/LIGGGHTS
// test), or the displacements' spread per axis (max - min over particles,
// r_a) satisfies r_x^2 + r_y^2 + r_z^2 <= skin^2, since
// |d_i - d_j|^2 = sum_a (d_ia - d_ja)^2 <= sum_a r_a^2. The second makes the
// test Galilean invariant: a block falling as one never rebuilds its list.
// Walls are not in the list (each particle tests the box planes directly).
#include <cstddef>
#include <span>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "dem/cell_grid.hpp"

namespace fdem {

class NeighbourList {
 public:
  void build(const Particles& p, double skin_m);
  bool needs_rebuild(const Particles& p) const;

  /// The rebuild test above, from the displacements since the last build:
  /// the largest squared norm and the per-axis spread (max - min).
  static bool skin_exceeded(double skin_m, double max_displacement2, double spread_x, double spread_y,
                            double spread_z) {
    const double skin2 = skin_m * skin_m;
    return 4.0 * max_displacement2 > skin2 &&
           spread_x * spread_x + spread_y * spread_y + spread_z * spread_z > skin2;
  }

  std::span<const Index> neighbours(std::size_t i) const {
    return {indices_.data() + offsets_[i], indices_.data() + offsets_[i + 1]};
  }
  const std::vector<Index>& offsets() const { return offsets_; }
  const std::vector<Index>& indices() const { return indices_; }
  std::size_t entries() const { return indices_.size(); }
  double skin() const { return skin_; }
  /// Particles with at least one list entry, ascending (the pair loop skips
  /// the rest: most of a dilute cloud).
  const std::vector<Index>& particles_with_neighbours() const { return listed_; }
  std::size_t builds() const { return builds_; }
  /// Positions at the last build (for a displacement check fused into another loop).
  const GrainArray& reference_x() const { return x0_; }
  const GrainArray& reference_y() const { return y0_; }
  const GrainArray& reference_z() const { return z0_; }

 private:
  double skin_ = 0.0;
  std::size_t builds_ = 0;
  GrainArray x0_, y0_, z0_;              // positions at the last build
  std::vector<Index> offsets_, indices_, listed_;
  CellGrid grid_;  // kept between builds for its storage
  GrainArray slot_x_, slot_y_, slot_z_, slot_r_;  // centres and radii in the grid's slot order
  // Build scratch, one per thread, each alone on its cache line (the end
  // pointer written at every push_back would otherwise be shared).
  struct alignas(64) ThreadRows {
    std::vector<Index> rows;
    std::vector<Index> found;  // one row's candidates, compacted
  };
  std::vector<ThreadRows> thread_rows_;
};

}  // namespace fdem

#pragma once
// Verlet neighbour list with a skin, built in O(N) from a compact cell grid
// over the particles' bounding box (not the whole domain: a 20x20x40 mm
// block in a 100x100x250 mm box costs cells only where the grains are).
//
// Full list: particle i lists every j != i with |x_i - x_j| < r_i + r_j + skin,
// ascending in j. Each pair appears twice (i->j, j->i) so a thread owning i
// writes only i's force: no atomics, and the result does not depend on the
// number of threads. Rebuild when some particle has moved more than skin/2
// since the last build (then no pair can have come into contact unseen).
#include <cstddef>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "dem/particles.hpp"

namespace fdem {

class NeighbourList {
 public:
  void build(const Particles& p, double skin_m);
  bool needs_rebuild(const Particles& p) const;

  std::span<const Index> neighbours(std::size_t i) const {
    return {indices_.data() + offsets_[i], indices_.data() + offsets_[i + 1]};
  }
  const std::vector<Index>& offsets() const { return offsets_; }
  const std::vector<Index>& indices() const { return indices_; }
  std::size_t entries() const { return indices_.size(); }
  double skin() const { return skin_; }
  std::size_t builds() const { return builds_; }
  /// Positions at the last build (for a displacement check fused into another loop).
  const std::vector<double>& reference_x() const { return x0_; }
  const std::vector<double>& reference_y() const { return y0_; }
  const std::vector<double>& reference_z() const { return z0_; }

 private:
  double skin_ = 0.0;
  std::size_t builds_ = 0;
  std::vector<double> x0_, y0_, z0_;     // positions at the last build
  std::vector<Index> offsets_, indices_;
  std::vector<Index> cell_start_, cell_particles_, cell_of_;
};

}  // namespace fdem

#pragma once
// The grains within a radius of a box face, and those outside the box, found
// after the fused kick-drift (DemEngine's lean step) without testing every
// grain: a grain whose gap to face f (centre to plane, less its radius) was
// at least reach[f] at the list build is still a radius or more inside
// while the grains moved towards f by less than that since (the per-axis
// displacement extremes bound every grain's move), so it is neither lost
// nor near a wall. The candidates are refiltered from the build positions,
// with reserve, when a face's approach outgrows its reach. The remaining
// grains get the fused pass's expressions, so the outside count and the
// near set are exact.
#include <cstddef>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "dem/neighbour_list.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// The box's planes as six numbers, and the two tests every grain gets
/// against them: here, in the engine's fused pass and in its wall mask (one
/// expression each, so all give the same answers). Branch-free, for
/// vector loops.
struct BoxFaces {
  double lx, ly, lz, hx, hy, hz;
  explicit BoxFaces(const Box& box)
      : lx(box.lower.x()), ly(box.lower.y()), lz(box.lower.z()), hx(box.upper.x()), hy(box.upper.y()),
        hz(box.upper.z()) {}
  /// The centre in the box (faces included).
  bool contains(double x, double y, double z) const {
    return (x >= lx) & (x <= hx) & (y >= ly) & (y <= hy) & (z >= lz) & (z <= hz);
  }
  /// The centre closer than r to a face's plane (a grain of radius r touches it).
  bool near_face(double x, double y, double z, double r) const {
    return (x - lx < r) | (hx - x < r) | (y - ly < r) | (hy - y < r) | (z - lz < r) | (hz - z < r);
  }
};

class NearWallGrains {
 public:
  static constexpr int faces = 6;  // x_min, x_max, y_min, y_max, z_min, z_max (scene FaceBoundary order)

  /// A list build or a load: the candidates are refiltered at the next scan.
  void invalidate() { stale_ = true; }

  struct Scan {
    std::size_t outside = 0;  // grains outside the box
    std::size_t near = 0;     // grains within a radius of a face (grains())
  };
  /// The grains near a face and the outside count at p's positions.
  /// lowest, highest: the per-axis extremes of the displacements since the
  /// list build; test_all: a non-finite grain escaped them (a blown-up
  /// run), so every grain is tested, and it counts as outside. Scans in
  /// shares on threads above `parallel_min` candidates.
  Scan scan(const Particles& p, const NeighbourList& list, const Box& domain, const double (&lowest)[3],
            const double (&highest)[3], bool test_all, std::ptrdiff_t parallel_min);
  /// The last scan's near grains, ascending.
  const std::vector<Index>& grains() const { return near_; }

 private:
  void filter_candidates(const Particles& p, const NeighbourList& list, const Box& domain,
                         const double (&approach)[faces]);

  std::vector<Index> candidates_, near_;
  double reach_[faces] = {};
  double rounding_ = 0.0;
  bool stale_ = true;
  std::vector<std::size_t> found_;  // near grains found per thread
};

}  // namespace fdem

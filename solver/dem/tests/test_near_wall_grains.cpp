// The grains near a box face (near_wall_grains.hpp) are found without
// testing every grain: only those whose gap at the list build was within a
// reach of a face. A grain it wrongly left out would go through a wall (no
// wall force) or leave the box uncounted; checked here against a test of
// every grain, as the grains drift further from their build positions
// (past the first reaches, so the candidates are refiltered), on one and
// on two threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "dem/near_wall_grains.hpp"
#include "dem/neighbour_list.hpp"

namespace fdem {
namespace {

constexpr double kEdge = 0.01;  // box [0, 10 mm]^3

Box unit_box() { return {Vec3::Zero(), Vec3(kEdge, kEdge, kEdge)}; }

// 3000 grains of 0.8-1.2 mm, centres anywhere a fifth of a radius inside
// the box: about a fifth of them overlap a face.
Particles grains_in_box() {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> diameter(0.8e-3, 1.2e-3), where(0.0, 1.0);
  Particles p;
  for (int k = 0; k < 3000; ++k) {
    const double d = diameter(rng), inset = 0.1 * d;
    const auto at = [&] { return inset + (kEdge - 2.0 * inset) * where(rng); };
    const double x = at(), y = at(), z = at();
    p.add(x, y, z, d, 2500.0);
  }
  return p;
}

struct BruteForce {
  std::vector<Index> near;
  std::size_t outside = 0;
};

BruteForce every_grain(const Particles& p, const Box& box) {
  BruteForce b;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = 0.5 * p.diameter[i];
    const Vec3 x(p.x[i], p.y[i], p.z[i]);
    bool inside = true, near = false;
    for (int a = 0; a < 3; ++a) {
      inside = inside && x[a] >= box.lower[a] && x[a] <= box.upper[a];
      near = near || x[a] - box.lower[a] < r || box.upper[a] - x[a] < r;
    }
    if (!inside) ++b.outside;
    if (near) b.near.push_back(static_cast<Index>(i));
  }
  return b;
}

// Drifts the grains by `amplitude` in random directions from the build
// positions; the per-axis displacement extremes into lowest / highest.
void drift(Particles& p, const NeighbourList& list, double amplitude, std::mt19937_64& rng, double (&lowest)[3],
           double (&highest)[3]) {
  std::uniform_real_distribution<double> step(-amplitude, amplitude);
  for (int a = 0; a < 3; ++a) {
    lowest[a] = std::numeric_limits<double>::infinity();
    highest[a] = -std::numeric_limits<double>::infinity();
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] = list.reference_x()[i] + step(rng);
    p.y[i] = list.reference_y()[i] + step(rng);
    p.z[i] = list.reference_z()[i] + step(rng);
    const double d[3] = {p.x[i] - list.reference_x()[i], p.y[i] - list.reference_y()[i],
                         p.z[i] - list.reference_z()[i]};
    for (int a = 0; a < 3; ++a) {
      lowest[a] = std::min(lowest[a], d[a]);
      highest[a] = std::max(highest[a], d[a]);
    }
  }
}

void expect_exact_scans(int threads) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  Particles p = grains_in_box();
  NeighbourList list;
  list.build(p, 0.2e-3);  // reaches start at half the skin: 0.1 mm
  NearWallGrains walls;
  walls.invalidate();
  std::mt19937_64 rng(23);
  std::size_t outside_seen = 0;
  // From within the first reach to well past it (refiltered), some grains out of the box.
  for (const double amplitude : {0.02e-3, 0.05e-3, 0.15e-3, 0.4e-3, 0.3e-3, 1.0e-3}) {
    double lowest[3], highest[3];
    drift(p, list, amplitude, rng, lowest, highest);
    const NearWallGrains::Scan scan = walls.scan(p, list, unit_box(), lowest, highest, false, 100);
    const BruteForce want = every_grain(p, unit_box());
    EXPECT_EQ(walls.grains(), want.near) << "amplitude " << amplitude << ", " << threads << " threads";
    EXPECT_EQ(scan.near, want.near.size());
    EXPECT_EQ(scan.outside, want.outside) << "amplitude " << amplitude;
    EXPECT_GT(want.near.size(), 300u);  // a fifth of the grains lie within a radius of some face
    outside_seen += want.outside;
  }
  EXPECT_GT(outside_seen, 0u) << "the test moves grains out of the box";
  omp_set_num_threads(saved);
}

TEST(NearWallGrains, ScanFindsExactlyTheGrainsNearAFaceAndThoseOutsideOnOneThread) { expect_exact_scans(1); }

TEST(NearWallGrains, ScanInSharesOnTwoThreadsFindsTheSameAscendingSet) { expect_exact_scans(2); }

// A non-finite grain escapes the displacement extremes: the scan of every
// grain counts it outside (so the engine's rebuild removes or stops it).
TEST(NearWallGrains, ANonFiniteGrainIsCountedOutsideWhenEveryGrainIsTested) {
  Particles p = grains_in_box();
  NeighbourList list;
  list.build(p, 0.2e-3);
  NearWallGrains walls;
  const double zero[3] = {0.0, 0.0, 0.0};
  const std::size_t near_before = walls.scan(p, list, unit_box(), zero, zero, false, 100).near;
  p.x[1234] = std::numeric_limits<double>::quiet_NaN();
  const NearWallGrains::Scan scan = walls.scan(p, list, unit_box(), zero, zero, true, 100);
  EXPECT_EQ(scan.outside, 1u);
  EXPECT_EQ(scan.near, every_grain(p, unit_box()).near.size());
  EXPECT_GT(near_before, 0u);
}

}  // namespace
}  // namespace fdem

// The plume metrics (plume_metrics.hpp) on synthetic clouds whose values are
// known in closed form: the definitions the study's gates rest on.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "plume_metrics.hpp"

namespace fdem::plume {
namespace {

// The paper's block: 28 x 28 x 36 lattice sites filling [40, 60]^2 x [180, 220] mm
// (shared/anchors/liggghts gen_scenes.py P), equal grains.
Particles lattice_block(double d_m) {
  Particles p;
  for (int k = 0; k < 36; ++k)
    for (int j = 0; j < 28; ++j)
      for (int i = 0; i < 28; ++i)
        p.add(0.040 + (i + 0.5) * 0.020 / 28, 0.040 + (j + 0.5) * 0.020 / 28, 0.180 + (k + 0.5) * 0.040 / 36, d_m,
              2170.0);
  return p;
}

const PlumeGeometry kPaperGeometry{0.05, 0.05, 0.220};

TEST(PlumeMetrics, Quantile_MatchesLinearInterpolationOfOrderStatistics) {
  const std::vector<double> v{5.0, 1.0, 4.0, 2.0, 3.0};
  EXPECT_DOUBLE_EQ(quantile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantile(v, 1.0), 5.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.05), 1.2);  // position 0.05 * 4 = 0.2 between 1 and 2 (numpy: 1.2)
}

TEST(PlumeMetrics, BlockAtRest_MetricsMatchClosedForm) {
  const Particles p = lattice_block(309e-6);
  const PlumeMetrics m = measure_plume(p, kPaperGeometry, {}, 0.0);
  // Centre of mass of a uniform block: its mid-height, 20 mm below the top.
  EXPECT_NEAR(m.centroid_depth_m, 0.020, 1e-12);  // round-off of a 28224-term sum of ~0.2 m values
  // Lattice of n sites with spacing h: mean dx^2 = h^2 (n^2 - 1) / 12, twice for x and y.
  const double h = 0.020 / 28;
  EXPECT_NEAR(m.radial_spread_m, std::sqrt(2.0 * h * h * (28.0 * 28.0 - 1.0) / 12.0), 1e-12);
  // 5 % quantile of 36 equal layers: position 0.05 (N - 1) falls in layer 1
  // (0-based), so the front is the second layer's centre, plus a fraction of
  // the layer spacing: type-7 interpolation between layers 1 and 2 is not
  // needed as both order statistics lie in layer 1 (784 grains per layer,
  // position 1411.15 < 2 * 784).
  EXPECT_NEAR(m.front_depth_m, 0.220 - (0.180 + 1.5 * 0.040 / 36), 1e-12);
  // Core and ring span the same layers: no dome.
  EXPECT_NEAR(m.dome_shape, 0.0, 1e-10);
  EXPECT_EQ(m.peak_fluid_speed_mps, 0.0);
}

TEST(PlumeMetrics, RigidFall_DepthsGrowByTheFallAndShapeIsUnchanged) {
  Particles p = lattice_block(309e-6);
  const PlumeMetrics before = measure_plume(p, kPaperGeometry, {}, 0.0);
  for (double& z : p.z) z -= 0.0375;
  const PlumeMetrics after = measure_plume(p, kPaperGeometry, {}, 1.0);
  EXPECT_NEAR(after.front_depth_m - before.front_depth_m, 0.0375, 1e-12);
  EXPECT_NEAR(after.centroid_depth_m - before.centroid_depth_m, 0.0375, 1e-12);
  EXPECT_DOUBLE_EQ(after.radial_spread_m, before.radial_spread_m);
  EXPECT_NEAR(after.dome_shape, 0.0, 1e-10);
  EXPECT_DOUBLE_EQ(after.t_s, 1.0);
}

TEST(PlumeMetrics, CapPointingDown_DomeShapeIsPositiveAndMatchesItsDefinition) {
  // Lower the centre by c (R^2 - r^2): the core runs ahead of the ring (dome_shape > 0).
  Particles p = lattice_block(309e-6);
  const double c = 20.0;  // [1/m]: 2 mm lower at the block's corner radius 10 mm
  std::vector<double> r2(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = p.x[i] - 0.05, dy = p.y[i] - 0.05;
    r2[i] = dx * dx + dy * dy;
    p.z[i] -= c * (0.01 * 0.01 - r2[i]);  // centre lowered most, corners not at all
  }
  const PlumeMetrics m = measure_plume(p, kPaperGeometry, {}, 0.0);
  EXPECT_GT(m.dome_shape, 0.0);
  // Direct evaluation of the definition: split at the median r.
  std::vector<double> r(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) r[i] = std::sqrt(r2[i]);
  const double r_med = quantile(r, 0.5);
  double zc = 0, zr = 0, nc = 0, nr = 0;
  for (std::size_t i = 0; i < p.size(); ++i) (r[i] <= r_med ? (zc += p.z[i], nc += 1) : (zr += p.z[i], nr += 1));
  EXPECT_NEAR(m.dome_shape, (zr / nr - zc / nc) / m.radial_spread_m, 1e-12);
}

TEST(PlumeMetrics, RadialSpread_IsTheSecondMomentAboutTheAxis) {
  Particles p;
  p.add(0.05 + 0.003, 0.05, 0.1, 1e-3, 2170.0);
  p.add(0.05, 0.05 - 0.004, 0.1, 1e-3, 2170.0);
  const PlumeMetrics m = measure_plume(p, kPaperGeometry, {}, 0.0);
  EXPECT_NEAR(m.radial_spread_m, std::sqrt((9e-6 + 16e-6) / 2.0), 1e-15);
}

TEST(PlumeMetrics, PeakFluidSpeed_IsTheLargestNodalSpeed) {
  const std::vector<double> u{0.0, 0.0, 0.0, 3e-3, -4e-3, 0.0, 1e-3, 1e-3, 1e-3};
  EXPECT_DOUBLE_EQ(peak_speed(u), 5e-3);
}

TEST(PlumeMetrics, CentroidDepth_IsMassWeighted) {
  Particles p;
  p.add(0.05, 0.05, 0.200, 2e-3, 2170.0);  // 8 times the mass of the other
  p.add(0.05, 0.05, 0.110, 1e-3, 2170.0);
  const PlumeMetrics m = measure_plume(p, kPaperGeometry, {}, 0.0);
  EXPECT_NEAR(m.centroid_depth_m, 0.220 - (8.0 * 0.200 + 0.110) / 9.0, 1e-14);
}

}  // namespace
}  // namespace fdem::plume

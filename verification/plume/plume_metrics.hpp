#pragma once
// What the salt plume study measures (paper Sect. 4.4, Fig. 24-25): the shape
// of the falling grain cloud and the speed of the flow it drives. The paper
// shows the dome only as pictures; these numbers make it a gate.
//
// Every depth is measured downward from the top face of the initial block
// (`PlumeGeometry::top_z_m`, z = 220 mm in the paper's setup), so it is 0 at
// the top of the block and grows as the cloud falls. Horizontal distances are
// from the column axis (the vertical line through the domain's x-y centre).
//
//   front_depth_m     depth of the 5 % quantile of the grain centres' z: the
//                     level above which 95 % of the grains lie. A quantile,
//                     not the lowest grain, so one fast grain does not move it.
//   centroid_depth_m  depth of the centre of mass (mass-weighted mean z).
//   radial_spread_m   sqrt(mean r^2), r = horizontal distance of a grain
//                     centre from the axis (second moment, number-weighted).
//                     A 20 x 20 mm block: sqrt(2/3) x 10 mm = 8.2 mm.
//   dome_shape        sqrt(3) cov(r^2, z) / (sd(r^2) radial_spread_m)
//                     = b sqrt(3) sd(r^2) / radial_spread_m, with b the
//                     least-squares slope of z against r^2 (number-weighted
//                     population moments over the grains, cov(a, z) =
//                     mean((a - mean a)(z - mean z)), sd(a) = sqrt(cov(a, a))):
//                     the fitted paraboloid's height difference across a
//                     radial band of width sqrt(3) sd(r^2) in r^2, over the
//                     spread. 0 when sd(r^2) = 0. sqrt(3) makes it equal to
//                     the old median split (mean z of the grains with r above
//                     the median minus below it, over the spread) for a
//                     paraboloid cloud of uniform areal density on a disc;
//                     on a uniform square it reads 3-5 % above the split, on
//                     a gaussian cloud 4-25 %, on the full plume within 32 %
//                     where |value| > 0.1 (0.2 % at its extreme; README.md
//                     "Metrics"). Unlike the median split it is smooth in
//                     every grain position (r^2, not r, so also on the axis):
//                     a lattice start, whose median r falls on a ring of
//                     equal-radius columns, no longer lets tiny drifts decide
//                     which side a grain counts on.
//                     0 for the initial block (every column spans the same
//                     heights, so z is uncorrelated with r^2). < 0 when the
//                     outer grains lie lower than the core: the cloud has
//                     widened at its front and left a narrow tail on the axis
//                     above, the "dome shape with a tail of grains" of
//                     Fig. 24 and 26. > 0 when the core runs ahead of the
//                     ring (a cap pointing down, the DPMFoam anchor's shape
//                     at 0.7-1 s). Equals sqrt(3) rho sigma_z / radial_spread
//                     (rho the correlation of r^2 and z), so |dome_shape| <=
//                     sqrt(3) sd(z) / radial_spread.
//   peak_fluid_speed  max over the mesh nodes of |u|.
#include <numbers>
#include <span>

#include "core/particles.hpp"

namespace fdem::plume {

struct PlumeGeometry {
  double axis_x_m = 0.0;
  double axis_y_m = 0.0;
  double top_z_m = 0.0;  // top face of the initial block
};

struct PlumeMetrics {
  double t_s = 0.0;
  double front_depth_m = 0.0;
  double centroid_depth_m = 0.0;
  double radial_spread_m = 0.0;
  double dome_shape = 0.0;
  double peak_fluid_speed_mps = 0.0;
};

inline constexpr double kFrontQuantile = 0.05;
/// Width of dome_shape's band in units of sd(r^2): sqrt(3) is half the range
/// of r^2 over its sd for a uniform disc, where r^2 is uniform, so the fitted
/// height difference equals the median split's mean(z, outer half) - mean(z,
/// inner half) for a paraboloid there.
inline constexpr double kDomeBand = std::numbers::sqrt3;

/// Cloud metrics of `particles` at time t_s; `fluid_velocity` is 3*num_nodes
/// node-major (empty: peak speed 0). Throws std::invalid_argument when there
/// are fewer than 2 particles.
PlumeMetrics measure_plume(const Particles& particles, const PlumeGeometry& geometry,
                           std::span<const double> fluid_velocity, double t_s);

/// max over nodes of |u| [m/s].
double peak_speed(std::span<const double> fluid_velocity);

/// The q-quantile (0 <= q <= 1) of `values` by linear interpolation between
/// order statistics (Hyndman-Fan type 7, numpy's default).
double quantile(std::span<const double> values, double q);

}  // namespace fdem::plume

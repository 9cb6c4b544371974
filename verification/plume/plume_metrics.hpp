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
//   dome_shape        (z_ring - z_core) / radial_spread: the grains split at
//                     the median r into a core (r <= median) and an outer
//                     ring; the difference of their mean heights over the
//                     spread. 0 for the initial block (core and ring span the
//                     same heights). < 0 when the outer grains lie lower
//                     than the core: the cloud has widened at its front and
//                     left a narrow tail on the axis above, the "dome shape
//                     with a tail of grains" of Fig. 24 and 26. > 0 when the
//                     core runs ahead of the ring (a cap pointing down, the
//                     DPMFoam anchor's shape at 0.7-1 s).
//   peak_fluid_speed  max over the mesh nodes of |u|.
#include <span>

#include "dem/particles.hpp"

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

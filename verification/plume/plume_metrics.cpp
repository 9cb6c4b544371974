#include "plume_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace fdem::plume {

double quantile(std::span<const double> values, double q) {
  if (values.empty()) throw std::invalid_argument("quantile of an empty set");
  std::vector<double> v(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
  const double a = v[lo];
  // The next order statistic is the smallest of the elements after lo.
  const double b = hi == lo ? a : *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(lo) + 1, v.end());
  return a + (pos - static_cast<double>(lo)) * (b - a);
}

double peak_speed(std::span<const double> u) {
  double peak2 = 0.0;
  for (std::size_t n = 0; n + 2 < u.size(); n += 3)
    peak2 = std::max(peak2, u[n] * u[n] + u[n + 1] * u[n + 1] + u[n + 2] * u[n + 2]);
  return std::sqrt(peak2);
}

PlumeMetrics measure_plume(const Particles& p, const PlumeGeometry& g, std::span<const double> fluid_velocity,
                           double t_s) {
  const std::size_t n = p.size();
  if (n < 2) throw std::invalid_argument("plume metrics need at least 2 grains");
  PlumeMetrics m;
  m.t_s = t_s;

  std::vector<double> r(n);
  double mass = 0.0, mass_z = 0.0, r2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = p.x[i] - g.axis_x_m, dy = p.y[i] - g.axis_y_m;
    r[i] = std::hypot(dx, dy);
    r2 += dx * dx + dy * dy;
    mass += p.mass[i];
    mass_z += p.mass[i] * p.z[i];
  }
  m.front_depth_m = g.top_z_m - quantile(p.z, kFrontQuantile);
  m.centroid_depth_m = g.top_z_m - mass_z / mass;
  m.radial_spread_m = std::sqrt(r2 / static_cast<double>(n));

  // Core (r <= median r) against outer ring (r > median r).
  const double r_median = quantile(r, 0.5);
  double z_core = 0.0, z_ring = 0.0;
  std::size_t n_core = 0, n_ring = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (r[i] <= r_median) {
      z_core += p.z[i];
      ++n_core;
    } else {
      z_ring += p.z[i];
      ++n_ring;
    }
  }
  if (n_core > 0 && n_ring > 0 && m.radial_spread_m > 0.0)
    m.dome_shape = (z_ring / static_cast<double>(n_ring) - z_core / static_cast<double>(n_core)) / m.radial_spread_m;
  m.peak_fluid_speed_mps = peak_speed(fluid_velocity);
  return m;
}

}  // namespace fdem::plume

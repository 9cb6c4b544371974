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

  double mass = 0.0, mass_z = 0.0, r2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = p.x[i] - g.axis_x_m, dy = p.y[i] - g.axis_y_m;
    r2 += dx * dx + dy * dy;
    mass += p.mass[i];
    mass_z += p.mass[i] * p.z[i];
  }
  m.front_depth_m = g.top_z_m - quantile(p.z, kFrontQuantile);
  m.centroid_depth_m = g.top_z_m - mass_z / mass;
  m.radial_spread_m = std::sqrt(r2 / static_cast<double>(n));

  // Least-squares slope of z against r^2, scaled (plume_metrics.hpp). Moments
  // about the means (two passes), so a cloud 0.2 m up loses no digits.
  const double s_mean = r2 / static_cast<double>(n);
  double z_mean = 0.0;
  for (std::size_t i = 0; i < n; ++i) z_mean += p.z[i];
  z_mean /= static_cast<double>(n);
  double cov_sz = 0.0, var_s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = p.x[i] - g.axis_x_m, dy = p.y[i] - g.axis_y_m;
    const double ds = dx * dx + dy * dy - s_mean;
    cov_sz += ds * (p.z[i] - z_mean);
    var_s += ds * ds;
  }
  if (var_s > 0.0 && m.radial_spread_m > 0.0)
    m.dome_shape = kDomeBand * cov_sz / (std::sqrt(var_s * static_cast<double>(n)) * m.radial_spread_m);
  m.peak_fluid_speed_mps = peak_speed(fluid_velocity);
  return m;
}

}  // namespace fdem::plume

#include "io/probes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fdem {

namespace {
constexpr std::array<std::string_view, 6> all_probes{"count",          "mean_position", "mean_velocity",
                                                     "max_speed",      "kinetic_energy", "z_range"};

std::vector<std::string_view> chosen(const std::vector<std::string>& probes) {
  if (probes.empty()) return {all_probes.begin(), all_probes.end()};
  return {probes.begin(), probes.end()};
}

double mean_of(const std::vector<double>& v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (double a : v) sum += a;
  return sum / static_cast<double>(v.size());
}
}  // namespace

std::span<const std::string_view> probe_names() { return all_probes; }

bool is_probe_name(std::string_view name) {
  return std::find(all_probes.begin(), all_probes.end(), name) != all_probes.end();
}

std::vector<std::string> probe_columns(const std::vector<std::string>& probes) {
  std::vector<std::string> columns;
  for (std::string_view p : chosen(probes)) {
    if (p == "count") columns.emplace_back("count");
    else if (p == "mean_position") columns.insert(columns.end(), {"mean_x", "mean_y", "mean_z"});
    else if (p == "mean_velocity") columns.insert(columns.end(), {"mean_vx", "mean_vy", "mean_vz"});
    else if (p == "max_speed") columns.emplace_back("max_speed");
    else if (p == "kinetic_energy") columns.emplace_back("kinetic_energy");
    else if (p == "z_range") columns.insert(columns.end(), {"min_z", "max_z"});
  }
  return columns;
}

std::vector<double> probe_values(const std::vector<std::string>& probes, const Particles& particles) {
  std::vector<double> values;
  const std::size_t n = particles.size();
  for (std::string_view p : chosen(probes)) {
    if (p == "count") {
      values.push_back(static_cast<double>(n));
    } else if (p == "mean_position") {
      values.insert(values.end(), {mean_of(particles.x), mean_of(particles.y), mean_of(particles.z)});
    } else if (p == "mean_velocity") {
      values.insert(values.end(), {mean_of(particles.vx), mean_of(particles.vy), mean_of(particles.vz)});
    } else if (p == "max_speed") {
      double max2 = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        max2 = std::max(max2, particles.vx[i] * particles.vx[i] + particles.vy[i] * particles.vy[i] +
                                  particles.vz[i] * particles.vz[i]);
      }
      values.push_back(std::sqrt(max2));
    } else if (p == "kinetic_energy") {
      double energy = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        energy += 0.5 * particles.mass[i] *
                  (particles.vx[i] * particles.vx[i] + particles.vy[i] * particles.vy[i] +
                   particles.vz[i] * particles.vz[i]);
      }
      values.push_back(energy);
    } else if (p == "z_range") {
      if (n == 0) {
        values.insert(values.end(), 2, std::numeric_limits<double>::quiet_NaN());
      } else {
        const auto [lo, hi] = std::minmax_element(particles.z.begin(), particles.z.end());
        values.insert(values.end(), {*lo, *hi});
      }
    }
  }
  return values;
}

}  // namespace fdem

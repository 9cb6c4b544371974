#include "io/probes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/petsc_runtime.hpp"

namespace fdem {

namespace {
constexpr std::array<std::string_view, 6> all_probes{"count",          "mean_position", "mean_velocity",
                                                     "max_speed",      "kinetic_energy", "z_range"};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<std::string_view> chosen(const std::vector<std::string>& probes) {
  if (probes.empty()) return {all_probes.begin(), all_probes.end()};
  return {probes.begin(), probes.end()};
}

// Adds grain i, in the order the caller visits them (a sum's rounding depends
// on it; one process visits 0, 1, 2, ... as it always has).
void add_grain(ProbeSums& s, const Particles& p, std::size_t i) {
  s.count += 1.0;
  s.x += p.x[i];
  s.y += p.y[i];
  s.z += p.z[i];
  s.vx += p.vx[i];
  s.vy += p.vy[i];
  s.vz += p.vz[i];
  const double speed2 = p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  s.kinetic_energy += 0.5 * p.mass[i] * speed2;
  s.max_speed_squared = std::max(s.max_speed_squared, speed2);
  s.min_z = std::min(s.min_z, p.z[i]);
  s.max_z = std::max(s.max_z, p.z[i]);
}
}  // namespace

ProbeSums::ProbeSums()
    : min_z(std::numeric_limits<double>::infinity()), max_z(-std::numeric_limits<double>::infinity()) {}

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

ProbeSums probe_sums(const Particles& particles) {
  ProbeSums s;
  for (std::size_t i = 0; i < particles.size(); ++i) add_grain(s, particles, i);
  return s;
}

ProbeSums probe_sums(const Particles& particles, std::span<const std::size_t> indices) {
  ProbeSums s;
  for (std::size_t i : indices) add_grain(s, particles, i);
  return s;
}

ProbeSums sum_over_ranks(const ProbeSums& mine) {
  if (mpi_ranks() == 1) return mine;
  ProbeSums all;
  std::array<double, 8> sums{mine.count, mine.x, mine.y, mine.z, mine.vx, mine.vy, mine.vz, mine.kinetic_energy};
  sum_over_ranks(sums);  // one reduction for the sums
  // Minima as maxima of the negated values: one reduction for the extrema.
  std::array<double, 3> extrema{mine.max_speed_squared, -mine.min_z, mine.max_z};
  max_over_ranks(extrema);
  all.count = sums[0];
  all.x = sums[1];
  all.y = sums[2];
  all.z = sums[3];
  all.vx = sums[4];
  all.vy = sums[5];
  all.vz = sums[6];
  all.kinetic_energy = sums[7];
  all.max_speed_squared = extrema[0];
  all.min_z = -extrema[1];
  all.max_z = extrema[2];
  return all;
}

std::vector<double> probe_values(const std::vector<std::string>& probes, const ProbeSums& s) {
  std::vector<double> values;
  const bool none = s.count == 0.0;
  const auto mean = [&](double sum) { return none ? kNaN : sum / s.count; };
  for (std::string_view p : chosen(probes)) {
    if (p == "count") {
      values.push_back(s.count);
    } else if (p == "mean_position") {
      values.insert(values.end(), {mean(s.x), mean(s.y), mean(s.z)});
    } else if (p == "mean_velocity") {
      values.insert(values.end(), {mean(s.vx), mean(s.vy), mean(s.vz)});
    } else if (p == "max_speed") {
      values.push_back(std::sqrt(s.max_speed_squared));
    } else if (p == "kinetic_energy") {
      values.push_back(s.kinetic_energy);
    } else if (p == "z_range") {
      values.insert(values.end(), {none ? kNaN : s.min_z, none ? kNaN : s.max_z});
    }
  }
  return values;
}

std::vector<double> probe_values(const std::vector<std::string>& probes, const Particles& particles) {
  return probe_values(probes, probe_sums(particles));
}

}  // namespace fdem

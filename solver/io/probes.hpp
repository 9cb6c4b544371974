#pragma once
// Probes: scalar time series a run records in its CSV (output.probes in the
// scene). Each probe names one or more columns computed from the particles.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/particles.hpp"

namespace fdem {

/// Every probe a scene may name, in the order their columns are written.
///   count           number of particles
///   mean_position   mean_x, mean_y, mean_z [m]
///   mean_velocity   mean_vx, mean_vy, mean_vz [m/s]
///   max_speed       largest particle speed [m/s]
///   kinetic_energy  translational kinetic energy, sum m |v|^2 / 2 [J]
///   z_range         min_z, max_z of the particle centres [m]
std::span<const std::string_view> probe_names();
bool is_probe_name(std::string_view name);

/// Column names for the chosen probes (all probes when `probes` is empty).
std::vector<std::string> probe_columns(const std::vector<std::string>& probes);

/// Values for those columns, in the same order (NaN for means of no particles).
std::vector<double> probe_values(const std::vector<std::string>& probes, const Particles& particles);

/// What every probe is computed from, over a set of grains: counts and sums
/// add over disjoint sets, extrema take their min or max, so a run on
/// several MPI ranks combines each rank's own grains into the whole's values
/// (sum_over_ranks below).
struct ProbeSums {
  double count = 0.0;
  double x = 0.0, y = 0.0, z = 0.0;        // sums of the centres [m]
  double vx = 0.0, vy = 0.0, vz = 0.0;     // sums of the velocities [m/s]
  double kinetic_energy = 0.0;             // sum m |v|^2 / 2 [J]
  double max_speed_squared = 0.0;          // [m^2/s^2]
  double min_z, max_z;                     // [m]; +inf, -inf over no grains
  ProbeSums();
};

/// Over all of `particles`, or over those at `indices` (in that order).
ProbeSums probe_sums(const Particles& particles);
ProbeSums probe_sums(const Particles& particles, std::span<const std::size_t> indices);

/// The sums of every MPI rank combined, on every rank (a collective: every
/// rank calls it at the same point); on one process `mine` itself.
ProbeSums sum_over_ranks(const ProbeSums& mine);

/// The columns' values from sums (the same as from the grains summed).
std::vector<double> probe_values(const std::vector<std::string>& probes, const ProbeSums& sums);

}  // namespace fdem

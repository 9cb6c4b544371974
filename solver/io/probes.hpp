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

}  // namespace fdem

// Contact timescales and the stable explicit DEM step (see stability.hpp).
#include "scene/stability.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "contact_laws/linear_spring_dashpot.hpp"
#include "core/error.hpp"
#include "core/particles.hpp"

namespace fdem {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

double ContactTimescale::stable_step_s() const {
  return std::min({spring_step_limit_s, damping_step_limit_s, tangential_step_limit_s});
}

double StabilityReport::stable_step_s() const {
  return contacts.empty() ? kInf : contacts[binding].stable_step_s();
}

MassRange mass_range(double min_diameter_m, double max_diameter_m, double density_kg_m3) {
  return {min_diameter_m, density_kg_m3 * sphere_volume(min_diameter_m), max_diameter_m,
          density_kg_m3 * sphere_volume(max_diameter_m)};
}

MassRange mass_range(const Particles& particles) {
  if (particles.size() == 0) throw std::invalid_argument("mass_range: no particles");
  const auto [lo, hi] = std::minmax_element(particles.mass.begin(), particles.mass.end());
  const auto ilo = static_cast<std::size_t>(lo - particles.mass.begin());
  const auto ihi = static_cast<std::size_t>(hi - particles.mass.begin());
  return {particles.diameter[ilo], *lo, particles.diameter[ihi], *hi};
}

double damping_from_restitution(double restitution, double stiffness_n_m, double effective_mass_kg) {
  if (restitution >= 1.0) return 0.0;
  if (restitution <= 0.0) throw std::invalid_argument("restitution must be in (0, 1]");
  return 2.0 * damping_ratio_from_restitution(restitution) * std::sqrt(stiffness_n_m * effective_mass_kg);
}

ContactTimescale contact_timescale(const ContactSpec& contact, const Effects& effects, std::string label,
                                   double diameter_a_m, double mass_a_kg, double diameter_b_m,
                                   double mass_b_kg) {
  ContactTimescale c;
  c.label = std::move(label);
  c.diameter_a_m = diameter_a_m;
  c.diameter_b_m = diameter_b_m;
  c.effective_mass_kg = mass_b_kg > 0.0 ? mass_a_kg * mass_b_kg / (mass_a_kg + mass_b_kg) : mass_a_kg;
  const double m = c.effective_mass_kg;
  c.stiffness_n_m = contact.normal_stiffness;
  c.damping_n_s_m = contact.restitution ? damping_from_restitution(*contact.restitution, contact.normal_stiffness, m)
                                        : contact.normal_damping;
  c.natural_frequency_rad_s = std::sqrt(c.stiffness_n_m / m);
  c.contact_time_undamped_s = c.natural_frequency_rad_s > 0.0 ? pi / c.natural_frequency_rad_s : kInf;
  c.damping_ratio = c.stiffness_n_m > 0.0 ? c.damping_n_s_m / (2.0 * std::sqrt(c.stiffness_n_m * m)) : kInf;
  const double decay = c.damping_n_s_m / (2.0 * m);
  const double omega_d2 = c.natural_frequency_rad_s * c.natural_frequency_rad_s - decay * decay;
  c.contact_time_s = omega_d2 > 0.0 ? pi / std::sqrt(omega_d2) : kInf;
  c.restitution = c.damping_ratio < 1.0
                      ? std::exp(-pi * c.damping_ratio / std::sqrt(1.0 - c.damping_ratio * c.damping_ratio))
                      : 0.0;
  // Velocity Verlet on x'' = -omega0^2 x: stable for omega0 dt < 2.
  c.spring_step_limit_s = c.natural_frequency_rad_s > 0.0 ? kStepSafetyFactor * 2.0 / c.natural_frequency_rad_s : kInf;
  // Explicit dashpot v' = -(C/m) v: stable for C dt / m < 2.
  c.damping_step_limit_s = c.damping_n_s_m > 0.0 ? kStepSafetyFactor * 2.0 * m / c.damping_n_s_m : kInf;
  c.tangential_step_limit_s = kInf;
  if (effects.tangential_contact) {
    // A tangential impulse also spins both spheres (I = m d^2/10, lever d/2):
    // the effective tangential mass is m_eff / (1 + m r^2 / I) = m_eff * 2/7.
    const double m_t = effects.rotation ? m * 2.0 / 7.0 : m;
    if (contact.tangential_stiffness > 0.0)
      c.tangential_step_limit_s = kStepSafetyFactor * 2.0 / std::sqrt(contact.tangential_stiffness / m_t);
    if (contact.tangential_damping > 0.0)
      c.tangential_step_limit_s =
          std::min(c.tangential_step_limit_s, kStepSafetyFactor * 2.0 * m_t / contact.tangential_damping);
  }
  return c;
}

StabilityReport analyse_stability(const ContactSpec& contact, const Effects& effects, const MassRange& r,
                                  double dem_step_s, bool walls) {
  StabilityReport report;
  report.dem_step_s = dem_step_s;
  auto add = [&](std::string label, double da, double ma, double db, double mb) {
    report.contacts.push_back(contact_timescale(contact, effects, std::move(label), da, ma, db, mb));
  };
  add("smallest pair", r.small_diameter_m, r.small_mass_kg, r.small_diameter_m, r.small_mass_kg);
  add("largest pair", r.large_diameter_m, r.large_mass_kg, r.large_diameter_m, r.large_mass_kg);
  add("smallest-largest pair", r.small_diameter_m, r.small_mass_kg, r.large_diameter_m, r.large_mass_kg);
  if (walls) {
    add("smallest on wall", r.small_diameter_m, r.small_mass_kg, 0.0, 0.0);
    add("largest on wall", r.large_diameter_m, r.large_mass_kg, 0.0, 0.0);
  }
  for (std::size_t i = 1; i < report.contacts.size(); ++i)
    if (report.contacts[i].stable_step_s() < report.contacts[report.binding].stable_step_s()) report.binding = i;
  return report;
}

std::string StabilityReport::table() const {
  std::string out = fmt::format(
      "DEM step stability (velocity Verlet, safety factor {}: dt <= {} * 2/omega0 and <= {} * 2 m_eff/C)\n"
      "{:<22} {:>9} {:>9} {:>11} {:>11} {:>11} {:>7} {:>6} {:>11} {:>8}\n",
      kStepSafetyFactor, kStepSafetyFactor, kStepSafetyFactor, "contact", "d_a [m]", "d_b [m]", "m_eff [kg]",
      "t_c0 [s]", "t_c [s]", "zeta", "e", "dt_max [s]", "dt/t_c0");
  for (const auto& c : contacts)
    out += fmt::format("{:<22} {:>9.3g} {:>9.3g} {:>11.4g} {:>11.4g} {:>11.4g} {:>7.3f} {:>6.3f} {:>11.4g} {:>8.3g}\n",
                       c.label, c.diameter_a_m, c.diameter_b_m, c.effective_mass_kg, c.contact_time_undamped_s,
                       c.contact_time_s, c.damping_ratio, c.restitution, c.stable_step_s(),
                       dem_step_s / c.contact_time_undamped_s);
  out += fmt::format("time.dem_step = {:g} s, stable bound {:.4g} s ({}): {}\n", dem_step_s, stable_step_s(),
                     contacts.empty() ? "no contacts" : contacts[binding].label, stable() ? "stable" : "UNSTABLE");
  return out;
}

void require_stable_step(const StabilityReport& report, const ContactSpec& contact, const std::string& source_file) {
  if (report.stable() || contact.allow_unstable_step) return;
  const ContactTimescale& c = report.contacts[report.binding];
  const char* which = c.stable_step_s() == c.spring_step_limit_s    ? "spring: 0.5 * 2/omega0"
                      : c.stable_step_s() == c.damping_step_limit_s ? "dashpot: 0.5 * 2 m_eff/Cn"
                                                                    : "tangential spring-dashpot";
  throw InputError(source_file, "time.dem_step", fmt::format("{:g}", report.dem_step_s),
                   fmt::format("DEM step {:g} s exceeds the stable bound {:.3g} s ({}) for the {} "
                               "(d {:.3g} m / {:.3g} m, m_eff {:.3g} kg, Kn {:g} N/m, Cn {:.3g} N s/m): contact "
                               "time t_c = {:.3g} s, so dt = {:.3g} t_c. Reduce time.dem_step to at most {:.3g} s, "
                               "soften contact.kn, or set contact.allow_unstable_step: true to run anyway",
                               report.dem_step_s, c.stable_step_s(), which, c.label, c.diameter_a_m, c.diameter_b_m,
                               c.effective_mass_kg, c.stiffness_n_m, c.damping_n_s_m, c.contact_time_undamped_s,
                               report.dem_step_s / c.contact_time_undamped_s, c.stable_step_s()));
}

}  // namespace fdem

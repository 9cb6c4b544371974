#pragma once
// Stability of the explicit DEM step for the linear spring-dashpot contact
// (Eq. 6-7; contact.law linear_spring_dashpot, contact_laws/linear_spring_dashpot.hpp,
// the only law of contact_laws/contact_law_table.cpp): contact times, damping ratio, restitution and the stable step,
// for the smallest pair, the largest pair, the smallest-largest pair and the
// particle-wall contact (m_eff = m). The bound of the time-step rules
// (scene/time_steps.hpp: the loader, Simulation, DemEngine, `fdem check`);
// `fdem check` also prints the table.
//
// The bound. Velocity Verlet on an undamped linear spring is stable for
// omega0 dt < 2 (omega0 = sqrt(K / m_eff)); the dashpot, evaluated explicitly
// with the half-step velocity, is an explicit-Euler decay stable for
// C dt / m_eff < 2. Both limits are where the scheme *diverges*; accuracy is
// already poor close to them (at omega0 dt = 2 the contact lasts ~1.6 steps),
// so the accepted step is a safety factor kStepSafetyFactor = 0.5 below each:
//   dt <= 0.5 * 2 / omega0 = t_c0 / pi   (t_c0 = pi sqrt(m_eff / K), ~3 steps per contact)
//   dt <= 0.5 * 2 m_eff / C
// With tangential contact the tangential spring is checked the same way with
// its effective stiffness (x 7/2 when rotation is on: a tangential impulse
// also spins both spheres, I = m d^2 / 10).
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace fdem {

struct Particles;

inline constexpr double kStepSafetyFactor = 0.5;

/// The extreme particles of a set: smallest and largest by mass.
struct MassRange {
  double small_diameter_m = 0.0, small_mass_kg = 0.0;
  double large_diameter_m = 0.0, large_mass_kg = 0.0;
};
MassRange mass_range(double min_diameter_m, double max_diameter_m, double density_kg_m3);
MassRange mass_range(const Particles& particles);  // throws std::invalid_argument when empty

/// One contact kind (a pair of sizes, or a particle on a wall).
struct ContactTimescale {
  std::string label;                 // "smallest pair", "largest pair", "smallest-largest pair", "smallest on wall", ...
  double diameter_a_m = 0.0;
  double diameter_b_m = 0.0;         // 0 for a wall
  double effective_mass_kg = 0.0;    // m_a m_b / (m_a + m_b), or m_a on a wall
  double stiffness_n_m = 0.0;        // Kn
  double damping_n_s_m = 0.0;        // Cn (given, or from the restitution for this m_eff)
  double natural_frequency_rad_s = 0.0;  // omega0 = sqrt(Kn / m_eff)
  double contact_time_undamped_s = 0.0;  // pi / omega0
  double contact_time_s = 0.0;           // pi / sqrt(omega0^2 - (Cn / 2 m_eff)^2); +inf when overdamped
  double damping_ratio = 0.0;            // zeta = Cn / (2 sqrt(Kn m_eff))
  double restitution = 0.0;              // exp(-pi zeta / sqrt(1 - zeta^2)); 0 when overdamped
  double spring_step_limit_s = 0.0;      // kStepSafetyFactor * 2 / omega0
  double damping_step_limit_s = 0.0;     // kStepSafetyFactor * 2 m_eff / Cn (+inf without damping)
  double tangential_step_limit_s = 0.0;  // same for Kt, Ct (+inf without tangential contact)
  double stable_step_s() const;          // the smallest of the three limits
};

struct StabilityReport {
  double dem_step_s = 0.0;
  std::vector<ContactTimescale> contacts;
  std::size_t binding = 0;             // index of the contact with the smallest stable step
  double stable_step_s() const;        // contacts[binding].stable_step_s()
  bool stable() const { return dem_step_s <= stable_step_s(); }
  /// Multi-line table for `fdem check` and logs.
  std::string table() const;
};

/// Damping coefficient [N s/m] that gives restitution e for effective mass
/// m_eff with the linear spring-dashpot: zeta = -ln e / sqrt(pi^2 + ln^2 e),
/// C = 2 zeta sqrt(K m_eff) (inverse of e = exp(-pi zeta / sqrt(1 - zeta^2))).
double damping_from_restitution(double restitution, double stiffness_n_m, double effective_mass_kg);

/// Timescales of one contact kind (Cn from contact.restitution when given).
ContactTimescale contact_timescale(const ContactSpec& contact, const Effects& effects, std::string label,
                                   double diameter_a_m, double mass_a_kg, double diameter_b_m,
                                   double mass_b_kg /* 0 = wall */);

/// All contact kinds for this mass range; wall contacts only when `walls`.
StabilityReport analyse_stability(const ContactSpec& contact, const Effects& effects, const MassRange& range,
                                  double dem_step_s, bool walls);

/// Throws fdem::InputError(source_file, "time.dem_step", value, reason) when
/// the report is unstable and contact.allow_unstable_step is false. The reason
/// names the bound, the binding contact, its t_c and dt / t_c.
void require_stable_step(const StabilityReport& report, const ContactSpec& contact,
                         const std::string& source_file);

}  // namespace fdem

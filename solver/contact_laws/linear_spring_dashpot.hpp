#pragma once
// The linear spring-dashpot normal force (Eq. 6), contact.law
// linear_spring_dashpot (a row of contact_law_table.cpp):
//   f_n = Kn delta_n + Cn delta_n_dot,
// delta_n > 0 the overlap and delta_n_dot its closing rate. Cn is the scene's
// contact.cn, or comes from a restitution e for each pair's effective mass:
// the free damped oscillator m_eff x'' + Cn x' + Kn x = 0 leaves the contact
// (f_n back to zero, as LIGGGHTS's hooke model ends it: the force is slightly
// attractive at the very end) with e = exp(-pi zeta / sqrt(1 - zeta^2)),
// zeta = Cn / (2 sqrt(Kn m_eff)), whose inverse is damping_ratio_from_restitution.
#include <cmath>

#include "core/types.hpp"

namespace fdem {

/// zeta = -ln e / sqrt(pi^2 + ln^2 e): the inverse of e = exp(-pi zeta / sqrt(1 - zeta^2)), e in (0, 1].
inline double damping_ratio_from_restitution(double restitution) {
  const double log_e = std::log(restitution);
  return -log_e / std::sqrt(pi * pi + log_e * log_e);
}

/// The law's coefficients, resolved once from the scene's contact map.
struct LinearSpringDashpot {
  double stiffness = 0.0;      // Kn [N/m]
  double damping = 0.0;        // Cn [N s/m], when not from the restitution
  double damping_ratio = 0.0;  // zeta, when Cn comes from the restitution: Cn = 2 zeta sqrt(Kn m_eff)
};

/// The law as the DEM kernel compiles it: Cn given (false) or from the
/// restitution for each pair's effective mass (true).
template <bool DampingFromRestitution>
struct LinearSpringDashpotForce {
  using Coefficients = LinearSpringDashpot;
  /// The pair loop forms m_eff only for a law that reads it.
  static constexpr bool needs_effective_mass = DampingFromRestitution;
  /// The kernel's bits in a DEM checkpoint's effect key (dem/dem_engine.cpp).
  static constexpr unsigned checkpoint_key = DampingFromRestitution ? 1u : 0u;
  /// With Cn given, f_n = Kn delta_n + Cn delta_n_dot has the same two
  /// coefficients for every pair, which the engine's vector pair pass
  /// (dem/touching_pairs_avx512.hpp) takes as constants.
  static constexpr bool pair_independent_linear = !DampingFromRestitution;
  static double linear_stiffness(const LinearSpringDashpot& law) { return law.stiffness; }
  static double linear_damping(const LinearSpringDashpot& law) { return law.damping; }

  /// Cn for a pair of effective mass m_eff.
  static double damping(const LinearSpringDashpot& law, double effective_mass_kg) {
    if constexpr (DampingFromRestitution)
      return 2.0 * law.damping_ratio * std::sqrt(law.stiffness * effective_mass_kg);
    else
      return law.damping;
  }
  /// Eq. 6: f_n [N], positive pushing the bodies apart.
  static double normal_force(const LinearSpringDashpot& law, double effective_mass_kg, double overlap_m,
                             double closing_rate_m_s) {
    return law.stiffness * overlap_m + damping(law, effective_mass_kg) * closing_rate_m_s;
  }
};

}  // namespace fdem

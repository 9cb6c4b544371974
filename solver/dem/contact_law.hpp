#pragma once
// Contact laws of one contact (Eq. 6-10), as inline functions so the pair loop
// of the engine specialises them at compile time. A contact is seen from
// sphere i: n is the unit normal from i towards the other body, delta_n > 0
// the overlap, v_rel = v_i(contact point) - v_other(contact point).
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>  // cross products (Eq. 10)

#include "core/types.hpp"

namespace fdem {

/// Contact coefficients, resolved once from the scene's ContactSpec.
struct ContactLaw {
  double normal_stiffness = 0.0;      // Kn [N/m]
  double normal_damping = 0.0;        // Cn [N s/m], when not from restitution
  double damping_ratio = 0.0;         // zeta, when Cn comes from the restitution: Cn = 2 zeta sqrt(Kn m_eff)
  double tangential_stiffness = 0.0;  // Kt [N/m]
  double tangential_damping = 0.0;    // Ct [N s/m]
  double friction = 0.0;              // mu_coulomb
};

struct ContactForce {
  Vec3 normal = Vec3::Zero();      // f_n n (on sphere i)
  Vec3 tangential = Vec3::Zero();  // f_t t (on sphere i)
  double normal_magnitude = 0.0;   // Kn delta + Cn delta_dot (may be < 0 at the end of a contact)
};

/// Normal dashpot coefficient for a pair of effective mass m_eff.
template <bool DampingFromRestitution>
inline double normal_damping(const ContactLaw& law, double effective_mass_kg) {
  if constexpr (DampingFromRestitution)
    return 2.0 * law.damping_ratio * std::sqrt(law.normal_stiffness * effective_mass_kg);
  else
    return law.normal_damping;
}

/// Eq. 6: f_n = Kn delta_n + Cn delta_n_dot, pushing i away from the other
/// body (-n). delta_n_dot = v_rel . n (closing rate). The force is left
/// slightly attractive at the end of a damped contact (as LIGGGHTS does):
/// that is the linear spring-dashpot whose restitution is
/// e = exp(-pi zeta / sqrt(1 - zeta^2)).
///
/// With Tangential: Eq. 7-8, slip history `slip` (delta_t, integrated from
/// the tangential slip rate, kept in the tangent plane), spring-dashpot
/// f_t = -(Kt delta_t + Ct delta_t_dot) capped by Coulomb mu |f_n|; when the
/// cap bites the history is reset to the spring length that gives exactly the
/// capped force (sliding).
template <bool Tangential, bool DampingFromRestitution>
inline ContactForce contact_force(const ContactLaw& law, double effective_mass_kg, double overlap_m,
                                  const Vec3& n, const Vec3& v_rel, double dt_s, Vec3* slip) {
  ContactForce f;
  const double closing_rate = v_rel.dot(n);
  const double cn = normal_damping<DampingFromRestitution>(law, effective_mass_kg);
  f.normal_magnitude = law.normal_stiffness * overlap_m + cn * closing_rate;  // Eq. 6
  f.normal = -f.normal_magnitude * n;
  if constexpr (Tangential) {
    const Vec3 slip_rate = v_rel - closing_rate * n;  // delta_t_dot
    Vec3& s = *slip;
    s -= s.dot(n) * n;      // the contact plane turns with the pair: keep the history in it
    s += slip_rate * dt_s;  // Eq. 8
    Vec3 ft = -law.tangential_stiffness * s - law.tangential_damping * slip_rate;  // Eq. 7, spring-dashpot
    const double cap = law.friction * std::abs(f.normal_magnitude);               // Eq. 7, Coulomb
    const double ft_norm = ft.norm();
    if (ft_norm > cap) {
      ft *= cap / ft_norm;
      if (law.tangential_stiffness > 0.0) s = -(ft + law.tangential_damping * slip_rate) / law.tangential_stiffness;
    }
    f.tangential = ft;
  }
  return f;
}

}  // namespace fdem

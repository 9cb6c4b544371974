#pragma once
// One contact (Eq. 6-10) as the DEM kernels evaluate it: the scene's normal
// law (contact.law, a row of contact_laws/contact_law_table.cpp, its formula
// in its own header) and the tangential spring-dashpot with its Coulomb cap
// (Eq. 7-8), as inline functions so the pair loop of the engine specialises
// them at compile time. A contact is seen from sphere i: n is the unit
// normal from i towards the other body, delta_n > 0 the overlap,
// v_rel = v_i(contact point) - v_other(contact point).
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>  // cross products (Eq. 10)

#include "contact_laws/linear_spring_dashpot.hpp"
#include "core/types.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// Contact coefficients, resolved once from the scene's ContactSpec.
struct ContactLaw {
  LinearSpringDashpot linear;         // contact.law linear_spring_dashpot: Kn, Cn or zeta
  double tangential_stiffness = 0.0;  // Kt [N/m]
  double tangential_damping = 0.0;    // Ct [N s/m]
  double friction = 0.0;              // mu_coulomb
};

/// The coefficients of the scene's contact map.
inline ContactLaw contact_law_of(const ContactSpec& c) {
  ContactLaw law;
  law.linear.stiffness = c.normal_stiffness;
  law.linear.damping = c.normal_damping;
  if (c.restitution) law.linear.damping_ratio = damping_ratio_from_restitution(*c.restitution);
  law.tangential_stiffness = c.tangential_stiffness;
  law.tangential_damping = c.tangential_damping;
  law.friction = c.friction;
  return law;
}

/// A normal law's coefficients in a ContactLaw (one specialisation a law).
template <class Coefficients>
const Coefficients& normal_coefficients(const ContactLaw& law);
template <>
inline const LinearSpringDashpot& normal_coefficients<LinearSpringDashpot>(const ContactLaw& law) {
  return law.linear;
}

struct ContactForce {
  Vec3 normal = Vec3::Zero();      // f_n n (on sphere i)
  Vec3 tangential = Vec3::Zero();  // f_t t (on sphere i)
  double normal_magnitude = 0.0;   // the law's f_n (may be < 0 at the end of a damped contact)
};

/// The normal law's f_n pushing i away from the other body (-n), with
/// delta_n_dot = v_rel . n (closing rate); NormalLaw is a law's kernel form
/// (e.g. LinearSpringDashpotForce<true>).
///
/// With Tangential: Eq. 7-8, slip history `slip` (delta_t, integrated from
/// the tangential slip rate, kept in the tangent plane), spring-dashpot
/// f_t = -(Kt delta_t + Ct delta_t_dot) capped by Coulomb mu |f_n|; when the
/// cap bites the history is reset to the spring length that gives exactly the
/// capped force (sliding).
template <bool Tangential, class NormalLaw>
inline ContactForce contact_force(const ContactLaw& law, double effective_mass_kg, double overlap_m,
                                  const Vec3& n, const Vec3& v_rel, double dt_s, Vec3* slip) {
  ContactForce f;
  const double closing_rate = v_rel.dot(n);
  const auto& normal = normal_coefficients<typename NormalLaw::Coefficients>(law);
  f.normal_magnitude = NormalLaw::normal_force(normal, effective_mass_kg, overlap_m, closing_rate);  // Eq. 6
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

#pragma once
// Drag on a particle among others (paper Sect. 2.1, Eq. 11-15).
//
//   f_D = pi/6 d^3 beta / (1 - eps) (u - v)                          Eq. 11
//   beta = 150 (1-eps)^2 mu / (eps d^2) + 1.75 (1-eps) rho |u-v| / d,  eps < 0.8   Eq. 12 (Ergun)
//   beta = 3/4 Cd eps (1-eps) rho |u-v| / d * eps^-2.65,              eps >= 0.8  Eq. 13 (Wen & Yu)
//   Cd = 24/Re (1 + 0.15 Re^0.687) for Re <= 1000, 0.44 above        Eq. 14 (Rowe & Henwood)
//   Re = eps rho |u-v| d / mu                                         Eq. 15
//
// Eq. 12 is garbled in the paper's text extraction; the form coded is the
// standard one of Kuipers et al. (1992) and Gidaspow (1994, "Multiphase Flow
// and Fluidization", Eq. 5.67), which the paper cites as [24]:
// 150 (1-eps)^2 mu / (eps d^2) + 1.75 (1-eps) rho |u-v| / d.
//
// Eq. 11 divides beta by (1 - eps), which is 0/0 for an isolated particle
// (eps = 1). Both closures carry a factor (1 - eps), so we code the force
// coefficient K = beta / (1 - eps) with that factor cancelled analytically:
//   Ergun:    K = 150 (1-eps) mu / (eps d^2) + 1.75 rho |u-v| / d
//   Wen & Yu: K = 3/4 Cd eps rho |u-v| / d * eps^-2.65
// and f_D = V_p K (u - v), V_p = pi d^3 / 6. At eps = 1 Wen & Yu gives the
// isolated-sphere drag 1/2 Cd rho (pi d^2/4) |u-v| (u-v).
//
// The switch at eps = 0.8 is discontinuous. In the viscous limit (Re -> 0)
// K_Ergun / K_WenYu = (150 * 0.2 / 0.8) / (18 * 0.8^-2.65) = 37.5 / 32.52 =
// 1.153: the drag drops by 13 % when eps crosses 0.8 from below. At higher
// Re the ratio changes (inertial terms differ: 1.33 at Re = 40, d = 0.5 mm);
// see drag_jump_at_switch().
// Cd of Eq. 14 is nearly continuous at Re = 1000: 0.4383 below, 0.44 above
// (0.4 %).
//
// DragLaw::stokes is the analytic limit f = 3 pi mu d (u - v) (K = 18 mu / d^2),
// independent of eps: the reference for Stokes' law, not a closure among others.
#include "core/types.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// Porosity at which Eq. 12 hands over to Eq. 13.
inline constexpr double ergun_wen_yu_switch = 0.8;
/// Particle Reynolds number above which Cd is constant (Eq. 14).
inline constexpr double cd_constant_above_reynolds = 1000.0;

/// Fluid properties the closures need.
struct FluidProperties {
  double density = 1000.0;    // rho_f [kg/m^3]
  double viscosity = 1.0e-3;  // mu_f [Pa s]
};

/// Eq. 15: Re_p = eps rho |u - v| d / mu.
double particle_reynolds(double porosity, double slip_speed_m_s, double diameter_m, const FluidProperties& fluid);

/// Eq. 14 (Rowe & Henwood). Re must be > 0.
double drag_coefficient(double reynolds);

/// Everything the closure computes for one particle.
struct DragEvaluation {
  double reynolds = 0.0;            // Eq. 15
  double drag_coefficient = 0.0;    // Eq. 14 (0 where unused: Ergun, Stokes, zero slip)
  double force_coefficient = 0.0;   // K = beta / (1 - eps) [kg/(m^3 s)]; f = V_p K (u - v)
  double beta = 0.0;                // momentum transfer coefficient [kg/(m^3 s)], Eq. 12/13
  Vec3 force = Vec3::Zero();        // Eq. 11, drag on the particle [N]
};

/// K = beta / (1 - eps) for a slip speed |u - v| (Eq. 12-15, see the header
/// comment); finite for eps in (0, 1] and slip >= 0.
double force_coefficient(DragLaw law, double porosity, double slip_speed_m_s, double diameter_m,
                         const FluidProperties& fluid);

/// Full evaluation: Re, Cd, beta and the force of Eq. 11 for fluid velocity u
/// and particle velocity v.
DragEvaluation evaluate_drag(DragLaw law, double porosity, const Vec3& fluid_velocity, const Vec3& particle_velocity,
                             double diameter_m, const FluidProperties& fluid);

/// K just below the switch over K at the switch (eps = 0.8), for a slip speed:
/// the relative size of the jump a particle sees crossing eps = 0.8.
double drag_jump_at_switch(double slip_speed_m_s, double diameter_m, const FluidProperties& fluid);

}  // namespace fdem

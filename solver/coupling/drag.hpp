#pragma once
// Drag on one particle among others (paper Sect. 2.1, Eq. 11), evaluated
// one particle at a time: the reference the subcycle kernel
// (coupling/drag_coupling.hpp) is tested against, and what the GSL settling
// reference integrates. It runs the law's own fold and closure
// (drag_laws/) on a one-particle block, so every formula is coded
// once, in its law's file:
//   f_D = V_p K (u - v),  V_p = pi d^3 / 6,  beta = K (1 - eps)        Eq. 11
//   Re = eps rho |u-v| d / mu                                         Eq. 15
#include "core/types.hpp"
#include "drag_laws/drag_law.hpp"
#include "drag_laws/ergun_wen_yu.hpp"

namespace fdem {

/// Eq. 15: Re_p = eps rho |u - v| d / mu.
double particle_reynolds(double porosity, double slip_speed_m_s, double diameter_m, const FluidProperties& fluid);

/// Everything the closure computes for one particle.
struct DragEvaluation {
  double reynolds = 0.0;            // Eq. 15
  double force_coefficient = 0.0;   // K = beta / (1 - eps) [kg/(m^3 s)]; f = V_p K (u - v)
  double beta = 0.0;                // momentum transfer coefficient [kg/(m^3 s)], Eq. 12/13
  Vec3 force = Vec3::Zero();        // Eq. 11, drag on the particle [N]
};

/// K for a slip speed |u - v|; finite for eps in (0, 1] and slip >= 0.
double force_coefficient(const DragLawEntry& law, double porosity, double slip_speed_m_s, double diameter_m,
                         const FluidProperties& fluid);

/// Full evaluation: Re, beta and the force of Eq. 11 for fluid velocity u
/// and particle velocity v.
DragEvaluation evaluate_drag(const DragLawEntry& law, double porosity, const Vec3& fluid_velocity,
                             const Vec3& particle_velocity, double diameter_m, const FluidProperties& fluid);

/// ergun_wen_yu's K just below the switch over K at the switch (eps = 0.8),
/// for a slip speed: the relative size of the jump a particle sees crossing eps = 0.8.
double drag_jump_at_switch(double slip_speed_m_s, double diameter_m, const FluidProperties& fluid);

}  // namespace fdem

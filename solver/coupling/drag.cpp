#include "coupling/drag.hpp"

#include <cmath>
#include <limits>

namespace fdem {

double particle_reynolds(double porosity, double slip_speed_m_s, double diameter_m, const FluidProperties& fluid) {
  return porosity * fluid.density * slip_speed_m_s * diameter_m / fluid.viscosity;  // Eq. 15
}

double drag_coefficient(double reynolds) {
  if (reynolds > cd_constant_above_reynolds) return 0.44;              // Eq. 14, Newton regime
  return 24.0 / reynolds * (1.0 + 0.15 * std::pow(reynolds, 0.687));  // Eq. 14, Rowe & Henwood
}

double force_coefficient(DragLaw law, double porosity, double slip_speed_m_s, double diameter_m,
                         const FluidProperties& fluid) {
  const double mu = fluid.viscosity, rho = fluid.density, d = diameter_m, eps = porosity;
  switch (law) {
    case DragLaw::stokes:
      return 18.0 * mu / (d * d);  // 3 pi mu d / V_p
    case DragLaw::ergun_wen_yu:
      if (eps < ergun_wen_yu_switch)  // Eq. 12 / (1 - eps), Ergun (Kuipers / Gidaspow form)
        return 150.0 * (1.0 - eps) * mu / (eps * d * d) + 1.75 * rho * slip_speed_m_s / d;
      {
        // Eq. 13 / (1 - eps), Wen & Yu. Cd * Re is finite as Re -> 0, so use
        // Cd |u-v| = 24 mu / (eps rho d) (1 + 0.15 Re^0.687) to stay finite at zero slip.
        const double re = particle_reynolds(eps, slip_speed_m_s, d, fluid);
        const double cd_times_slip = re > cd_constant_above_reynolds
                                         ? 0.44 * slip_speed_m_s
                                         : 24.0 * mu / (eps * rho * d) * (1.0 + 0.15 * std::pow(re, 0.687));
        return 0.75 * cd_times_slip * eps * rho / d * std::pow(eps, -2.65);
      }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

DragEvaluation evaluate_drag(DragLaw law, double porosity, const Vec3& fluid_velocity, const Vec3& particle_velocity,
                             double diameter_m, const FluidProperties& fluid) {
  DragEvaluation out;
  const Vec3 slip = fluid_velocity - particle_velocity;
  const double speed = slip.norm();
  out.reynolds = particle_reynolds(porosity, speed, diameter_m, fluid);
  if (law == DragLaw::ergun_wen_yu && porosity >= ergun_wen_yu_switch && out.reynolds > 0.0)
    out.drag_coefficient = drag_coefficient(out.reynolds);
  out.force_coefficient = force_coefficient(law, porosity, speed, diameter_m, fluid);
  out.beta = out.force_coefficient * (1.0 - porosity);
  out.force = sphere_volume(diameter_m) * out.force_coefficient * slip;  // Eq. 11
  return out;
}

double drag_jump_at_switch(double slip_speed_m_s, double diameter_m, const FluidProperties& fluid) {
  const double below = std::nextafter(ergun_wen_yu_switch, 0.0);
  return force_coefficient(DragLaw::ergun_wen_yu, below, slip_speed_m_s, diameter_m, fluid) /
         force_coefficient(DragLaw::ergun_wen_yu, ergun_wen_yu_switch, slip_speed_m_s, diameter_m, fluid);
}

}  // namespace fdem

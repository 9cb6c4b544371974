#include "coupling/drag.hpp"

#include <cmath>

namespace fdem {

double particle_reynolds(double porosity, double slip_speed_m_s, double diameter_m, const FluidProperties& fluid) {
  return porosity * fluid.density * slip_speed_m_s * diameter_m / fluid.viscosity;  // Eq. 15
}

double force_coefficient(const DragLawEntry& law, double porosity, double slip_speed_m_s, double diameter_m,
                         const FluidProperties& fluid) {
  // One particle in lane 0 of a block; the other lanes have no fluid.
  alignas(64) DragLanes eps{}, d{}, s2{}, c{};
  eps[0] = porosity;
  d[0] = diameter_m;
  s2[0] = slip_speed_m_s * slip_speed_m_s;
  FoldedDrag folded;
  law.fold(eps, d, fluid, folded);
  law.coefficient(folded, s2, c);
  return c[0] / sphere_volume(diameter_m);
}

DragEvaluation evaluate_drag(const DragLawEntry& law, double porosity, const Vec3& fluid_velocity,
                             const Vec3& particle_velocity, double diameter_m, const FluidProperties& fluid) {
  DragEvaluation out;
  const Vec3 slip = fluid_velocity - particle_velocity;
  const double speed = slip.norm();
  out.reynolds = particle_reynolds(porosity, speed, diameter_m, fluid);
  out.force_coefficient = force_coefficient(law, porosity, speed, diameter_m, fluid);
  out.beta = out.force_coefficient * (1.0 - porosity);
  out.force = sphere_volume(diameter_m) * out.force_coefficient * slip;  // Eq. 11
  return out;
}

double drag_jump_at_switch(double slip_speed_m_s, double diameter_m, const FluidProperties& fluid) {
  const DragLawEntry& law = drag_law("ergun_wen_yu");
  const double below = std::nextafter(ergun_wen_yu_switch, 0.0);
  return force_coefficient(law, below, slip_speed_m_s, diameter_m, fluid) /
         force_coefficient(law, ergun_wen_yu_switch, slip_speed_m_s, diameter_m, fluid);
}

}  // namespace fdem

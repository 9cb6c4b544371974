#include "coupling/coupled_step_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "coupling/drag.hpp"
#include "coupling/drag_coupling.hpp"
#include "scene/stability.hpp"

namespace fdem {

CoupledStepBounds assess_coupled_step(const Scene& scene, const BoxMesh& mesh, const Particles& particles,
                                      const ParticleMapping& mapping, std::span<const double> porosity,
                                      std::span<const double> fluid_velocity, double fluid_step_s, double dem_step_s) {
  CoupledStepBounds b;
  b.fluid_step_s = fluid_step_s;
  b.dem_step_s = dem_step_s;
  const FluidProperties fluid{scene.fluid.density, scene.fluid.viscosity};
  std::vector<double> exchange(static_cast<std::size_t>(mesh.num_elements()), 0.0);  // sum V_p K per element
  const std::size_t n = std::min(particles.size(), mapping.element.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Index e = mapping.element[i];
    if (e < 0 || !std::isfinite(particles.diameter[i])) continue;
    const double eps = porosity[static_cast<std::size_t>(e)];
    double k = force_coefficient(drag_law(scene.effects.drag), eps, 0.0, particles.diameter[i], fluid);  // viscous limit
    if (grain_drag_form(scene.fluid.model) == GrainDragForm::drag_over_porosity) k /= eps;  // model B: f_d / eps
    const double volume = sphere_volume(particles.diameter[i]);
    exchange[static_cast<std::size_t>(e)] += volume * k;
    b.drag_ratio = std::max(b.drag_ratio, 0.5 * k * dem_step_s / (particles.mass[i] / volume));
  }
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const double eps = porosity[static_cast<std::size_t>(e)];
    const double ratio = 0.5 * exchange[static_cast<std::size_t>(e)] * fluid_step_s /
                         (scene.fluid.density * eps * mesh.element_volume(e));
    if (ratio > b.exchange_ratio) {
      b.exchange_ratio = ratio;
      b.exchange_element = e;
      b.exchange_porosity = eps;
    }
  }
  if (scene.effects.normal_contact && particles.size() > 0) {
    const StabilityReport report =
        analyse_stability(scene.contact, scene.effects, mass_range(particles), dem_step_s, scene.effects.walls);
    b.contact_ratio = dem_step_s / report.stable_step_s();
  }
  const Vec3 length = scene.domain.upper - scene.domain.lower;
  const double h = std::min({length.x() / scene.cells[0], length.y() / scene.cells[1], length.z() / scene.cells[2]});
  double max_speed2 = 0.0;
  for (std::size_t k = 0; k + 2 < fluid_velocity.size(); k += 3)
    max_speed2 = std::max(max_speed2, fluid_velocity[k] * fluid_velocity[k] + fluid_velocity[k + 1] * fluid_velocity[k + 1] +
                                          fluid_velocity[k + 2] * fluid_velocity[k + 2]);
  b.cfl = std::sqrt(max_speed2) * fluid_step_s / h;
  return b;
}

std::string CoupledStepBounds::cause() const {
  const std::string ratios =
      fmt::format("(drag exchange lambda dt_fluid / 2 = {:.3g}, drag on grains K dt_dem / (2 rho_p) = {:.3g}, contacts "
                  "dt_dem / stable bound = {:.3g}, fluid CFL = {:.3g})",
                  exchange_ratio, drag_ratio, contact_ratio, cfl);
  const double worst = std::max({exchange_ratio, drag_ratio, contact_ratio});
  if (worst <= 1.0)
    return "no step bound is exceeded " + ratios + (cfl > 1.0 ? "; the fluid CFL above 1 is the likeliest cause" : "");
  if (worst == exchange_ratio)
    return fmt::format("the fluid step {:g} s is at fault: the drag exchange with the grains of element {} (porosity "
                       "{:.3g}) is unstable for an explicit source; reduce time.fluid_step below {:.3g} s {}",
                       fluid_step_s, exchange_element, exchange_porosity, fluid_step_s / exchange_ratio, ratios);
  if (worst == drag_ratio)
    return fmt::format("the DEM step {:g} s is at fault: the drag relaxes the grains faster than one subcycle; "
                       "reduce time.dem_step below {:.3g} s {}",
                       dem_step_s, dem_step_s / drag_ratio, ratios);
  return fmt::format("the DEM step {:g} s is at fault: above the contacts' stable bound; reduce time.dem_step below "
                     "{:.3g} s {}",
                     dem_step_s, dem_step_s / contact_ratio, ratios);
}

}  // namespace fdem

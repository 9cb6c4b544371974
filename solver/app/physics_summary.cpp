#include "app/physics_summary.hpp"

#include <iterator>
#include <string>

#include <fmt/format.h>

#include "coupling/source_term.hpp"
#include "drag_laws/drag_law.hpp"
#include "scene/scene_schema.hpp"

namespace fdem {

std::vector<std::pair<std::string, std::string>> active_physics(const Scene& scene) {
  const Effects& e = scene.effects;
  std::string effects;
  auto add = [&](bool on, const char* name) {
    if (on) effects += (effects.empty() ? "" : ", ") + std::string(name);
  };
  add(e.gravity, "gravity");
  add(e.fluid && e.buoyancy, "buoyancy");
  const std::string normal_contact = fmt::format("normal contact ({})", contact_law_entry(scene.contact.law).summary);
  add(e.normal_contact, normal_contact.c_str());
  add(e.tangential_contact, "tangential contact (Eq. 7-8)");
  add(e.rotation, "rotation (Eq. 10)");
  add(e.walls, "walls");
  std::vector<std::pair<std::string, std::string>> out{{"effects", effects.empty() ? "none" : effects}};
  if (!e.fluid) {
    out.emplace_back("fluid", "none (dry DEM)");
    return out;
  }
  const FluidSpec& f = scene.fluid;
  const char* model = f.model == FluidModel::vans_a   ? "volume-averaged Navier-Stokes set II (vans_a, Eq. 18-19)"
                      : f.model == FluidModel::vans_b ? "volume-averaged Navier-Stokes set I (vans_b, Eq. 18-19)"
                                                      : "incompressible Navier-Stokes, drag / eps as body force (Eq. 21-22)";
  const char* scheme = f.scheme == FluidScheme::projection
                           ? "P1/P1 incremental projection (rotational; SUPG predictor, pressure Poisson)"
                           : "P1/P1 SUPG/PSPG + LSIC";
  out.emplace_back("fluid", fmt::format("{}{}, {}, {}, {} advection, rho {:g} kg/m^3, mu {:g} Pa s",
                                        model, f.porosity_time_derivative ? " with d(eps)/dt" : "", scheme,
                                        f.time_scheme == TimeScheme::bdf2 ? "BDF2" : "BDF1",
                                        f.linearization == FluidLinearization::picard ? "Picard" : "extrapolated",
                                        f.density, f.viscosity));
  if (e.coupling == CouplingMode::off || scene.particles.empty()) return out;
  out.emplace_back("coupling", std::string(choice_word("effects.coupling", static_cast<std::size_t>(e.coupling))));
  const DragLawEntry& law = drag_law(e.drag);
  out.emplace_back("drag", fmt::format("{} ({})", law.name, law.doc));
  const PorositySchemeEntry& porosity = porosity_scheme_entry(scene.coupling.porosity);
  out.emplace_back("porosity",
                   fmt::format("{} ({}), floor {:g}", porosity.name, porosity.summary, scene.coupling.porosity_floor));
  if (e.coupling == CouplingMode::particle_to_fluid || e.coupling == CouplingMode::two_way) {
    std::string exchange = fmt::format("{}, {}", momentum_exchange_entry(scene.coupling.exchange).summary,
                                       source_form_entry(fluid_source_form(scene)).summary);
    if (scene.fluid.model == FluidModel::vans_b) exchange += ", grains feel drag / eps (Zhou et al. 2010 model B)";
    if (scene.coupling.freeze_until > 0.0) exchange += fmt::format(", grains frozen until {:g} s", scene.coupling.freeze_until);
    out.emplace_back("exchange", exchange);
  }
  return out;
}

}  // namespace fdem

#pragma once
// Scenes of the hard cases, built in code (SI units). Each function states the
// physical situation; the tests change one setting at a time.
#include <string>

#include "scene/scene.hpp"
#include "scene/tests/dry_box_scene.hpp"
#include "scene/tests/paper_channel_contact.hpp"
#include "scene/tests/uniform_lattice_of_grains.hpp"

namespace fdem::hard {

/// The paper's channel-flow grains and contact (Sect. 4.3, Table 3): d uniform
/// in [0.2, 0.3] mm, rho 2170, Kn 1e5 N/m, Cn 0.026 N s/m, DEM step 1e-5 s
/// (15 contact times of a 0.2 mm pair). Dry: a 5 x 5 x 10 lattice of grains at
/// 0.3 mm spacing (touching at most) in a walled 1.5 x 1.5 x 3.5 mm box,
/// falling at 5 cm/s onto the floor under gravity.
inline Scene paper_channel_contact_bed() {
  Scene s = scene_test::dry_box_scene("hard_cases/channel_contact", Vec3(1.5e-3, 1.5e-3, 3.5e-3));
  s.particles.push_back(scene_test::uniform_lattice_of_grains("bed", {Vec3::Zero(), Vec3(1.5e-3, 1.5e-3, 3.0e-3)},
                                                             {5, 5, 10}, {0.2e-3, 0.3e-3}, 2170.0,
                                                             Vec3(0.0, 0.0, -0.05), 20240602));
  s.contact = scene_test::paper_channel_contact();
  s.time.dem_step = 1e-5;
  s.time.fluid_step = 0.0;  // dry: one DEM step per Simulation::step
  s.time.end_time = 1.0;
  return s;
}

/// A fluid-filled box of n^3 cubic cells of size h [m], water, no-slip walls,
/// no particles, BDF2; the caller adds particles, boundaries and times.
inline Scene water_box(int n_x, int n_y, int n_z, double h_m) {
  Scene s;
  s.source_file = "hard_cases/water_box";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(n_x * h_m, n_y * h_m, n_z * h_m);
  s.cells = {n_x, n_y, n_z};
  s.effects.fluid = true;
  s.effects.coupling = CouplingMode::two_way;
  s.fluid.density = 1000.0;
  s.fluid.viscosity = 1.0e-3;
  return s;
}

/// The `fluid:` block of a scene file: water (1000 kg/m^3, 1e-3 Pa s) driven
/// along x, entering at x_min at `inlet_speed` (YAML number, m/s) and leaving
/// at x_max; the other faces no-slip. A caller may add keys of the block
/// (two-space indent) right after it.
inline std::string water_along_x_yaml(const std::string& inlet_speed) {
  return R"(fluid:
  density: 1000
  viscosity: 1.0e-3
  boundaries:
    x_min: {type: inlet, velocity: [)" +
         inlet_speed + R"(, 0, 0]}
    x_max: outlet
)";
}

/// A soft contact (Kn 10 N/m, e 0.5) for the cases that do not test grain
/// contact (a grain settling, rising, leaving or stuck before its first DEM
/// step): it only has to pass the stability check at the case's DEM step.
inline ContactSpec soft_contact() {
  ContactSpec contact;
  contact.normal_stiffness = 10.0;
  contact.restitution = 0.5;
  return contact;
}

inline ParticleSet single_particle(const Vec3& position_m, double diameter_m, double density_kg_m3,
                                   const Vec3& velocity_m_s = Vec3::Zero()) {
  ParticleSet p;
  p.name = "single";
  p.placement = PlacementKind::single;
  p.position = position_m;
  p.size.kind = SizeKind::fixed;
  p.size.diameter = diameter_m;
  p.density = density_kg_m3;
  p.velocity = velocity_m_s;
  return p;
}

}  // namespace fdem::hard

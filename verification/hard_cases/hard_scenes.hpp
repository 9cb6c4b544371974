#pragma once
// Scenes of the hard cases, built in code (SI units). Each function states the
// physical situation; the tests change one setting at a time.
#include "scene/scene.hpp"

namespace fdem::hard {

/// The paper's channel-flow grains and contact (Sect. 4.3, Table 3): d uniform
/// in [0.2, 0.3] mm, rho 2170, Kn 1e5 N/m, Cn 0.026 N s/m, DEM step 1e-5 s
/// (15 contact times of a 0.2 mm pair). Dry: a 5 x 5 x 10 lattice of grains at
/// 0.3 mm spacing (touching at most) in a walled 1.5 x 1.5 x 3.5 mm box,
/// falling at 5 cm/s onto the floor under gravity.
inline Scene paper_channel_contact_bed() {
  Scene s;
  s.source_file = "hard_cases/channel_contact";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(1.5e-3, 1.5e-3, 3.5e-3);
  s.effects.fluid = false;
  s.effects.coupling = CouplingMode::off;
  s.effects.buoyancy = false;
  ParticleSet bed;
  bed.name = "bed";
  bed.placement = PlacementKind::lattice;
  bed.region.lower = Vec3::Zero();
  bed.region.upper = Vec3(1.5e-3, 1.5e-3, 3.0e-3);
  bed.lattice = {5, 5, 10};
  bed.size.kind = SizeKind::uniform;
  bed.size.minimum = 0.2e-3;
  bed.size.maximum = 0.3e-3;
  bed.density = 2170.0;
  bed.velocity = Vec3(0.0, 0.0, -0.05);
  bed.seed = 20240602;
  s.particles.push_back(bed);
  s.contact.normal_stiffness = 1e5;
  s.contact.normal_damping = 0.026;
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

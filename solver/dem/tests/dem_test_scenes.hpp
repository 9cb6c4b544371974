#pragma once
// Test scenes the DEM's unit tests share: a lattice of grains with random
// sizes and velocities, and a dry walled box to step it in.
#include <cstdint>
#include <random>

#include "core/particles.hpp"
#include "scene/scene.hpp"

namespace fdem::dem_test {

// 3072 grains of 0.8-1.2 mm on a cubic lattice (16 x 16 x 12) of `spacing`
// [m] (none overlapping at 1.2 mm or more), velocities +-0.05 m/s per axis.
inline Particles lattice_grains(double spacing, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> d(0.8e-3, 1.2e-3), v(-0.05, 0.05);
  Particles p;
  for (int i = 0; i < 3072; ++i)
    p.add(1.5e-3 + (i % 16) * spacing, 1.5e-3 + (i / 16 % 16) * spacing, 1e-3 + (i / 256) * spacing, d(rng), 2500.0,
          v(rng), v(rng), v(rng));
  return p;
}

// A walled box from the origin to `upper`, grains only: no fluid, no
// coupling, no buoyancy (the contact law and step are the caller's).
inline Scene dry_box_scene(const char* source_file, const Vec3& upper) {
  Scene s;
  s.source_file = source_file;
  s.domain.upper = upper;
  s.effects.fluid = false;
  s.effects.coupling = CouplingMode::off;
  s.effects.buoyancy = false;
  return s;
}

}  // namespace fdem::dem_test

#pragma once
// The grains the DEM's unit tests share: a lattice with random sizes and
// velocities (the dry walled box to step it in: scene/tests/dry_box_scene.hpp).
#include <cstdint>
#include <random>

#include "core/particles.hpp"

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

}  // namespace fdem::dem_test

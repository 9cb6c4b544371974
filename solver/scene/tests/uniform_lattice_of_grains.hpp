#pragma once
// Grains on a lattice filling a region (placement: lattice), diameters
// uniform in [d_min, d_max] drawn from a seed, all starting at one velocity:
// the beds of the checkpoint tests (solver/coupling/tests) and the hard
// cases (verification/hard_cases), built in code. Test code only.
#include <array>
#include <cstdint>
#include <string>
#include <utility>

#include "scene/scene.hpp"

namespace fdem::scene_test {

struct UniformSizes {
  double minimum_m = 0.0, maximum_m = 0.0;
};

inline ParticleSet uniform_lattice_of_grains(std::string name, const Box& region_m, const std::array<int, 3>& lattice,
                                             UniformSizes diameters, double density_kg_m3, const Vec3& velocity_m_s,
                                             std::uint64_t seed) {
  ParticleSet p;
  p.name = std::move(name);
  p.placement = PlacementKind::lattice;
  p.region = region_m;
  p.lattice = lattice;
  p.size.kind = SizeKind::uniform;
  p.size.minimum = diameters.minimum_m;
  p.size.maximum = diameters.maximum_m;
  p.density = density_kg_m3;
  p.velocity = velocity_m_s;
  p.seed = seed;
  return p;
}

}  // namespace fdem::scene_test

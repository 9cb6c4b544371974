#pragma once
// A dry DEM scene built in code: the box [0, upper] with walls and gravity,
// no fluid, so no coupling and no buoyancy; the caller adds the grains, the
// contact and the DEM step. Shared by the checkpoint tests
// (solver/coupling/tests) and the hard cases (verification/hard_cases).
// Test code only.
#include <string>
#include <utility>

#include "scene/scene.hpp"

namespace fdem::scene_test {

inline Scene dry_box_scene(std::string source_file, const Vec3& upper_m) {
  Scene s;
  s.source_file = std::move(source_file);
  s.domain.lower = Vec3::Zero();
  s.domain.upper = upper_m;
  s.effects.fluid = false;
  s.effects.coupling = CouplingMode::off;
  s.effects.buoyancy = false;
  return s;
}

}  // namespace fdem::scene_test

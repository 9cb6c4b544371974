#pragma once
// A dry DEM scene for the verification tests: no fluid, the given box.
#include "scene/scene.hpp"

namespace fdem::verification {

inline Scene dry_scene(double box_m, double kn, double dt, bool gravity, bool walls) {
  Scene s;
  s.source_file = "verification/dem";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3::Constant(box_m);
  s.effects.fluid = false;
  s.effects.coupling = CouplingMode::off;
  s.effects.buoyancy = false;
  s.effects.gravity = gravity;
  s.effects.walls = walls;
  s.contact.normal_stiffness = kn;
  s.time.dem_step = dt;
  return s;
}

}  // namespace fdem::verification

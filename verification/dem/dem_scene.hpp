#pragma once
// A dry DEM scene for the verification tests: no fluid, the cube [0, box_m]^3.
#include "scene/scene.hpp"
#include "scene/tests/dry_box_scene.hpp"

namespace fdem::verification {

inline Scene dry_scene(double box_m, double kn, double dt, bool gravity, bool walls) {
  Scene s = scene_test::dry_box_scene("verification/dem", Vec3::Constant(box_m));
  s.effects.gravity = gravity;
  s.effects.walls = walls;
  s.contact.normal_stiffness = kn;
  s.time.dem_step = dt;
  return s;
}

}  // namespace fdem::verification

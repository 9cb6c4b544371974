#pragma once
// Particle storage as structure of arrays: each hot quantity contiguous, so the
// per-particle loops vectorise and stream through cache.
#include <cstddef>
#include <vector>

namespace fdem {

struct Particles {
  std::vector<double> x, y, z;        // position [m]
  std::vector<double> vx, vy, vz;     // velocity [m/s]
  std::vector<double> fx, fy, fz;     // force [N]
  std::vector<double> diameter;       // [m]
  std::vector<double> mass;           // [kg]
  // Rotation is an effect: these stay empty when the scene leaves it off.
  std::vector<double> wx, wy, wz;     // angular velocity [rad/s]
  std::vector<double> tx, ty, tz;     // torque [N m]
  std::vector<double> inertia;        // moment of inertia [kg m^2]

  std::size_t size() const { return x.size(); }
};

}  // namespace fdem

#pragma once
// Particle storage as structure of arrays: each hot quantity contiguous, so the
// per-particle loops vectorise and stream through cache (each array at its own
// cache-set offset: core/grain_array.hpp). In core because every
// layer above holds particles: the scene draws them, io writes them, the DEM
// moves them, the coupling maps them.
#include <cstddef>
#include <vector>

#include "core/grain_array.hpp"
#include "core/types.hpp"

namespace fdem {

struct Particles {
  GrainArray x, y, z;        // position [m]
  GrainArray vx, vy, vz;     // velocity [m/s]
  GrainArray fx, fy, fz;     // force [N]
  GrainArray diameter;       // [m]
  GrainArray mass;           // [kg]
  // Rotation is an effect: these stay empty when the scene leaves it off.
  GrainArray wx, wy, wz;     // angular velocity [rad/s]
  GrainArray tx, ty, tz;     // torque [N m]
  GrainArray inertia;        // moment of inertia [kg m^2]
  // Identity of each particle as created (its index at start). Particles that
  // leave the domain are removed by the DEM engine, which shifts indices;
  // `id` keeps the original label. Empty until the engine fills it.
  std::vector<Index> id;

  std::size_t size() const { return x.size(); }

  /// Appends one sphere at rest (force zero); rotation arrays untouched.
  void add(double x_m, double y_m, double z_m, double diameter_m, double density_kg_m3,
           double vx_m_s = 0.0, double vy_m_s = 0.0, double vz_m_s = 0.0) {
    x.push_back(x_m); y.push_back(y_m); z.push_back(z_m);
    vx.push_back(vx_m_s); vy.push_back(vy_m_s); vz.push_back(vz_m_s);
    fx.push_back(0.0); fy.push_back(0.0); fz.push_back(0.0);
    diameter.push_back(diameter_m);
    mass.push_back(density_kg_m3 * sphere_volume(diameter_m));
  }
};

}  // namespace fdem

#pragma once
// Vocabulary types shared by every module. SI units everywhere.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <numbers>

namespace fdem {

using Vec3 = Eigen::Vector3d;
using Index = std::int32_t;  // nodes, elements, particles: 2^31 is far beyond a 2-core run

inline constexpr double pi = std::numbers::pi;

/// Volume of a sphere of diameter d [m^3].
constexpr double sphere_volume(double diameter_m) {
  return pi / 6.0 * diameter_m * diameter_m * diameter_m;
}

}  // namespace fdem

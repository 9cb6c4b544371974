#pragma once
// Drag as the DEM engine's external force, evaluated in every DEM subcycle
// (Fig. 3) with the particle's current velocity and the fluid velocity frozen
// over the fluid step (interpolated at the particle with P1 shape functions at
// the start of the step). Evaluating it in every subcycle matters: the
// response time rho_p d^2 / (18 mu) of a 0.208 mm grain in water is 6.4 ms,
// shorter than the 10 ms fluid step, so drag held fixed over a fluid step
// would be unstable.
//
// It also accumulates each particle's drag over the subcycles, so the fluid
// receives the mean drag of the step: exactly the impulse the particles got.
//
// Cost split (the subcycle is the hot loop: 100 per fluid step in the plume).
// Over a fluid step the porosity eps, the fluid velocity u at the particle and
// the diameter d are frozen, so begin_step() folds every factor of Eq. 11-15
// that depends on them alone into three coefficients per particle, whatever
// the law (drag.hpp; V_p = pi d^3 / 6, a = eps rho d / mu so Re = a |u - v|):
//   f = c (u - v),   c = c0 + c1 s + c2 s^0.687,  s = |u - v|      (Re <= 1000)
//                    c = c0 (0.44 / 24) a s                          (Re > 1000, Wen & Yu only)
//   Ergun (Eq. 12):    c0 = V_p 150 (1-eps) mu / (eps d^2), c1 = V_p 1.75 rho / d, c2 = 0, a = 0
//   Wen & Yu (13, 14): c0 = V_p 18 mu / d^2 eps^-2.65,       c1 = 0, c2 = 0.15 a^0.687 c0
//   Stokes:            c0 = V_p 18 mu / d^2,                  c1 = c2 = a = 0
//   outside the mesh:  all zero (no fluid, no drag)
// (Wen & Yu: V_p K = V_p 3/4 Cd eps rho s / d eps^-2.65 with Cd s = 24 mu /
// (eps rho d) (1 + 0.15 Re^0.687) gives c0 (1 + 0.15 a^0.687 s^0.687); above
// Re = 1000, Cd = 0.44 gives c0 (0.44/24) a s.) The subcycle then needs only
// the slip: s^2, s = sqrt(s^2), and s^0.687 = (s^2)^0.3435 (the same double
// exponent halved, an exact rewrite; the switch Re > 1000 is tested as
// a^2 s^2 > 1e6; s itself only in a block where some lane is Ergun or above
// Re = 1000). That power is the one transcendental left per particle and
// subcycle: it has no closed form, so it is evaluated eight particles at a
// time as exp(0.3435 log s^2) by glibc's vectorised exp and log (libmvec)
// where available.
//
// Compared with force_coefficient() evaluated per particle (drag.cpp), the
// folded constants and the vectorised exp/log change the force in the last
// bits only (tests/test_drag.cpp bounds it). The result of a
// particle does not depend on the thread count, its position in the block
// or the memory address of the arrays: every particle goes through the same
// eight-wide block kernel (the last block padded with zero-drag lanes).
#include <array>
#include <span>
#include <vector>

#include "coupling/drag.hpp"
#include "coupling/particle_mapping.hpp"
#include "dem/dem_engine.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem {

class DragCoupling final : public ExternalForce {
 public:
  /// Particles per block of the subcycle kernel: the widest vector of
  /// doubles (AVX-512) so no lane of a block is ever left to scalar code.
  static constexpr std::size_t block_size = 8;

  /// apply_to_particles: false in particle_to_fluid mode (drag computed for
  /// the fluid, not felt by the particles).
  DragCoupling(DragLaw law, FluidProperties fluid, bool apply_to_particles);

  /// Start a fluid step: fluid velocity at each particle (P1 interpolation of
  /// the nodal field in its element), its element's porosity, and from these
  /// the per-particle drag coefficients (header comment); zero the
  /// accumulated drag. `particles` are those `mapping` was built from.
  void begin_step(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles,
                  std::span<const double> fluid_velocity, std::span<const double> porosity);

  /// Drag with the current particle velocities, added to fx, fy, fz (when
  /// applied to the particles) and to the step's accumulated drag.
  void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) override;

  /// Turn the accumulated sums into means (call once after the subcycles).
  void end_step();
  /// Mean drag per particle over the evaluations since begin_step [N]
  /// (valid after end_step; zero when no subcycle ran).
  std::span<const double> mean_drag_x() const { return mean_x_; }
  std::span<const double> mean_drag_y() const { return mean_y_; }
  std::span<const double> mean_drag_z() const { return mean_z_; }
  /// Sum over particles of the mean drag [N] (after end_step).
  Vec3 total_mean_drag() const;
  /// True when the particle count changed during the step (particles removed
  /// by the DEM): the fluid velocities were re-interpolated from the new order.
  bool remapped() const { return remapped_; }
  /// Wall time spent in add() since begin_step [s] (part of the DEM subcycles' time).
  double evaluation_seconds() const { return evaluation_seconds_; }

 private:
  // Frozen over the step, then the step's drag sums: eight particles a block,
  // all their data in ten consecutive cache lines (aligned, so the vector
  // loops need no peeling).
  struct alignas(64) Block {
    std::array<double, block_size> ux, uy, uz;  // fluid velocity at the particle [m/s]
    std::array<double, block_size> c0;          // [kg/s]
    std::array<double, block_size> c1;          // [kg/m]
    std::array<double, block_size> c2;          // [kg s^-0.313 m^-0.687]
    std::array<double, block_size> a;           // Re per slip speed, Wen & Yu only [s/m]
    std::array<double, block_size> sum_x, sum_y, sum_z;  // drag summed over the subcycles [N]
  };

  void prepare(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles);

  DragLaw law_;
  FluidProperties fluid_;
  bool apply_;
  const BoxMesh* mesh_ = nullptr;
  std::span<const double> nodal_velocity_, porosity_;
  ParticleMapping own_mapping_;  // used only when particles are removed mid-step
  std::size_t particles_ = 0;    // particle count the blocks were prepared for
  std::vector<Block> blocks_;
  std::vector<double> mean_x_, mean_y_, mean_z_;  // mean drag of the step (end_step)
  long evaluations_ = 0;
  bool remapped_ = false;
  double evaluation_seconds_ = 0.0;
};

}  // namespace fdem

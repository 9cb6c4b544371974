#pragma once
// Drag as the DEM engine's external force, evaluated in every DEM subcycle
// (Fig. 3) with the particle's current velocity and the fluid velocity frozen
// over the fluid step (interpolated at the particle with P1 shape functions at
// the start of the step). Evaluating it in every subcycle matters: the
// response time rho_p d^2 / (18 mu) of a 0.208 mm grain in water is 6.4 ms,
// shorter than the 10 ms fluid step, so drag held fixed over a fluid step
// would be unstable (DESIGN.md pitfall).
//
// It also accumulates each particle's drag over the subcycles, so the fluid
// receives the mean drag of the step: exactly the impulse the particles got.
#include <span>
#include <vector>

#include "coupling/drag.hpp"
#include "coupling/particle_mapping.hpp"
#include "dem/dem_engine.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem {

class DragCoupling final : public ExternalForce {
 public:
  /// apply_to_particles: false in particle_to_fluid mode (drag computed for
  /// the fluid, not felt by the particles).
  DragCoupling(DragLaw law, FluidProperties fluid, bool apply_to_particles);

  /// Start a fluid step: fluid velocity at each particle (P1 interpolation of
  /// the nodal field in its element) and its element's porosity; zero the
  /// accumulated drag.
  void begin_step(const BoxMesh& mesh, const ParticleMapping& mapping, std::span<const double> fluid_velocity,
                  std::span<const double> porosity);

  void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) override;

  /// Mean drag per particle over the evaluations since begin_step [N].
  std::span<const double> mean_drag_x() const { return mean_x_; }
  std::span<const double> mean_drag_y() const { return mean_y_; }
  std::span<const double> mean_drag_z() const { return mean_z_; }
  /// Turn the accumulated sums into means (call once after the subcycles).
  void end_step();
  /// Sum over particles of the mean drag [N] (after end_step).
  Vec3 total_mean_drag() const;
  /// True when the particle count changed during the step (particles removed
  /// by the DEM): the fluid velocities were re-interpolated from the new order.
  bool remapped() const { return remapped_; }

 private:
  void interpolate(const BoxMesh& mesh, const ParticleMapping& mapping);

  DragLaw law_;
  FluidProperties fluid_;
  bool apply_;
  const BoxMesh* mesh_ = nullptr;
  std::span<const double> nodal_velocity_, porosity_;
  ParticleMapping own_mapping_;  // used only when particles are removed mid-step
  std::vector<double> ux_, uy_, uz_, eps_;                  // per particle, frozen over the step
  std::vector<double> mean_x_, mean_y_, mean_z_;            // accumulated, then mean
  long evaluations_ = 0;
  bool remapped_ = false;
};

}  // namespace fdem

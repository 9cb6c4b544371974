#pragma once
// The grains' fluid-stress forces of the volume-averaged model A (Zhou, Kuang,
// Chu & Yu 2010, J. Fluid Mech. 661, set II; paper Eq. 19 with the fluid
// carrying -eps grad p + div(eps tau)): besides the drag each grain feels
//
//   pressure-gradient force   f_p = -V_p grad p                 (p the DYNAMIC pressure)
//   viscous-stress force      f_t =  V_p div tau                (omitted: see below)
//
// The fluid solver's p is the dynamic pressure (fluid/fluid_solver.hpp): the
// full pressure's -V_p grad P = -V_p grad p - V_p rho_f g, and its second part
// is the buoyancy of Eq. 5, which the DEM already applies (effects.buoyancy).
// Adding -V_p grad p only therefore counts buoyancy once.
// grad p is taken as the fluid's porosity takes the grains' solid, so that
// the grains feel exactly what the fluid's -eps_h grad p leaves out: the
// fluid weights the P1 pressure's element gradient G_e with the P1 porosity
// eps_h, the lumped projection of the element porosity eps_e
// (fluid/fluid_solver.hpp), so it gives up
//   int (1 - eps_h) grad p = sum_e V_e (1 - eps_e) Ghat_e,
//   Ghat_e = mean over e's nodes of Gbar_a, Gbar_a = sum_{e ni a} V_e G_e / sum V_e
// (the sums over nodes and elements swap). Each grain takes V_p times its
// share of Ghat, the transpose of where its solid went in V_e (1 - eps_e)
// (PorosityField::grain_means): the centre scheme's Ghat of the grain's
// element, the shape-function scheme's P1 interpolation at the centre of
// Ghat projected to the nodes once more, the intersection scheme's mean of
// Ghat over the elements the sphere overlaps. The grains and the fluid then
// exchange the pressure force as they do the drag, to round-off, and a
// steady bed's pressure drop is its buoyant weight less what the floor
// carries (tests/test_fluid_stress_force.cpp). With each grain's own element
// gradient G_e instead, the grains at a bed's ends, where eps_h goes from
// the bed's to 1 over a cell, took more than the fluid gave: a fluidized
// bed's plateau came out 4 % of its weight below it at cell / d = 2
// (verification/fluidized_bed/README.md). The price: a grain near a bed's
// surface feels the gradient averaged over about two cells, less than its
// own element's. It is taken after the fluid step and held over the DEM
// subcycles like the fluid velocity of the drag.
// div tau: for P1 velocity mu lap u vanishes inside every element, so the
// consistent element value is zero; a recovered (patch-averaged) gradient
// would give a nonzero one, but in a bed the term is of order (d / L)^2 of
// the drag (Zhou et al. 2010 Sect. 2) and it is left out.
// It wraps the drag (or any other ExternalForce): the DEM takes one.
#include <span>
#include <vector>

#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "dem/dem_engine.hpp"
#include "core/particles.hpp"
#include "fluid/fluid_solver.hpp"

namespace fdem {

/// Ghat_e: the element mean of the volume-weighted nodal mean Gbar_a of the
/// element gradients G_e (one per element, the same size).
std::vector<Vec3> projected_element_gradient(const BoxMesh& mesh, std::span<const Vec3> element_gradient);

/// Each grain's pressure gradient as model A's grains feel it: its share of
/// projected_element_gradient(G) where `porosity` (updated for these
/// particles and this mapping) put its solid. Sum_i V_p,i out[i] =
/// int (1 - eps_h) G, the fluid's eps_h made from porosity's values.
void grain_pressure_gradients(const BoxMesh& mesh, std::span<const Vec3> element_gradient, PorosityField& porosity,
                              const ParticleMapping& mapping, const Particles& particles, std::span<Vec3> out);

class FluidStressForce final : public ExternalForce {
 public:
  /// `inner` (may be null) is added first in every evaluation.
  explicit FluidStressForce(ExternalForce* inner) : inner_(inner) {}

  /// Per-particle -V_p grad p from the fluid's current pressure, shared out
  /// as `porosity` (updated for these particles and this mapping) deposited
  /// their solid; particles that deposited nothing get none.
  void begin_step(const ParticleMapping& mapping, const Particles& particles, const FluidSolver& fluid,
                  PorosityField& porosity);

  /// inner's force, then the stored pressure-gradient forces (skipped when
  /// the particle count changed since begin_step: grains were removed).
  void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) override;

  /// Decomposed over MPI ranks (ExternalForce): inner's state, then each
  /// grain's -V_p grad p, move with the grains; grains lost on any rank end
  /// the pressure force for the rest of the step, as in one process.
  std::vector<std::vector<double>> carried_state(const Particles& p) const override;
  void grains_redistributed(const Particles& p, std::vector<std::vector<double>>&& carried,
                            bool lost_anywhere) override;

  std::span<const double> force_x() const { return fx_; }
  std::span<const double> force_y() const { return fy_; }
  std::span<const double> force_z() const { return fz_; }

 private:
  ExternalForce* inner_;
  std::vector<double> fx_, fy_, fz_;
  std::vector<Vec3> element_gradient_;  // G_e
  std::vector<Vec3> grain_gradient_;    // each grain's share of Ghat
};

}  // namespace fdem

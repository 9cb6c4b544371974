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
// grad p is the P1 pressure's, constant in the grain's element
// (FluidSolver::pressure_gradient), taken after the fluid step and held over
// the DEM subcycles like the fluid velocity of the drag.
// div tau: for P1 velocity mu lap u vanishes inside every element, so the
// consistent element value is zero; a recovered (patch-averaged) gradient
// would give a nonzero one, but in a bed the term is of order (d / L)^2 of
// the drag (Zhou et al. 2010 Sect. 2) and it is left out.
// It wraps the drag (or any other ExternalForce): the DEM takes one.
#include <span>
#include <vector>

#include "coupling/particle_mapping.hpp"
#include "dem/dem_engine.hpp"
#include "core/particles.hpp"
#include "fluid/fluid_solver.hpp"

namespace fdem {

class FluidStressForce final : public ExternalForce {
 public:
  /// `inner` (may be null) is added first in every evaluation.
  explicit FluidStressForce(ExternalForce* inner) : inner_(inner) {}

  /// Per-particle -V_p grad p from the fluid's current pressure; particles
  /// whose centre is outside the mesh get none.
  void begin_step(const ParticleMapping& mapping, const Particles& particles, const FluidSolver& fluid);

  /// inner's force, then the stored pressure-gradient forces (skipped when
  /// the particle count changed since begin_step: grains were removed).
  void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) override;

  std::span<const double> force_x() const { return fx_; }
  std::span<const double> force_y() const { return fy_; }
  std::span<const double> force_z() const { return fz_; }

 private:
  ExternalForce* inner_;
  std::vector<double> fx_, fy_, fz_;
};

}  // namespace fdem

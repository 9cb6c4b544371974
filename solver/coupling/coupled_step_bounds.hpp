#pragma once
// Which step of a coupled run is too large, for the message of a blow-up.
// Three explicit parts of the coupled step each have a stability bound:
//   - the fluid step through the drag exchange: the fluid receives the
//     particles' drag as an explicit source (Fig. 2, Eq. 21-22), a relaxation
//     at rate lambda_e = sum_i V_p K_i / (rho_f eps_e V_e) per element; explicit
//     relaxation is stable for lambda dt_fluid < 2;
//   - the DEM step through the drag: each subcycle applies f = V_p K (u - v)
//     explicitly, a relaxation at rate K / rho_p: stable for K dt_dem / rho_p < 2;
//   - the DEM step through the contacts: dt_dem / the stable bound of
//     scene/stability.hpp (1 at the bound).
// K is taken in its viscous limit (slip 0), a lower bound of the drag at any
// slip, so a ratio above its bound is at fault whatever the blown-up
// velocities. The fluid CFL number (max |u| dt / h) is reported beside them:
// the implicit fluid step is stable at any CFL, but above 1 a grain's fluid
// velocity, frozen over the subcycles, comes from a cell it has left.
#include <span>
#include <string>

#include "core/particles.hpp"
#include "coupling/particle_mapping.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct CoupledStepBounds {
  double exchange_ratio = 0.0;  // max_e lambda_e dt_fluid / 2
  Index exchange_element = -1;
  double exchange_porosity = 1.0;
  double drag_ratio = 0.0;      // max_i K_i dt_dem / rho_p,i / 2
  double contact_ratio = 0.0;   // dt_dem / the contacts' stable step
  double cfl = 0.0;             // max |u| dt_fluid / smallest cell edge
  double fluid_step_s = 0.0, dem_step_s = 0.0;
  /// One sentence naming the step at fault (the largest ratio above 1) and
  /// how far to reduce it, with the other ratios.
  std::string cause() const;
};

CoupledStepBounds assess_coupled_step(const Scene& scene, const BoxMesh& mesh, const Particles& particles,
                                      const ParticleMapping& mapping, std::span<const double> porosity,
                                      std::span<const double> fluid_velocity, double fluid_step_s, double dem_step_s);

}  // namespace fdem

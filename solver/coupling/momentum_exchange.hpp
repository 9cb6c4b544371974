#pragma once
// The semi-implicit momentum exchange (scene coupling.exchange: semi_implicit).
//
// The explicit exchange hands the fluid last step's mean drag as a body
// force; in a packed bed (beta / rho ~ 3000 1/s) that bounds the fluid step
// to about 2 rho / beta. Here each grain's drag is linear in the velocities
// over a step, f_i = c_i (u - v_i), c_i = V_p K_i frozen from the end of the
// previous step (DragCoupling::freeze_coefficients), and per element e
//   beta_e = sum_{i in e} c_i / V_e                  [kg/(m^3 s)]
//   v_e    = sum_{i in e} c_i v_i / sum_{i in e} c_i  (K-weighted mean grain velocity)
// enter the fluid's momentum equation as the force density beta_e (v_e - u),
// beta_e u^{n+1} in its matrix and beta_e v_e on its right-hand side
// (FluidSolver::set_momentum_exchange; Lethe's VANS "semi-implicit" drag,
// CFDEM's implicitCouple). The grains feel the same c_i in every DEM
// subcycle with their current velocity and their element's mean fluid
// velocity <u>_e (the mean of its 4 nodes, the P1 field's element mean): the
// velocity beta_e multiplies in the fluid (CFDEM's default, cell values
// without interpolation). With the paper's source form (Eq. 22, F/eps; the
// simplified model only) beta_e is divided by eps_e, as the explicit source
// is; model B's c_i already carry their 1/eps (coupling/drag_coupling.hpp).
//
// Momentum balance over a step (conservative form): the fluid receives
//   sum_e V_e beta_e (v_e - <u^{n+1}>_e) = sum_i c_i (v_i^start - <u^{n+1}>_e(i)),
// the grains sum_i c_i (<u^{n+1}>_e(i) - <v_i>), so the two differ by
//   sum_i c_i (<v_i> - v_i^start):
// the grains' velocity change over the step, the one lag (v_e is taken
// before the subcycles). It vanishes at steady grain velocity; the run's
// CouplingDiagnostics report the imbalance of every step
// (tests/test_momentum_exchange.cpp). Interpolating u at the grain instead
// (P1, Eq. 28-31) would add sum_i c_i (u(x_i) - <u>_e(i)), which a bed's
// top layer, with ~0 below and the free stream above in one element, makes
// larger than the bed's net drag (measured 1.6x on the channel bed).
#include <span>
#include <vector>

#include "core/types.hpp"
#include "coupling/particle_mapping.hpp"
#include "core/particles.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/grain_share.hpp"
#include "scene/scene.hpp"

namespace fdem {

class SemiImplicitExchange {
 public:
  SemiImplicitExchange(const BoxMesh& mesh, SourceForm form);

  /// beta_e and v_e from the grains' frozen coefficients c_i [kg/s] (particle
  /// order of `mapping`), their velocities and the element porosity.
  /// Decomposed over MPI ranks (share): this rank's owned grains, the
  /// element sums then completed where this rank needs them
  /// (parallel/grain_share.hpp; 0 elsewhere).
  void compute(const Particles& particles, const ParticleMapping& mapping, std::span<const double> coefficients,
               std::span<const double> porosity, const GrainShare& share = {});
  /// No exchange (frozen start, or nothing to exchange).
  void clear();

  std::span<const double> element_beta() const { return beta_; }                 // num_elements [kg/(m^3 s)]
  std::span<const double> element_particle_velocity() const { return velocity_; }  // 3 per element [m/s]
  /// What the fluid receives for the nodal velocity u: sum_e V_e beta_e (v_e - <u>_e) [N].
  /// On several ranks (share with ElementSums) each element's owner adds it
  /// and the ranks' totals are added (a collective): rounding of the order.
  Vec3 force_on_fluid(std::span<const double> nodal_velocity, const GrainShare& share = {}) const;

 private:
  const BoxMesh* mesh_;
  SourceForm form_;
  std::vector<double> beta_, velocity_;
};

}  // namespace fdem

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
// the diameter d are frozen, so begin_step() lets the law fold every factor
// that depends on them alone into per-particle coefficients (the law's file
// in drag_laws/ says which); the subcycle then needs only the slip.
// The kernel (drag_laws/drag_kernel.hpp) is compiled once per law
// and works on blocks of eight particles.
//
// Semi-implicit momentum exchange (coupling.exchange: semi_implicit): the
// fluid takes the drag implicitly as beta_e (u^{n+1} - v_e) per element
// (coupling/momentum_exchange.hpp), with each grain's c_i = V_p K_i frozen at
// the end of the previous step (freeze_coefficients()). The grains then feel
// that same c_i in every subcycle, f_i = c_i (<u>_e - v_i) with their current
// velocity and their element's mean fluid velocity <u>_e (the velocity
// beta_e multiplies in the fluid; CFDEM's default without interpolation):
// the drag is linear in v over the step, and the fluid and the grains
// exchange one coefficient on one velocity.
//
// What the grains feel of the law's drag f_d depends on the fluid model
// (GrainDragForm): f_d itself with the simplified model (Eq. 11) and with
// model A (whose grains feel -V_p grad p beside it, fluid_stress_force.hpp);
// f_d / eps with model B (Zhou, Kuang, Chu & Yu 2010, J. Fluid Mech. 661,
// model B = set I: the fluid carries -grad p + div tau, and the grain's
// fluid force is the drag with its pressure-gradient part folded in through
// model A's uniform-bed balance eps grad p = -n f_d: f_d - V_p grad p
// = f_d (1 + (1 - eps) / eps) = f_d / eps, besides the hydrostatic buoyancy
// of Eq. 5). eps is the grain's element porosity, the one the law sees; the
// factor multiplies c_i in both exchanges, so the semi-implicit beta_e and
// the accumulated mean drag carry it and the fluid receives exactly minus
// it (source form conservative, source_term.hpp).
//
// Compared with force_coefficient() (drag.cpp: the same law functions on a
// one-particle block) the forces differ by a few ulp, from the slip's
// rounding (tests/test_drag.cpp bounds it).
#include <array>
#include <span>
#include <vector>

#include "coupling/drag.hpp"
#include "drag_laws/drag_law.hpp"
#include "coupling/particle_mapping.hpp"
#include "dem/dem_engine.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/grain_share.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// What each grain feels of its drag law's force f_d (header comment).
enum class GrainDragForm {
  drag,                // f_d: the simplified model (Eq. 11), model A (Zhou et al. 2010 set II)
  drag_over_porosity,  // f_d / eps_e: model B (Zhou et al. 2010 set I)
};

/// The form of the scene's fluid model.
GrainDragForm grain_drag_form(FluidModel model);

class DragCoupling final : public ExternalForce {
 public:
  /// Particles per block of the subcycle kernel: the widest vector of
  /// doubles (AVX-512) so no lane of a block is ever left to scalar code.
  static constexpr std::size_t block_size = drag_block_size;

  /// apply_to_particles: false in particle_to_fluid mode (drag computed for
  /// the fluid, not felt by the particles). frozen_coefficients: the
  /// semi-implicit exchange (header comment). form: f_d or f_d / eps.
  DragCoupling(const DragLawEntry& law, FluidProperties fluid, bool apply_to_particles,
               bool frozen_coefficients = false, GrainDragForm form = GrainDragForm::drag);

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
  /// Mean drag per particle over the evaluations since begin_step [N], as
  /// the grain feels it (f_d / eps with model B; valid after end_step; zero
  /// when no subcycle ran).
  std::span<const double> mean_drag_x() const { return mean_x_; }
  std::span<const double> mean_drag_y() const { return mean_y_; }
  std::span<const double> mean_drag_z() const { return mean_z_; }
  /// The DEM put its grains in another order (DemEngine::sort_in_cell_order,
  /// new index -> old index) after end_step: the mean drags move with their
  /// grains. The per-subcycle state (blocks, frozen c_i) is rebuilt by the
  /// next begin_step / freeze_coefficients, which the coupled step calls first.
  void reorder(std::span<const Index> new_to_old);
  /// Semi-implicit exchange: c_i = V_p K_i of each particle from its slip
  /// now (fluid velocity interpolated at its position, its velocity, its
  /// element's porosity), held over the next step's subcycles. Call at the
  /// end of a step (and once before the first); `particles` are those
  /// `mapping` was built from.
  void freeze_coefficients(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles,
                           std::span<const double> fluid_velocity, std::span<const double> porosity);
  /// The frozen c_i [kg/s] per particle (empty unless frozen_coefficients).
  std::span<const double> frozen_coefficients() const { return frozen_; }
  /// Sum over particles of the mean drag [N] (after end_step); decomposed
  /// over MPI ranks, over every rank's owned grains (share).
  Vec3 total_mean_drag(const GrainShare& share = {}) const;

  /// Decomposed over MPI ranks (ExternalForce): what a grain's drag in the
  /// subcycles depends on moves with it at a list rebuild: the fluid
  /// velocity at it, the law's folded coefficients, the drag summed so far,
  /// the form's factor, the law's memory between subcycles and
  /// (semi-implicit) its frozen c_i, 14 values a grain. So a grain's mean drag is the one one process computes for it,
  /// bit for bit, whichever ranks it passed. Grains lost on any rank: the
  /// survivors are mapped again and the sums restarted, as add() does in
  /// one process when the count changes.
  std::vector<std::vector<double>> carried_state(const Particles& p) const override;
  void grains_redistributed(const Particles& p, std::vector<std::vector<double>>&& carried,
                            bool lost_anywhere) override;
  /// True when the particle count changed during the step (particles removed
  /// by the DEM): the fluid velocities were re-interpolated from the new order.
  bool remapped() const { return remapped_; }
  /// Wall time spent in add() since begin_step [s] (part of the DEM subcycles' time).
  double evaluation_seconds() const { return evaluation_seconds_; }

 private:
  // Interpolates the fluid velocity at the block's particles into blk (P1
  // shape functions, Eq. 28-31) and lets the law fold its coefficients;
  // scale: the form's factor per lane (1, or 1 / eps_e; 0 without fluid).
  void fill_block(std::size_t b, const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles,
                  std::span<const double> fluid_velocity, std::span<const double> porosity, DragBlock& blk,
                  DragLanes& scale) const;
  void prepare(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles);
  // After particles were removed: the survivors mapped again, sums restarted (add(), grains_redistributed).
  void remap(const Particles& p);

  const DragLawEntry* law_;
  FluidProperties fluid_;
  bool apply_;
  bool frozen_mode_;
  GrainDragForm form_;
  const BoxMesh* mesh_ = nullptr;
  std::span<const double> nodal_velocity_, porosity_;
  ParticleMapping own_mapping_;  // used only when particles are removed mid-step
  std::size_t particles_ = 0;    // particle count the blocks were prepared for
  std::vector<DragBlock> blocks_;
  std::vector<DragLanes> scale_;          // the form's factor per block lane (fill_block)
  std::vector<DragLanes> frozen_blocks_;  // semi-implicit: c_i per block lane
  std::vector<double> frozen_;            // the same per particle
  std::vector<double> mean_x_, mean_y_, mean_z_;  // mean drag of the step (end_step)
  long evaluations_ = 0;
  bool remapped_ = false;
  double evaluation_seconds_ = 0.0;
};

}  // namespace fdem

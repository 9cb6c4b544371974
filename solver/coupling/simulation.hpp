#pragma once
// The coupled FEM-DEM run (paper Sect. 2.3, Fig. 2-4). One Simulation owns
// the particles (DEM engine), and, only when scene.effects.fluid, the box
// mesh, the fluid solver and the coupling state (particle mapping, porosity,
// drag, source term). A scene without fluid builds no mesh and no fluid.
//
// One step() is one fluid step of scene.time.fluid_step (Fig. 2); a dry
// scene (no fluid) takes the same number of DEM steps and nothing else:
//   1. solve the fluid with the body force of the previous step's source term
//      (BDF1 on the first step, then the scene's scheme). Skipped when the
//      fluid provably stays at rest: no source term reaches it and all
//      boundary data are zero (one-way settling in still water);
//   2. map the particles to elements (Eq. 23-31) and interpolate the fluid
//      velocity at each particle with P1 shape functions;
//   3. porosity per element (Eq. 32, or the smoother scheme);
//   4. DEM subcycles (Fig. 3): drag (Eq. 11-15) evaluated in EVERY subcycle
//      with the current particle velocity and the frozen fluid velocity, its
//      impulse accumulated per particle;
//   5. contact search/mapping again at the new positions, porosity updated;
//   6. source term (Fig. 4-5): mean drag of the step per element, volume
//      weighted, to the nodes with P1 weights; handed to the fluid as body
//      force for the next step. With coupling.exchange: semi_implicit
//      instead each grain's drag coefficient is frozen here and the fluid
//      gets beta_e, v_e per element for an implicit exchange in its next
//      solve (coupling/momentum_exchange.hpp).
// Coupling modes (scene.effects.coupling): off (no exchange),
// fluid_to_particle (drag on particles, fluid receives nothing),
// particle_to_fluid (fluid receives the drag, particles feel none), two_way.
// Until scene.coupling.freeze_until the particles are frozen and the source
// term is zero (channel flow start).
#include <iosfwd>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "dem/dem_engine.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/element_sums.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct CouplingDiagnostics {
  // Porosity floor (scene.coupling.porosity_floor).
  long floored_elements = 0;            // elements floored at the latest porosity update
  long floored_element_updates = 0;     // sum of the above over every update of the run
  double min_porosity = 1.0;            // smallest element porosity before flooring, latest update
  // Momentum exchange over the latest fluid step [N], time-averaged over its subcycles.
  Vec3 drag_on_particles = Vec3::Zero();  // sum over particles of the drag computed (felt unless particle_to_fluid)
  Vec3 force_on_fluid = Vec3::Zero();     // integral of the body force density handed to the fluid (semi-implicit
                                          // exchange: sum_e V_e beta_e (v_e - <u^{n+1}>_e) of this step's solve)
  double momentum_imbalance = 0.0;        // |drag + force_on_fluid| / |drag| (0 when no drag)
  long particles_outside_mesh = 0;        // particles whose centre is outside the mesh (feel no drag)
  int subcycles = 0;                      // DEM steps per fluid step
  // Wall time of the latest step [s], per phase (Fig. 2).
  double fluid_seconds = 0.0;
  double dem_seconds = 0.0;             // the DEM subcycles, drag included
  double drag_seconds = 0.0;            // of dem_seconds: drag evaluated in the subcycles (Eq. 11-15)
  double coupling_seconds = 0.0;
  DemDiagnostics dem;
};

class Simulation {
 public:
  /// Builds what scene.effects needs. Throws InputError for scenes it cannot
  /// run (e.g. coupling without fluid, an unstable DEM step).
  explicit Simulation(const Scene& scene);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  /// One coupled step: one fluid step with its DEM subcycles (dry scene: one DEM step).
  void step();

  double time() const;           // [s], step_index() * step size (no drift from summing)
  bool finished() const;         // time() >= scene.time.end_time (within half a DEM step)
  long step_index() const;       // steps taken
  long steps_to_end() const;     // step_index() at which finished() becomes true
  double step_size() const;      // fluid step [s] (dry scene: DEM step)
  int subcycles() const;         // DEM steps per step()

  const Scene& scene() const;
  /// Every grain of the run (on several MPI ranks too: gathered after each
  /// step, or with set_gather_each_step(false) at the last gather_particles()).
  const Particles& particles() const;
  /// This rank's grains and ghosts as the DEM steps them (decomposed over MPI
  /// ranks; GrainExchange::ghost_mask tells which are ghosts); one process: all.
  const Particles& local_particles() const;
  /// Decomposed over MPI ranks: whether each step() ends by gathering every
  /// rank's grains onto every rank (on: particles() and save_checkpoint()
  /// always of the present step). Off, only the diagnostics are summed after
  /// a step and the caller calls gather_particles() before it reads
  /// particles() or saves a checkpoint: fdem run does, at the steps it
  /// writes output (a step's gather moves 8 * 12 bytes per grain, 19 doubles with
  /// rotation, to every rank). No effect in one process.
  void set_gather_each_step(bool on);
  /// Decomposed: every rank's grains of this step onto every rank, unless
  /// gathered since the last step (a collective: every rank, same point).
  void gather_particles();
  /// On several MPI ranks the grains are decomposed in slabs
  /// (parallel/grain_exchange.hpp), dry and coupled scenes alike: the
  /// exchange, else nullptr, and then why not (one rank, tangential contact, ...).
  /// Coupled, each rank maps, drags and deposits its own grains; the
  /// porosity, source term and exchange coefficients are their sums over
  /// the ranks (parallel/grain_share.hpp): each rank holds the per-element
  /// fields where its grains and its fluid rows read them (0 and a porosity
  /// of 1 elsewhere; parallel/element_sums.hpp), equal to one process's
  /// there up to the rounding of elements that two ranks' grains touch.
  const GrainExchange* grain_exchange() const;
  /// Decomposed with a fluid: the per-element sums' exchange between the ranks, else nullptr.
  const ElementSums* element_sums() const;
  const std::string& replicated_because() const;
  const BoxMesh* mesh() const;   // nullptr without fluid

  // Empty spans without fluid.
  std::span<const double> fluid_velocity() const;  // 3*num_nodes, node-major [m/s]
  std::span<const double> fluid_pressure() const;  // num_nodes, dynamic pressure [Pa]
  std::span<const double> porosity() const;        // num_elements, floored [-]
  std::span<const double> source_term() const;     // 3*num_nodes node-major body force density on the fluid [N/m^3]
  /// Semi-implicit exchange (coupling/momentum_exchange.hpp): beta_e per
  /// element handed to the next fluid solve [kg/(m^3 s)]; empty otherwise.
  std::span<const double> momentum_exchange_beta() const;
  /// porosity() and source_term() over the whole mesh, for output. Decomposed
  /// over MPI ranks each rank holds them only where its grains and fluid rows
  /// need them: a collective that gathers each element layer (node) from its
  /// owner to rank 0; the other ranks get empty vectors. Else copies.
  std::vector<double> porosity_for_output() const;
  std::vector<double> source_term_for_output() const;
  /// Element of each particle (-1 outside the mesh), at the latest mapping;
  /// decomposed over MPI ranks, of this rank's grains and ghosts (DemEngine::particles()).
  std::span<const Index> particle_elements() const;

  /// When the DEM puts its grains in memory order (DemEngine::GrainSortPolicy;
  /// default: every 1000 DEM steps from 8192 grains). A benchmark's or a
  /// test's switch, like the thread count: not in the scene nor a checkpoint.
  void set_grain_sort_policy(DemEngine::GrainSortPolicy policy);
  CouplingDiagnostics diagnostics() const;
  /// diagnostics() without the DEM's part (`dem` left default): the latest
  /// step's phase seconds and momentum exchange, for a caller that reads them
  /// after every step. The DEM's part is a pass over every grain and contact
  /// (kinetic energy, contacts, largest overlap): 0.9 % of a plume step's
  /// samples when fdem run read it for its timers.
  CouplingDiagnostics coupling_diagnostics() const;

  /// Changes an inlet face's velocity from the next step() on (a study
  /// driver's stages: a fluidized bed's inflow raised and lowered); scene()
  /// reports the new value. Not written to checkpoints (their fingerprint
  /// keeps the scene's), so a restart resumes with the scene file's inlet.
  /// Throws SolverError without fluid or when the face is not an inlet.
  void set_inlet_velocity(BoxFace face, const Vec3& velocity_m_s);

  /// Checkpoint (file layout in coupling/checkpoint_format.hpp):
  /// the exact state, binary doubles, behind a header with the scene's key
  /// numbers, the payload length and checksum, and an end marker. It holds
  /// the step index, the DEM state (DemEngine::save_state), and with fluid
  /// the fluid state (FluidSolver::save_state: u^n, u^{n-1}, p, BDF2 state,
  /// body force = the previous step's source term), the coupling
  /// diagnostics counters, the porosity and the mean drag the source term
  /// was built from. The particle mapping, porosity and source term are
  /// rebuilt from these on load and checked against the file bit for bit.
  /// A checkpoint is a refactor point of the fluid's ILUT preconditioner
  /// (see FluidSolver::save_state): a run restarted from it equals the run
  /// that wrote it bit for bit (same scene, same thread count), and a run
  /// that wrote none to the linear solver tolerance.
  /// Not atomic by itself: write into a std::ostringstream and hand it to
  /// io/atomic_file.hpp's write_file_atomically.
  void save_checkpoint(std::ostream& out) const;
  /// Replaces this run's state by the checkpoint's. Refuses (SolverError,
  /// saying why) a checkpoint of another scene (naming the keys that differ;
  /// the end time and output settings may differ, so a run can be
  /// extended), one cut short or corrupt, or of another format version; on
  /// any refusal this run is left exactly as it was.
  void load_checkpoint(std::istream& in);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fdem

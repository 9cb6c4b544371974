#pragma once
// The DEM engine (Sect. 2.1, Eq. 1-10): soft spheres in a box, advanced by
// velocity Verlet, usable alone (dry granular scenes) or as the particle side
// of the coupling, which plugs drag in through ExternalForce.
//
// Effects are dispatched once, at construction, to a kernel specialised at
// compile time for {tangential contact, rotation, walls, damping from
// restitution}: a switched-off effect has no branch in the pair loop and no
// storage (no slip history without tangential contact).
//
// Time integration (velocity Verlet, "kick-drift-kick"), one step of dt:
//   v^{n+1/2} = v^n + dt/2 F^n / m
//   x^{n+1}   = x^n + dt v^{n+1/2}
//   F^{n+1}   = F(x^{n+1}, v^{n+1/2})          contacts, gravity/buoyancy, then ExternalForce
//   v^{n+1}   = v^{n+1/2} + dt/2 F^{n+1} / m
// Position-dependent forces (springs) are second order; velocity-dependent
// ones (dashpots, drag) use the half-step velocity v^{n+1/2}, which is the
// LIGGGHTS/LAMMPS choice: first order in the dashpot term alone but explicit
// and symmetric between the two spheres of a pair, so Newton's third law
// holds bit for bit. Angular velocity follows the same kick-drift-kick.
#include <cstddef>
#include <iosfwd>
#include <memory>
#include <span>
#include <vector>

#include "core/particles.hpp"
#include "dem/pair_shares.hpp"  // contact_cost_in_pair_tests, which dem_steps and plume_dem_profile print
#include "scene/scene.hpp"

namespace fdem {

/// A force added inside every DEM step after the contact forces, with the
/// positions x^{n+1} and velocities v^{n+1/2} of that step (drag with the
/// current particle velocity in every subcycle; coupling/drag_coupling.hpp says why).
/// add() must *add* to fx, fy, fz (size p.size()); it may be called from the
/// thread that calls step() only, and may use OpenMP inside.
class GrainExchange;  // parallel/grain_exchange.hpp

struct ExternalForce {
  virtual ~ExternalForce() = default;
  virtual void add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) = 0;

  /// Decomposed over MPI ranks (DemEngine::decompose), per-grain state the
  /// force keeps by grain index (the coupling's drag state of the fluid
  /// step) moves with its grain when a list rebuild migrates grains and
  /// renews the ghosts: carried_state gives it as arrays of p.size() values
  /// (none, or arrays of another length: nothing carried), and after the
  /// rebuild grains_redistributed gets them back at the grains' new indices
  /// (a ghost: its owner's values), with whether any rank removed lost
  /// grains in that rebuild (what one process sees as a change of count).
  /// Never called in one process.
  virtual std::vector<std::vector<double>> carried_state(const Particles& /*p*/) const { return {}; }
  virtual void grains_redistributed(const Particles& /*p*/, std::vector<std::vector<double>>&& /*carried*/,
                                    bool /*lost_anywhere*/) {}
};

/// Where a DemEngine's wall time went since construction [s] (steady clock,
/// around each pass of DemEngine::step; the clock calls cost ~0.1 us a step).
struct DemPhaseSeconds {
  double integration = 0.0;      // kicks, drift, displacement and lost-grain tests
  double neighbour_build = 0.0;  // Verlet list rebuilds (cell grid + list)
  double body_force = 0.0;       // gravity and buoyancy (Eq. 4-5)
  double pairs = 0.0;            // particle-particle contacts (Eq. 6-10)
  double walls = 0.0;            // particle-wall contacts (in `pairs` when a threaded pair pass applies them)
  double external = 0.0;         // ExternalForce::add (the coupling's drag, Eq. 11-15)
  double sorting = 0.0;          // sort_in_cell_order (the permutation and the list rebuilt after it)
  std::size_t force_evaluations = 0;  // compute_forces calls (one a step, plus restarts)
  std::size_t pair_entries_tested = 0;  // neighbour-list entries tested, summed over the evaluations
  std::size_t pairs_tested = 0;  // without tangential contact: pairs i < j distance-tested (those that can touch), summed likewise
  std::size_t pairs_touching = 0;  // without tangential contact: of those, the pairs in contact (each once), summed likewise
  std::size_t threaded_pair_passes = 0;  // without tangential contact: pair passes that ran on more than one thread
  std::size_t near_pair_filters = 0;  // without tangential contact: filterings of the pairs that can touch (a distance test a pair)
  std::size_t threaded_near_filters = 0;  // of those, the filterings that ran in shares on more than one thread
  double total() const { return integration + neighbour_build + body_force + pairs + walls + external + sorting; }
};

struct DemDiagnostics {
  std::size_t steps = 0;                  // DEM steps taken
  std::size_t particles = 0;              // particles now in the engine
  std::size_t contacts = 0;               // particle-particle pairs in overlap (each pair once)
  std::size_t wall_contacts = 0;          // particle-wall overlaps
  double max_overlap_over_diameter = 0.0; // max over contacts of delta_n / min(d_a, d_b) (walls: / d)
  double kinetic_energy_j = 0.0;          // translational + rotational
  std::size_t particles_removed = 0;      // left the domain (lost), removed since construction
  std::size_t neighbour_rebuilds = 0;     // Verlet list rebuilds since construction
  std::size_t neighbour_entries = 0;      // entries of the current list (each pair twice)
  std::size_t grain_sorts = 0;            // sort_in_cell_order calls that reordered, since construction
  DemPhaseSeconds phases;                 // since construction
};

class DemEngine {
 public:
  /// Takes the particles (fills mass from diameter if empty is NOT done: mass
  /// must be set). Reads scene.effects, scene.contact, scene.domain (six box
  /// walls when effects.walls), scene.gravity, scene.time.dem_step and, when
  /// effects.buoyancy and effects.fluid, scene.fluid.density (Eq. 5).
  /// Throws InputError (key time.dem_step) when the step is unstable for these
  /// particles unless scene.contact.allow_unstable_step.
  DemEngine(Particles particles, const Scene& scene);
  ~DemEngine();
  DemEngine(DemEngine&&) noexcept;
  DemEngine& operator=(DemEngine&&) noexcept;
  DemEngine(const DemEngine&) = delete;
  DemEngine& operator=(const DemEngine&) = delete;

  /// One DEM step of scene.time.dem_step (time advances also when frozen).
  void step();
  /// n steps.
  void run(std::size_t steps);
  /// n steps, the grains sorted whenever due (sort_due below): for an owner
  /// that keeps no per-grain state of its own (a dry scene).
  void run_sorting(std::size_t steps);

  double time() const;       // [s]
  double dem_step() const;   // [s]

  Particles& particles();
  const Particles& particles() const;
  /// Call after changing positions or diameters from outside, so the
  /// neighbour list is rebuilt before the next step.
  void particles_moved();

  /// Not owned; nullptr removes it. Called in every step after contacts.
  void set_external_force(ExternalForce* force);
  /// Frozen particles keep position and velocity; only time advances.
  void set_frozen(bool frozen);
  bool frozen() const;

  /// Contact count, overlap, energy, losses, measured at the current state.
  DemDiagnostics diagnostics() const;

  /// DEM steps taken (as diagnostics().steps, without its O(N) measures).
  std::size_t steps() const;

  /// Memory order (dem/cell_order.hpp): the grains are put in the order of
  /// the cells of the neighbour grid (edge: largest diameter + skin) every
  /// GrainSortPolicy::interval DEM steps, as LAMMPS / LIGGGHTS sort atoms by
  /// default (atom_modify sort 1000). Only the owner knows when no per-grain
  /// state of its own would be left in the old order, so the engine never
  /// sorts inside step(): the owner asks sort_due(steps before its last
  /// batch of steps) and then calls sort_in_cell_order, which returns the
  /// permutation (new index -> old index; empty when the grains were in
  /// order) for the owner's own per-grain arrays. Below min_particles the
  /// per-grain state fits in a core's L2 (~100 B a grain, 1 MiB) and order
  /// costs nothing: never due. Positions, velocities and forces move with
  /// their grain unchanged; a grain's contact forces are then summed in the
  /// new index order of its neighbours, so later steps differ from an
  /// unsorted run by rounding (tests/test_grain_sorting.cpp bounds it). The
  /// decision depends on the step count and the order on the positions,
  /// both in a checkpoint: a restarted run sorts where the first run did
  /// (under the same policy: like the thread count, it is not in the file).
  /// Decomposed over MPI ranks (decompose) the engine does not sort.
  struct GrainSortPolicy {
    std::size_t interval = 1000;       // DEM steps; 0: never
    std::size_t min_particles = 8192;
  };
  void set_grain_sort_policy(GrainSortPolicy policy);
  GrainSortPolicy grain_sort_policy() const;
  bool sort_due(std::size_t steps_before) const;
  std::span<const Index> sort_in_cell_order();

  /// Verlet skin [m] (default 0.5 * largest diameter, rebuilt when any
  /// particle has moved more than skin / 2 since the last build).
  void set_skin(double skin_m);

  /// Decomposes the grains over MPI ranks (parallel/grain_exchange.hpp, a
  /// collective: every rank calls it, with the same particles): from the
  /// next step on this rank integrates only the grains whose centre lies in
  /// its slab, and holds ghost copies of its neighbours' grains within
  /// largest diameter + skin of its faces, refreshed every step; grains
  /// migrate at list rebuilds, which all ranks take together. Each grain's
  /// force is summed over its contacts in ascending id, as in one process,
  /// so the trajectories are those of one process bit for bit. particles()
  /// then holds this rank's grains and ghosts (ascending id), diagnostics()
  /// sums over the ranks at the last collect(). With tangential contact the
  /// slip history travels with the grains (pair slips with the grain of
  /// their row, wall slips with theirs), so friction too is one process's
  /// bit for bit. Every later step(), collect(), save_state() and
  /// load_state() is a collective.
  /// `owners_stay_in_slabs`: migrate whenever a grain moved half the skin
  /// since the list build, so that every owned grain stays within half a
  /// skin of its slab (what the coupling's per-rank element sums need,
  /// parallel/element_sums.hpp). Without it (dry DEM) a grain keeps its
  /// owner until the grains' relative displacement rebuilds the list: its
  /// contacts across a face are ghost contacts whatever its position, and a
  /// block falling as one never migrates (scene P on 2 ranks: 81 needless
  /// redistributions in 5000 steps otherwise).
  void decompose(std::unique_ptr<GrainExchange> exchange, bool owners_stay_in_slabs = false);
  /// The exchange, or nullptr in one process.
  const GrainExchange* exchange() const;
  /// Decomposed: gathers every rank's grains (and the diagnostics summed
  /// over the ranks) for whole_particles(), diagnostics() and save_state()
  /// (a collective, after the same step on every rank). One process: nothing.
  void collect();
  /// Decomposed: the diagnostics alone summed over the ranks (a collective
  /// of a few numbers, where collect() moves every grain to every rank);
  /// whole_particles() stays the last collect()'s. One process: nothing.
  void collect_diagnostics();
  /// Every grain of the run, ascending id: particles() in one process, the
  /// last collect()'s gathering when decomposed.
  const Particles& whole_particles() const;
  /// Whether whole_particles() is of the present step (one process: always;
  /// decomposed: collect() since the last step()). save_state() needs it.
  bool whole_particles_current() const;

  /// Checkpoint: the exact state, binary doubles. Covers every
  /// particle array (positions, velocities, forces F^n, diameters, masses,
  /// ids, the rotation arrays when present), the per-particle body force
  /// factor, time, step count, frozen flag, whether F^n must be recomputed,
  /// the skin, the removed count and the tangential slip history (pair
  /// entries with a non-zero slip, keyed by particle pair, and the wall
  /// slips). Not saved: the external force (the owner sets it again) and the
  /// neighbour list: load_state rebuilds it at the loaded positions. A rebuilt
  /// list holds every pair in contact and each particle's forces are summed
  /// over its list in ascending j, where a pair out of contact adds nothing,
  /// so the next steps are bitwise those of the run that wrote the state
  /// (tested in coupling/tests/test_checkpoint.cpp). Only
  /// diagnostics().neighbour_rebuilds differs. load_state needs an engine
  /// built from the same scene (same effects, DEM step, at least as many
  /// particles); it throws SolverError otherwise or on a short or corrupt
  /// stream, and then leaves the engine unchanged. Decomposed, save_state
  /// writes the last collect()'s whole set (the file one process writes)
  /// and load_state takes the whole set, then redistributes it.
  void save_state(std::ostream& out) const;
  void load_state(std::istream& in);

  class Kernel;  // the effect-specialised implementation (dem_engine.cpp)

 private:
  std::unique_ptr<Kernel> kernel_;
};

}  // namespace fdem

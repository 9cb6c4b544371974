#pragma once
// Simulation's state, private to solver/coupling: the coupled step
// (simulation.cpp, the flowchart of Fig. 2-4) and the checkpoint payload
// (simulation_state.cpp) share it. Nothing outside those two files includes it.
#include <array>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coupling/checkpoint_format.hpp"
#include "coupling/drag_coupling.hpp"
#include "coupling/fluid_stress_force.hpp"
#include "coupling/momentum_exchange.hpp"
#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "coupling/simulation.hpp"
#include "coupling/source_term.hpp"
#include "fluid/fluid_solver.hpp"
#include "parallel/element_sums.hpp"

namespace fdem {

struct Simulation::Impl {
  Scene scene;               // as given, with the DEM step resolved
  double step_size = 0.0;    // [s]
  int subcycles = 1;
  long steps_to_end = 0;
  long step_index = 0;

  std::optional<DemEngine> dem;
  // Decomposed over MPI ranks: the grains' exchange, which `dem` owns (a
  // checkpoint's load restores its cut before the DEM's state); else nullptr.
  GrainExchange* grains = nullptr;
  // Decomposed over MPI ranks with a fluid: the per-element sums completed
  // between the ranks that need them (parallel/element_sums.hpp).
  std::unique_ptr<ElementSums> element_sums;
  // Fluid side: exists only when scene.effects.fluid.
  std::unique_ptr<BoxMesh> mesh;
  std::unique_ptr<FluidSolver> fluid;
  ParticleMapping mapping;
  std::unique_ptr<PorosityField> porosity;
  std::unique_ptr<DragCoupling> drag;     // only when some drag is exchanged
  std::unique_ptr<FluidStressForce> fluid_stress;  // model A with drag on the grains: -V_p grad p, wraps drag
  std::unique_ptr<SourceTerm> source;     // explicit exchange: last step's mean drag as a body force
  std::unique_ptr<SemiImplicitExchange> exchange;  // semi-implicit exchange: beta_e, v_e in the fluid's matrix
  std::vector<double> zero_source;        // returned by source_term() when the fluid gets nothing
  bool fluid_at_rest = false;             // fluid_stays_at_rest(): no solve needed
  std::string replicated_because;         // why the grains are not decomposed over the MPI ranks ("" when they are)
  bool gather_each_step = true;           // decomposed: every rank's grains to every rank after each step()
  // The end of a step decomposed: the whole set gathered, or the diagnostics alone.
  void collect() { gather_each_step ? dem->collect() : dem->collect_diagnostics(); }

  CouplingDiagnostics diag;

  // Checkpoint support: the scene's key numbers (a checkpoint of another
  // scene is refused), and the mean drag a loaded source term was built
  // from, kept until the next step so a checkpoint written right after a
  // restart holds it again.
  checkpoint::SceneFingerprint fingerprint;
  long restored_at_step = -1;
  bool restored_source_from_drag = false;
  std::array<std::vector<double>, 3> restored_mean_drag;

  explicit Impl(const Scene& s);  // simulation.cpp

  // Which grains this rank counts in sums over grains (all in one process).
  GrainShare share() const { return GrainShare{dem->exchange(), element_sums.get()}; }

  // ---- The coupled step (simulation.cpp).
  void map_and_porosity();
  // Semi-implicit exchange: each grain's coefficient c_i from its slip now,
  // and from them the fluid's beta_e, v_e for the next fluid step (none
  // while that step is frozen).
  void prepare_exchange();
  void step();
  std::string blow_up_message(std::string solver_message) const;  // names the step at fault

  // Whether the particles are frozen (and the source term zero) in the step
  // that starts at step `step`: until scene.coupling.freeze_until.
  bool frozen_at(long step) const {
    const double t = static_cast<double>(step) * step_size;
    return t + 0.5 * step_size <= scene.coupling.freeze_until;
  }

  // Whether step 5 builds the source term from this step's mean drag (else
  // it clears it): two-way exchange, particles not frozen in the step, and
  // a mean drag for every particle. step() and the checkpoint writer both
  // ask this, so the file records exactly the branch the step took.
  bool builds_source_from_drag(bool frozen) const {
    return source && drag && !frozen && drag->mean_drag_x().size() == dem->particles().size();
  }

  // ---- Checkpoint payload (simulation_state.cpp): sections "SIM ", "DEM ",
  // and with fluid "FLUI", "COUP" (layout in coupling/checkpoint_format.hpp).

  // Whether the source term now handed to the fluid was built from drag.
  bool source_from_drag() const;
  void write_payload(std::ostream& out) const;
  // Reads into this (freshly built) Impl; any inconsistency throws.
  void read_payload(std::istream& in);
};

}  // namespace fdem

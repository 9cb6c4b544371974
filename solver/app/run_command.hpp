#pragma once
// `fdem run SCENE`: the run loop around a coupled simulation. It reads like
// the run itself: build, write the initial state, step until the end time
// (progress, probes CSV, VTU/PVD, checkpoints at the scene's cadence), stop
// cleanly on SIGINT/SIGTERM after the current step.
#include <cstdio>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "io/probes.hpp"
#include "mesh/box_mesh.hpp"
#include "parallel/slab_partition.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// Wall time of a step per phase [s] (Fig. 2); drag is part of dem.
struct PhaseSeconds {
  double fluid = 0.0, dem = 0.0, drag = 0.0, coupling = 0.0;
  PhaseSeconds& operator+=(const PhaseSeconds& o) {
    fluid += o.fluid;
    dem += o.dem;
    drag += o.drag;
    coupling += o.coupling;
    return *this;
  }
};

/// What the run loop needs from a running simulation. fdem::Simulation is
/// adapted to it in run_command.cpp; tests drive the loop with a small fake.
class RunTarget {
 public:
  virtual ~RunTarget() = default;
  virtual void step() = 0;                  // one fluid step with its DEM subcycles
  virtual double time() const = 0;          // [s]
  virtual double step_size() const = 0;     // [s]
  virtual long step_index() const = 0;
  virtual bool finished() const = 0;
  virtual const Particles& particles() const = 0;
  virtual const BoxMesh* mesh() const = 0;  // nullptr without fluid
  virtual std::span<const double> fluid_velocity() const = 0;  // 3 per node, node-major
  virtual std::span<const double> fluid_pressure() const = 0;  // 1 per node
  virtual std::span<const double> porosity() const = 0;        // 1 per element
  virtual std::span<const double> source_term() const = 0;     // 3 per node, node-major
  /// porosity() and source_term() whole, for output, on rank 0 (a collective
  /// where the ranks hold them in part: every rank calls it at the same point;
  /// the other ranks may get empty vectors).
  virtual std::vector<double> porosity_for_output() const {
    return {porosity().begin(), porosity().end()};
  }
  virtual std::vector<double> source_term_for_output() const {
    return {source_term().begin(), source_term().end()};
  }
  /// Extra CSV columns (name, value) beyond the probes, the same names every call.
  virtual std::vector<std::pair<std::string, double>> diagnostics() const { return {}; }
  /// Where the latest step's time went (the end-of-run summary adds them up).
  virtual PhaseSeconds step_seconds() const { return {}; }
  virtual void save_checkpoint(std::ostream& out) const = 0;
  /// True while particles() holds every grain on every MPI rank (stepped by
  /// every rank, or gathered after each step): each rank then writes the
  /// grains whose centre lies in its slab (io/grain_ownership.hpp) and rank
  /// 0 the probes of all. False when particles() are this rank's own grains
  /// alone: each rank writes them all and the probes are summed over ranks.
  virtual bool particles_replicated() const { return true; }
  /// Makes particles() of the present step where the grains are gathered
  /// from the ranks only on demand (a collective then: every rank calls it at
  /// the same point). The loop calls it before any output and grain count,
  /// so a step that writes nothing moves no grains between the ranks.
  virtual void gather_particles() {}
  /// With the grains decomposed over MPI ranks: the probes' sums over this
  /// rank's own grains (ghosts left out), which the ranks add
  /// (io/probes.hpp, sum_over_ranks) instead of gathering every grain;
  /// nullopt where the grains are replicated or gathered (then from particles()).
  virtual std::optional<ProbeSums> own_probe_sums() const { return std::nullopt; }
  /// With the grains decomposed over MPI ranks: their slabs, whose cut follows
  /// the grain count (the output's pieces take it); nullptr otherwise.
  virtual const SlabPartition* grain_slabs() const { return nullptr; }
  /// On several MPI ranks: how the grains are spread over them, for the start-up report.
  virtual std::string grain_layout() const { return "the grains stepped by every rank"; }
  /// On several MPI ranks with the grains decomposed: what their exchange
  /// sent so far, over all ranks (empty otherwise). A collective: every rank
  /// calls it at the same point.
  virtual std::string exchange_summary() const { return {}; }
};

struct RunOptions {
  std::string output_dir;   // empty: scene.output.directory
  int threads = 0;          // 0: OpenMP default
  bool quiet = false;       // no progress line
  std::string restart;      // checkpoint to resume from (same scene); empty: start at t = 0
  bool overwrite = false;   // clear an output folder of another scene instead of refusing it
  bool stop_when_empty = false;  // end the run when every particle has left the open domain
  bool ignore_memory_limit = false;  // run even when the memory estimate exceeds what is available
};

/// Exit codes of `fdem run` (0 ok; 2 bad input and 3 solver failure are thrown).
inline constexpr int kExitInterrupted = 130;

/// Runs `target` to the scene's end time writing the scene's outputs into
/// the output folder; returns 0, or kExitInterrupted after a SIGINT/SIGTERM
/// (the step in progress is finished and every output written first).
/// `log` receives the start summary (counts, then the active physics,
/// app/physics_summary.hpp), progress, and at the end where the wall time
/// went: fluid, DEM (of it drag), coupling, output, other (null: silent).
int run_loop(RunTarget& target, const Scene& scene, const RunOptions& options, std::FILE* log);

/// The whole command: load the scene, build fdem::Simulation, resume it from
/// options.restart when given, run_loop. A resumed run writes its output from
/// the checkpoint's time on, so it must go to another folder than the one
/// holding the checkpoint (it would renumber and overwrite those snapshots):
/// that is refused as bad input.
int run_scene_command(const std::string& scene_path, const RunOptions& options);

/// Installs SIGINT/SIGTERM handlers that only raise a flag, for the lifetime
/// of the object (the previous handlers come back after).
class StopOnSignal {
 public:
  StopOnSignal();
  ~StopOnSignal();
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;
  bool requested() const;
  int signal_number() const;
};

}  // namespace fdem

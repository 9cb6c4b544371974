#include "app/run_command.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/check_command.hpp"
#include "app/physics_summary.hpp"
#include "core/error.hpp"
#include "core/petsc_runtime.hpp"
#include "coupling/checkpoint_format.hpp"
#include "coupling/simulation.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_series.hpp"
#include "io/grain_ownership.hpp"
#include "io/output_folder.hpp"
#include "io/probes.hpp"
#include "io/progress.hpp"
#include "io/pvd_writer.hpp"
#include "io/pvtu_writer.hpp"
#include "io/vtu_writer.hpp"
#include "parallel/slab_partition.hpp"
#include "parallel/grain_exchange.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {

namespace {

// The one piece of process-wide state: a signal handler can do nothing but
// set a flag of this type (C++ [support.signal]).
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void fdem_stop_handler(int signal_number) { g_stop_signal = signal_number; }

struct SavedHandlers {
  struct sigaction interrupt {};
  struct sigaction terminate {};
};
SavedHandlers g_saved;  // restored by ~StopOnSignal

// Outputs due at a cadence: due(t) is true at the first step whose time
// reaches the next multiple of the interval. A millionth of a step absorbs
// round-off in t = n * dt without writing a step early.
class Cadence {
 public:
  Cadence(double interval_s, double step_s) : interval_(interval_s), tolerance_(1e-6 * step_s) {}
  bool enabled() const { return interval_ > 0.0; }
  bool due(double time_s) const { return enabled() && time_s + tolerance_ >= next_ * interval_; }
  void done(double time_s) {
    if (!enabled()) return;  // a forced write (stop on signal) without a cadence
    while (next_ * interval_ <= time_s + tolerance_) ++next_;
  }

 private:
  double interval_, tolerance_;
  double next_ = 0.0;
};

// On several MPI ranks every rank calls after_step at the same steps (the
// cadences depend on the time alone) and takes part in its collectives; rank
// 0 alone writes probes.csv, the .pvd and .pvtu index files and the fluid
// (velocity and pressure whole on every rank, porosity and source term
// gathered from the ranks that own them), each rank its own
// particles piece and its own checkpoint file.
class Outputs {
 public:
  Outputs(const Scene& scene, const RunTarget& target, std::string directory)
      : dir_(create_folder(std::move(directory))),
        ranks_(mpi_ranks()),
        rank_(mpi_rank()),
        probes_(scene.output.probes),
        vtu_encoding_(scene.output.vtu_format == VtuFormat::ascii ? VtuEncoding::ascii : VtuEncoding::binary),
        particles_pvd_(dir_ + "/particles.pvd"),
        fluid_pvd_(dir_ + "/fluid.pvd"),
        vtu_(scene.output.vtu_interval, target.step_size()),
        // csv_interval 0: every step.
        csv_cadence_(scene.output.csv_interval > 0 ? scene.output.csv_interval : target.step_size(),
                     target.step_size()),
        checkpoint_(scene.output.checkpoint_interval, target.step_size()) {
    if (rank_ == 0) csv_.emplace(dir_ + "/probes.csv", columns(scene, target));
    if (ranks_ > 1) slabs_.emplace(scene.domain.lower, scene.domain.upper, ranks_);
  }

  /// A resumed run starts its probes with the earlier run's rows before the
  /// checkpoint's step (the checkpoint's own row is sampled again, equal).
  /// Rank 0's; -1 on the others.
  long carry_probes_from(const std::string& old_csv, long restart_step) {
    return csv_ ? csv_->carry_rows(old_csv, "step", static_cast<double>(restart_step)) : -1;
  }

  // `force`: end of run or stop on signal; `interrupted`: a signal stopped
  // the run, so a checkpoint is written even when the scene sets no interval.
  void after_step(RunTarget& target, bool force, bool interrupted = false) {
    const double t = target.time();
    const long step = target.step_index();
    // Forced (end of run, stop on signal): write what this step has not written yet.
    // The cadences are of the time alone: every rank decides alike, and
    // gathers the grains (a collective) only at a step that writes them:
    // with the grains decomposed the probes are summed from each rank's
    // own grains (no gather), snapshots and checkpoints take the whole set.
    const bool csv_due = csv_cadence_.due(t) || (force && step != csv_step_);
    const bool vtu_due = vtu_.due(t) || (force && vtu_.enabled() && step != vtu_step_);
    const bool checkpoint_due =
        checkpoint_.due(t) || (force && (checkpoint_.enabled() || interrupted) && step != checkpoint_step_);
    std::optional<ProbeSums> own_sums;
    if (csv_due) own_sums = target.own_probe_sums();
    if ((csv_due && !own_sums) || vtu_due || checkpoint_due) target.gather_particles();
    if (csv_due) {
      sample(target, own_sums);
      csv_cadence_.done(t);
      csv_step_ = step;
    }
    if (vtu_due) {
      write_vtu(target);
      vtu_.done(t);
      vtu_step_ = step;
    }
    if (checkpoint_due) {
      if (csv_) csv_->sync();  // the rows up to a checkpoint reach the disk with it
      write_checkpoint(target);
      checkpoint_.done(t);
      checkpoint_step_ = step;
    }
  }

  const std::string& directory() const { return dir_; }
  int vtu_written() const { return vtu_count_; }

 private:
  static std::string create_folder(std::string directory) {
    std::filesystem::create_directories(directory);
    return directory;
  }

  static std::vector<std::string> columns(const Scene& scene, const RunTarget& target) {
    std::vector<std::string> c{"time", "step"};
    for (auto& name : probe_columns(scene.output.probes)) c.push_back(name);
    for (auto& [name, value] : target.diagnostics()) c.push_back(name);
    return c;
  }

  // The grains this rank writes and counts (io/grain_ownership.hpp): those
  // in its slab of the grains' own cut where they are decomposed (it follows
  // the grain count), else of the equal-length cut.
  std::vector<std::size_t> owned(const RunTarget& target) const {
    const Particles& p = target.particles();
    if (ranks_ == 1 || !target.particles_replicated()) {
      std::vector<std::size_t> all(p.size());
      for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
      return all;
    }
    const SlabPartition* cut = target.grain_slabs();
    return owned_indices(p, cut != nullptr ? *cut : *slabs_, rank_);
  }

  void sample(const RunTarget& target, const std::optional<ProbeSums>& own_sums) {
    // With the grains decomposed each rank sums its own grains and the sums
    // are added over the ranks (io/probes.hpp: counts and extrema bit for
    // bit, the sums of positions, velocities and energy to their rounding,
    // 2 (n - 1) eps sum |x_i| at most). While every rank holds every grain,
    // rank 0 sums them in index order as one process does (the same row,
    // bit for bit, and no collective); a rank holding only its own grains
    // adds them to the others'.
    if (own_sums) {
      const ProbeSums sums = sum_over_ranks(*own_sums);
      if (csv_) append_row(target, sums);
      return;
    }
    if (target.particles_replicated() && !csv_) return;
    const ProbeSums sums = target.particles_replicated() ? probe_sums(target.particles())
                                                         : sum_over_ranks(probe_sums(target.particles()));
    append_row(target, sums);
  }

  void append_row(const RunTarget& target, const ProbeSums& sums) {
    if (!csv_) return;
    std::vector<double> row{target.time(), static_cast<double>(target.step_index())};
    for (double v : probe_values(probes_, sums)) row.push_back(v);
    for (auto& [name, value] : target.diagnostics()) row.push_back(value);
    csv_->append(row);
  }

  void write_vtu(const RunTarget& target) {
    const double t = target.time();
    const std::string base = fmt::format("particles_{:06d}", vtu_count_);
    if (ranks_ == 1) {
      write_particles_vtu(dir_ + "/" + base + ".vtu", target.particles(), t, vtu_encoding_);
      particles_pvd_.add(t, base + ".vtu");
    } else {
      write_particle_pieces(target, base);
    }
    // The porosity and source term from their owners (a collective), then rank 0 writes.
    if (const BoxMesh* mesh = target.mesh(); mesh != nullptr) {
      const std::vector<double> porosity = target.porosity_for_output(), source = target.source_term_for_output();
      if (rank_ != 0) {
        ++vtu_count_;
        return;
      }
      const std::string fluid_file = fmt::format("fluid_{:06d}.vtu", vtu_count_);
      const std::vector<Field> point_data{Field::vector_interleaved("velocity", target.fluid_velocity()),
                                          Field::scalar("pressure", target.fluid_pressure()),
                                          Field::vector_interleaved("source_term", source)};
      const std::vector<Field> cell_data{Field::scalar("porosity", porosity)};
      write_mesh_vtu(dir_ + "/" + fluid_file, *mesh, point_data, cell_data, t, vtu_encoding_);
      fluid_pvd_.add(t, fluid_file);
    }
    ++vtu_count_;
  }

  // Each rank its own grains as one piece; then, once every piece is whole
  // on disk, rank 0 the .pvtu naming them and the .pvd entry naming it.
  void write_particle_pieces(const RunTarget& target, const std::string& base) {
    const Particles mine = particle_subset(target.particles(), owned(target));
    // The arrays every piece holds: those any rank's grains have (an empty
    // piece has none of its own).
    const ParticleArrays here = particle_arrays_of(mine);
    const ParticleArrays arrays{on_any_rank(here.angular_velocity), on_any_rank(here.id)};
    write_particles_vtu(dir_ + "/" + piece_file_name(base, rank_), mine, target.time(), vtu_encoding_, arrays);
    // A rank that failed to write has thrown and ends every rank
    // (app/main.cpp) before this collective returns.
    on_any_rank(false);
    if (rank_ != 0) return;
    std::vector<std::string> pieces;
    for (int r = 0; r < ranks_; ++r) pieces.push_back(piece_file_name(base, r));
    write_particles_pvtu(dir_ + "/" + base + ".pvtu", arrays, pieces);
    particles_pvd_.add(target.time(), base + ".pvtu");
  }

  void write_checkpoint(const RunTarget& target) {
    std::ostringstream out(std::ios::binary);
    target.save_checkpoint(out);
    // Every rank its own file (rank 0's is checkpoint.bin, the one --restart names).
    write_file_atomically(checkpoint::rank_file_path(dir_ + "/checkpoint.bin", static_cast<std::uint32_t>(rank_)),
                          out.str());
  }

  std::string dir_;
  int ranks_, rank_;
  std::optional<SlabPartition> slabs_;  // on several ranks
  std::vector<std::string> probes_;
  VtuEncoding vtu_encoding_;
  PvdCollection particles_pvd_, fluid_pvd_;
  std::optional<CsvSeries> csv_;  // rank 0's
  Cadence vtu_, csv_cadence_, checkpoint_;
  int vtu_count_ = 0;
  long csv_step_ = -1, vtu_step_ = -1, checkpoint_step_ = -1;
};

// During set-up (scene, particles, mesh, fluid system) a SIGINT/SIGTERM ends
// the process at once with a message: there is no state worth saving yet.
// Only async-signal-safe calls (write, _exit) in the handler.
extern "C" void fdem_setup_stop_handler(int) {
  static const char message[] = "fdem run: stopped by a signal during set-up, before the first step; nothing written\n";
  const ssize_t ignored = ::write(2, message, sizeof message - 1);
  (void)ignored;
  ::_exit(kExitInterrupted);
}

class StopDuringSetup {
 public:
  StopDuringSetup() {
    struct sigaction action {};
    action.sa_handler = fdem_setup_stop_handler;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &saved_interrupt_);
    sigaction(SIGTERM, &action, &saved_terminate_);
  }
  ~StopDuringSetup() {
    sigaction(SIGINT, &saved_interrupt_, nullptr);
    sigaction(SIGTERM, &saved_terminate_, nullptr);
  }
  StopDuringSetup(const StopDuringSetup&) = delete;
  StopDuringSetup& operator=(const StopDuringSetup&) = delete;

 private:
  struct sigaction saved_interrupt_ {};
  struct sigaction saved_terminate_ {};
};

// A checkpoint resumes only on the rank count that wrote it (each rank holds
// its own part of the state, checkpoint_format.hpp): another count is bad
// input, refused before any set-up, naming the file and both counts. Every
// rank reads the same file (rank 0's), so every rank refuses alike.
void require_same_rank_count(const std::string& restart) {
  std::ifstream in(restart, std::ios::binary);
  if (!in) throw InputError(restart, "--restart", restart, "cannot open the checkpoint file");
  checkpoint::RankLayout written;
  try {
    written = checkpoint::read_rank_layout(in);
  } catch (const SolverError& e) {
    throw InputError(restart, "--restart", restart, e.what());
  }
  const int ranks = mpi_ranks();
  if (written.ranks != static_cast<std::uint32_t>(ranks))
    throw InputError(restart, "--restart", restart,
                     fmt::format("written by a run on {} MPI rank{}, this run has {}: resume it on {} (`mpirun -n {} "
                                 "fdem run ...`{}); each rank's part of the state is its own file beside it",
                                 written.ranks, written.ranks == 1 ? "" : "s", ranks, written.ranks, written.ranks,
                                 written.ranks == 1 ? ", or without mpirun" : ""));
  if (ranks > 1)
    for (std::uint32_t r = 1; r < written.ranks; ++r) {
      const std::string file = checkpoint::rank_file_path(restart, r);
      std::error_code ec;
      if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(restart, "--restart", restart,
                         fmt::format("written on {} ranks, but rank {}'s file {} is missing", written.ranks, r, file));
    }
}

// Hex FNV-1a of the scene's input files (the scene and its particle CSVs):
// the manifest's scene identity.
std::string scene_inputs_hash(const std::vector<std::string>& files) {
  checkpoint::Hasher h;
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    h.text(text.str());
  }
  return fmt::format("{:016x}", h.value());
}

// fdem::Simulation seen through RunTarget.
class SimulationTarget final : public RunTarget {
 public:
  // fdem run gathers the grains only at the steps it writes (Outputs::after_step).
  explicit SimulationTarget(const Scene& scene) : sim_(scene) { sim_.set_gather_each_step(false); }
  void gather_particles() override { sim_.gather_particles(); }
  void load_checkpoint(std::istream& in) { sim_.load_checkpoint(in); }
  void step() override { sim_.step(); }
  double time() const override { return sim_.time(); }
  double step_size() const override { return sim_.step_size(); }
  long step_index() const override { return sim_.step_index(); }
  bool finished() const override { return sim_.finished(); }
  const Particles& particles() const override { return sim_.particles(); }
  const BoxMesh* mesh() const override { return sim_.mesh(); }
  std::span<const double> fluid_velocity() const override { return sim_.fluid_velocity(); }
  std::span<const double> fluid_pressure() const override { return sim_.fluid_pressure(); }
  std::span<const double> porosity() const override { return sim_.porosity(); }
  std::span<const double> source_term() const override { return sim_.source_term(); }
  std::vector<double> porosity_for_output() const override { return sim_.porosity_for_output(); }
  const SlabPartition* grain_slabs() const override {
    const GrainExchange* exchange = sim_.grain_exchange();
    return exchange != nullptr ? &exchange->slabs() : nullptr;
  }
  std::optional<ProbeSums> own_probe_sums() const override {
    const GrainExchange* exchange = sim_.grain_exchange();
    if (exchange == nullptr || !exchange->distributed()) return std::nullopt;  // every rank holds every grain
    const Particles& here = sim_.local_particles();
    const std::span<const std::uint8_t> ghost = exchange->ghost_mask();
    std::vector<std::size_t> owned;
    owned.reserve(exchange->owned_count());
    for (std::size_t i = 0; i < here.size(); ++i)
      if (i >= ghost.size() || ghost[i] == 0) owned.push_back(i);
    return probe_sums(here, owned);
  }
  std::vector<double> source_term_for_output() const override { return sim_.source_term_for_output(); }
  std::vector<std::pair<std::string, double>> diagnostics() const override {
    const CouplingDiagnostics d = sim_.diagnostics();
    std::vector<std::pair<std::string, double>> out{
        {"contacts", static_cast<double>(d.dem.contacts)},
        {"max_overlap_over_d", d.dem.max_overlap_over_diameter},
        {"particles_removed", static_cast<double>(d.dem.particles_removed)}};
    if (sim_.mesh() != nullptr) {
      out.insert(out.end(), {{"floored_elements", static_cast<double>(d.floored_elements)},
                             {"min_porosity", d.min_porosity},
                             {"momentum_imbalance", d.momentum_imbalance},
                             {"particles_outside_mesh", static_cast<double>(d.particles_outside_mesh)}});
    }
    return out;
  }
  PhaseSeconds step_seconds() const override {
    const CouplingDiagnostics d = sim_.coupling_diagnostics();  // every step: not the DEM's pass over the grains
    return {d.fluid_seconds, d.dem_seconds, d.drag_seconds, d.coupling_seconds};
  }
  void save_checkpoint(std::ostream& out) const override { sim_.save_checkpoint(out); }
  std::string grain_layout() const override {
    const GrainExchange* exchange = sim_.grain_exchange();
    if (exchange == nullptr) return fmt::format("the grains stepped by every rank ({})", sim_.replicated_because());
    return fmt::format("the grains decomposed in {} slabs along {} (ghosts within {:.3g} m of a slab face; the cuts "
                       "follow the grain count at neighbour-list rebuilds)",
                       exchange->ranks(), "xyz"[exchange->slabs().axis()], exchange->cutoff());
  }
  std::string exchange_summary() const override {
    const GrainExchange* exchange = sim_.grain_exchange();
    if (exchange == nullptr) return {};
    const ExchangeCounters& c = exchange->counters();
    std::array<double, 5> total{static_cast<double>(c.bytes_sent), static_cast<double>(c.ghost_updates),
                                static_cast<double>(c.redistributions), static_cast<double>(c.migrated),
                                static_cast<double>(exchange->ghost_count())};
    exchange->sum_over_ranks(total);
    const double ranks = exchange->ranks();
    // The load: each rank's owned grains at the end, in its slot.
    std::vector<double> owned(static_cast<std::size_t>(exchange->ranks()), 0.0);
    owned[static_cast<std::size_t>(exchange->rank())] = static_cast<double>(exchange->owned_count());
    exchange->sum_over_ranks(owned);
    double owned_total = 0.0, owned_most = 0.0;
    for (double n : owned) {
      owned_total += n;
      owned_most = std::max(owned_most, n);
    }
    const double imbalance = owned_total > 0.0 ? owned_most * ranks / owned_total : 1.0;
    // Every rank takes part in every update and redistribution: per rank, the same count.
    // The inner cuts (every rank holds the same), moved by rebalances of the slabs.
    std::vector<double> cuts;
    for (int b = 1; b < exchange->ranks(); ++b) cuts.push_back(exchange->slabs().boundary(b));
    std::string summary = fmt::format(
        "{:.6g} bytes sent by the {} ranks in {:.0f} ghost updates and {:.0f} redistributions, {:.0f} "
        "grains migrated, {:.0f} ghosts held at the end; grains per rank at the end {} (largest / mean "
        "{:.3f}); slabs cut at {} = {:.6g} m after {} rebalance{}",
        total[0], exchange->ranks(), total[1] / ranks, total[2] / ranks, total[3], total[4], fmt::join(owned, ", "),
        imbalance, "xyz"[exchange->slabs().axis()], fmt::join(cuts, ", "), c.rebalances, c.rebalances == 1 ? "" : "s");
    if (const ElementSums* sums = sim_.element_sums(); sums != nullptr) {
      std::array<double, 1> sent{static_cast<double>(sums->bytes_sent())};
      exchange->sum_over_ranks(sent);
      summary += fmt::format("; the coupling's element sums: {:.6g} bytes sent by the {} ranks in {} exchanges",
                             sent[0], exchange->ranks(), sums->exchanges());
    }
    return summary;
  }

 private:
  Simulation sim_;
};

}  // namespace

StopOnSignal::StopOnSignal() {
  g_stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = fdem_stop_handler;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: a blocking write returns EINTR and is retried by our writers
  sigaction(SIGINT, &action, &g_saved.interrupt);
  sigaction(SIGTERM, &action, &g_saved.terminate);
}
StopOnSignal::~StopOnSignal() {
  sigaction(SIGINT, &g_saved.interrupt, nullptr);
  sigaction(SIGTERM, &g_saved.terminate, nullptr);
}
bool StopOnSignal::requested() const { return g_stop_signal != 0; }
int StopOnSignal::signal_number() const { return static_cast<int>(g_stop_signal); }

namespace {
// The grains of the whole run, on every rank (a collective when the ranks
// hold only their own grains).
std::size_t total_particles(const RunTarget& target) {
  const std::size_t here = target.particles().size();
  if (mpi_ranks() == 1 || target.particles_replicated()) return here;
  return static_cast<std::size_t>(sum_over_ranks(static_cast<double>(here)));
}
}  // namespace

int run_loop(RunTarget& target, const Scene& scene, const RunOptions& options, std::FILE* log) {
  using Clock = std::chrono::steady_clock;
  const auto started = Clock::now();
  const StopOnSignal stop;
  // On several MPI ranks every rank writes its part of the output (Outputs);
  // rank 0 alone reports (the others get log == nullptr from run_scene_command).
  Outputs outputs(scene, target, options.output_dir.empty() ? scene.output.directory : options.output_dir);
  if (!options.restart.empty()) {
    const std::filesystem::path old_csv = std::filesystem::path(options.restart).parent_path() / "probes.csv";
    const long carried = outputs.carry_probes_from(old_csv.string(), target.step_index());
    if (log != nullptr) {
      if (carried >= 0)
        std::fprintf(log, "fdem run: %ld probe rows before step %ld carried from %s\n", carried, target.step_index(),
                     old_csv.c_str());
      else
        std::fprintf(log, "fdem run: no probe rows carried (%s missing or of other columns)\n", old_csv.c_str());
    }
  }
  target.gather_particles();  // the loaded or initial state: a no-op unless gathered lazily
  const std::size_t initial_particles = total_particles(target);
  PhaseSeconds phases;
  double output_s = 0.0;
  const auto write_outputs = [&](bool force, bool interrupted) {
    const auto t0 = Clock::now();
    outputs.after_step(target, force, interrupted);
    output_s += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  if (log != nullptr) {
    std::fprintf(log, "fdem run: %s: %zu particles, %s, step %g s to %g s, output in %s\n", scene.source_file.c_str(),
                 initial_particles,
                 target.mesh() != nullptr ? fmt::format("{} fluid elements", target.mesh()->num_elements()).c_str()
                                          : "no fluid",
                 target.step_size(), scene.time.end_time, outputs.directory().c_str());
    for (const auto& [topic, what] : active_physics(scene)) std::fprintf(log, "  %-9s %s\n", topic.c_str(), what.c_str());
    if (mpi_ranks() > 1)
      std::fprintf(log, "  %-9s %d MPI ranks: %s%s; each rank writes the grains of its slab (particles_*.pvtu pieces) "
                   "and its checkpoint, rank 0 the rest\n",
                   "ranks", mpi_ranks(),
                   target.mesh() != nullptr ? "the fluid's linear solve shared (PETSc, a block of rows each), " : "",
                   target.grain_layout().c_str());
  }
  // 1. The initial state, so every series starts at t = 0.
  write_outputs(false, false);
  // 2. Step to the end, or until asked to stop.
  ProgressReporter progress(options.quiet ? nullptr : log, scene.time.end_time,
                            log != nullptr && ProgressReporter::is_terminal(log));
  progress.update(target.step_index(), target.time());
  // A failed step throws: its state is suspect (NaN, blow-up), and every
  // probe row before it is already in the file.
  bool all_gone = false;
  // on_any_rank: the ranks stop after the same step (a collective; finished()
  // and all_gone are the same on every rank, so all of them reach it).
  while (!target.finished() && !on_any_rank(stop.requested()) && !all_gone) {
    target.step();
    phases += target.step_seconds();
    write_outputs(false, false);
    progress.update(target.step_index(), target.time());
    if (options.stop_when_empty && initial_particles > 0) {
      target.gather_particles();
      all_gone = total_particles(target) == 0;
    }
  }
  const bool stopped = on_any_rank(stop.requested());
  // 3. The last state, whatever the cadence.
  write_outputs(true, stopped);
  progress.finish(target.step_index(), target.time());
  target.gather_particles();  // written by the forced outputs above, or now
  const std::size_t remaining = total_particles(target);
  const std::size_t lost = initial_particles - std::min(initial_particles, remaining);
  if (log != nullptr && lost > 0) {
    std::fprintf(log, "fdem run: %zu of %zu particles left the open domain and were removed (particles_removed in "
                 "probes.csv)%s\n",
                 lost, initial_particles,
                 all_gone ? fmt::format("; none left at t = {:g} s, run stopped (--stop-when-empty)", target.time())
                                .c_str()
                          : "");
  }
  const std::string exchanged = target.exchange_summary();  // a collective: before any rank's early return
  if (log != nullptr && !exchanged.empty()) std::fprintf(log, "fdem run: grain exchange: %s\n", exchanged.c_str());
  if (log != nullptr) {
    const double wall_s = std::chrono::duration<double>(Clock::now() - started).count();
    std::fprintf(log, "fdem run: wall %.3g s: fluid %.3g s, DEM %.3g s (drag %.3g s of it), coupling %.3g s, output %.3g s, "
                 "other %.3g s\n", wall_s, phases.fluid, phases.dem, phases.drag, phases.coupling, output_s,
                 wall_s - phases.fluid - phases.dem - phases.coupling - output_s);
  }
  if (stopped) {
    if (log != nullptr) {
      std::fprintf(log,
                   "fdem run: stopped by signal %d at t = %g s (step %ld); output is complete up to it; resume with "
                   "--restart %s/checkpoint.bin\n",
                   stop.signal_number(), target.time(), target.step_index(),
                   outputs.directory().c_str());
    }
    return kExitInterrupted;
  }
  return 0;
}

int run_scene_command(const std::string& scene_path, const RunOptions& options) {
  namespace fs = std::filesystem;
  const StopDuringSetup stop_during_setup;
  if (options.threads > 0) {
    omp_set_num_threads(options.threads);
  } else if (mpi_ranks() > 1 && std::getenv("OMP_NUM_THREADS") == nullptr) {
    // The ranks share the machine's cores rather than each taking all of them.
    omp_set_num_threads(std::max(1, omp_get_num_procs() / mpi_ranks()));
  }
  const bool rank0 = mpi_rank() == 0;
  // 1. Bad input first: the scene, the checkpoint's path, the output folder.
  const Scene scene = load_scene(scene_path);
  require_runnable_size(scene);
  require_memory_fits(scene, options.ignore_memory_limit);
  const std::string out_dir = options.output_dir.empty() ? scene.output.directory : options.output_dir;
  std::vector<std::string> inputs{scene_path};
  for (const ParticleSet& set : scene.particles)
    if (set.placement == PlacementKind::csv) inputs.push_back(set.csv_file);
  const std::string scene_hash = scene_inputs_hash(inputs);
  if (!options.restart.empty()) {
    std::error_code ec;
    if (fs::equivalent(fs::path(options.restart).parent_path().empty() ? fs::path(".")
                                                                       : fs::path(options.restart).parent_path(),
                       fs::path(out_dir), ec))
      throw InputError(options.restart, "--output", out_dir,
                       "a resumed run must write to another folder than the checkpoint's (its snapshots would be "
                       "overwritten); pass --output NEW_DIR");
    if (!fs::is_regular_file(options.restart, ec))
      throw InputError(options.restart, "--restart", options.restart, "cannot open the checkpoint file");
    require_same_rank_count(options.restart);
    inputs.push_back(options.restart);
  }
  std::optional<OutputFolder> folder;  // rank 0's (the others write into it once it is claimed)
  if (rank0)
    folder.emplace(OutputFolderRequest{out_dir, options.output_dir.empty() ? "output.directory" : "--output",
                                       scene_path, inputs, scene_hash, options.restart, options.overwrite},
                   stderr);
  // The other ranks write their pieces only into a claimed (cleared) folder;
  // a refusal on rank 0 ends every rank (app/main.cpp) while they wait here.
  on_any_rank(false);
  // 2. Set-up.
  SimulationTarget target(scene);
  if (!options.restart.empty()) {
    // Every rank its own file of the same step (checkpoint_format.hpp).
    const std::string mine =
        checkpoint::rank_file_path(options.restart, static_cast<std::uint32_t>(mpi_rank()));
    std::ifstream in(mine, std::ios::binary);
    if (!in) throw InputError(mine, "--restart", options.restart, "cannot open this rank's checkpoint file");
    try {
      target.load_checkpoint(in);  // refuses another scene's or a truncated checkpoint
    } catch (const SolverError& e) {
      // On several ranks the file is this rank's own: name it.
      if (mpi_ranks() == 1) throw;
      throw SolverError(fmt::format("{}: {}", mine, e.what()));
    }
    std::array<double, 2> steps{static_cast<double>(target.step_index()), -static_cast<double>(target.step_index())};
    max_over_ranks(steps);
    if (steps[0] != -steps[1])
      throw InputError(options.restart, "--restart", options.restart,
                       fmt::format("the ranks' checkpoint files hold different steps ({:.0f} to {:.0f}: a run "
                                   "stopped while writing them); resume from an earlier complete set",
                                   -steps[1], steps[0]));
    if (rank0) std::fprintf(stderr, "fdem: resumed from %s at t = %.6g s\n", options.restart.c_str(), target.time());
  }
  return run_loop(target, scene, options, rank0 ? stderr : nullptr);
}

}  // namespace fdem

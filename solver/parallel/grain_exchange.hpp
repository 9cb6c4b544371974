#pragma once
// The DEM's grains decomposed over MPI ranks by slabs (parallel/slab_partition.hpp):
// each rank owns the grains whose centre lies in its slab and holds, besides
// them, ghost copies of the neighbours' grains within `cutoff` of its slab
// faces, so every contact of an owned grain is between two grains it holds.
//
//   rebalance()      at each Verlet-list rebuild, first: the slab boundaries
//                    moved to the quantiles of the owned grains' coordinate
//                    (SlabPartition::rebalanced) when the most loaded rank
//                    holds more than kBalanceTolerance over the mean and the
//                    move would take that much off it (the hysteresis: a
//                    cut within the tolerance stays, so grains near it do
//                    not migrate back and forth as they jiggle).
//   redistribute()   at each Verlet-list rebuild: ghosts dropped, owned grains
//                    whose centre left the slab sent to the slab's owner
//                    (migration), then every owned grain within the cutoff of
//                    a face sent to that neighbour as a ghost. Afterwards the
//                    arrays hold owned and ghost grains together in ascending
//                    id, so a neighbour-list row lists its grains in the order
//                    one process would: a grain's force is summed over its
//                    contacts in the same order, bit for bit.
//                    Per-grain arrays of the caller's own (`carried`: the
//                    coupling's drag state of each grain) travel with the
//                    grains: reordered, sent along on migration, copied to
//                    the ghosts, so the caller finds each grain's values at
//                    its new index.
//   update_ghosts()  every DEM step, after the drift: the ghosts' positions
//                    and velocities (angular too, with rotation) overwritten
//                    with their owners' (the ghosts' own drift, made with
//                    incomplete forces, is discarded).
//
// The cutoff for contacts is d_max + skin: a pair (i, j) enters the list
// when |x_i - x_j| < r_i + r_j + skin <= d_max + skin, and along the cut axis
// |x_i - x_j| >= the distance from j to i's slab face, so every grain j that
// can be listed with an owned i is a ghost on i's rank. The list stays valid
// until the next rebuild (no pair's relative displacement exceeds the skin),
// so ghosts and ownership are refreshed only then.
//
// Collective: every rank calls each method at the same point. Built only
// for a run on several ranks; one process never constructs one.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/particles.hpp"
#include "parallel/duplicate_communicator.hpp"
#include "parallel/slab_partition.hpp"

namespace fdem {

/// Messages between neighbours since construction (for the benchmarks'
/// communication volume).
struct ExchangeCounters {
  std::size_t redistributions = 0;
  std::size_t ghost_updates = 0;
  std::size_t migrated = 0;          // grains this rank sent away as their new owner's
  std::size_t rebalances = 0;        // rebalance() calls that moved the boundaries
  std::size_t bytes_sent = 0;        // by this rank to its neighbours, payloads only (not the
                                     // collectives: rebalance's sum is kBalanceBins + ranks doubles)
};

class GrainExchange {
 public:
  /// On MPI_COMM_WORLD (duplicated, so its messages never meet PETSc's);
  /// slabs.ranks() must equal its size. `rotation`: the grains carry angular
  /// velocity, torque and inertia (they travel and the ghosts' spin is
  /// updated). Throws std::invalid_argument when MPI is not running or the
  /// rank counts differ.
  GrainExchange(const SlabPartition& slabs, bool rotation);
  ~GrainExchange();
  GrainExchange(const GrainExchange&) = delete;
  GrainExchange& operator=(const GrainExchange&) = delete;

  int rank() const { return rank_; }
  int ranks() const { return slabs_.ranks(); }
  const SlabPartition& slabs() const { return slabs_; }

  /// Ghost band width [m] (d_max + skin for contacts). Throws
  /// std::invalid_argument when a slab is thinner than it (a ghost would be
  /// needed two slabs away: fewer ranks).
  void set_cutoff(double cutoff_m);
  double cutoff() const { return cutoff_; }

  /// Load tolerance of rebalance(): the largest rank's grains over the mean, less 1.
  static constexpr double kBalanceTolerance = 0.05;
  /// Bins of rebalance()'s histogram along the cut axis (summed over the
  /// ranks: 8 bytes each per call); within a bin the cut is interpolated.
  static constexpr int kBalanceBins = 2048;
  /// Moves the slab boundaries towards equal grain counts (see the header
  /// comment), each boundary at least the cutoff inside its old neighbours
  /// once the grains are distributed (migration stays between neighbours),
  /// every slab at least the cutoff thick. Counts the owned grains of p as
  /// the last redistribute left them (before the first: the whole set every
  /// rank holds, no messages). Call before route_with_grains and
  /// drop_ghosts, on every rank. Returns whether the boundaries moved.
  bool rebalance(const Particles& p);
  /// Off: rebalance() keeps the boundaries the exchange was built with (a
  /// test of migration across a boundary that must stay put). On by default.
  void set_balancing(bool on) { balancing_ = on; }
  bool balancing() const { return balancing_; }

  /// The first call takes the whole replicated set every rank was built
  /// with and keeps this rank's share; later calls migrate. Either way the
  /// ghosts are then gathered and the arrays sorted by id. Particles p must
  /// carry ids (global and unique). Throws SolverError when a grain moved
  /// past a whole slab between two calls.
  /// `carried`: arrays of p.size() values each that move with their grains
  /// (the same number of arrays on every rank; std::invalid_argument otherwise
  /// when their lengths are not p.size()).
  void redistribute(Particles& p, std::span<std::vector<double>> carried = {}) {
    drop_ghosts(p, carried);
    migrate_and_gather_ghosts(p, carried);
  }
  /// redistribute() in two halves, for a caller that removes lost grains
  /// between them (so a ghost is never counted as lost): the ghosts dropped
  /// (on the first call: the other ranks' grains), then migration and ghosts.
  void drop_ghosts(Particles& p, std::span<std::vector<double>> carried = {});
  /// The next drop_ghosts() takes a whole replicated set again (a checkpoint loaded on every rank).
  void forget_distribution() {
    distributed_ = false;
    ghost_.clear();
  }
  /// A checkpoint's cut (its inner boundaries, as slabs().boundary(1..ranks-1)
  /// gave them when it was written) in place of this one's, and the
  /// distribution forgotten: the next redistribute takes the whole loaded
  /// set and keeps each rank's share by this cut, which the next rebalance
  /// moves only past the hysteresis, as the writer's would. Throws
  /// std::invalid_argument for a cut that does not fit the box and ranks.
  void restore_cut(std::span<const double> inner_boundaries) {
    slabs_ = slabs_.with_inner_boundaries(inner_boundaries);
    forget_distribution();
  }
  void migrate_and_gather_ghosts(Particles& p, std::span<std::vector<double>> carried = {});
  /// The ghosts' x, v (and w) from their owners; p as the last redistribute left it.
  void update_ghosts(Particles& p);

  /// Per local grain: 1 for a ghost, 0 for an owned grain (as of the last redistribute).
  std::span<const std::uint8_t> ghost_mask() const { return ghost_; }
  /// Whether redistribute has split the set (before that, every rank holds the whole set).
  bool distributed() const { return distributed_; }
  std::size_t owned_count() const { return owned_count_; }
  std::size_t ghost_count() const { return ghost_.size() - owned_count_; }
  const ExchangeCounters& counters() const { return counters_; }

  /// Records of `record_size` doubles, each about one of this rank's owned
  /// grains (record r about grain `grain[r]` of p as it is before
  /// redistribute): each goes where its grain goes in the next
  /// redistribute (kept when the grain stays, sent when it migrates to a
  /// neighbour, dropped otherwise). Returns the records this rank holds
  /// afterwards: its staying ones, then its neighbours'. For per-grain
  /// state of varying length (the DEM's slip history, one record per
  /// contact). A collective; call before drop_ghosts, on p unchanged.
  std::vector<double> route_with_grains(const Particles& p, std::span<const std::size_t> grain,
                                        std::span<const double> records, std::size_t record_size) const;
  /// Every rank's records, on every rank, rank after rank (a collective).
  std::vector<double> gather_records(std::span<const double> mine) const;

  /// Collectives over the exchange's communicator (every rank, same point).
  void max_over_ranks(std::span<double> values) const;
  void sum_over_ranks(std::span<double> values) const;
  bool any_rank(bool flag) const;

  /// Every rank's owned grains, on every rank, in ascending id (all arrays
  /// the grains carry): the whole set as one process holds it, for output
  /// and checkpoints. The ghosts are left out.
  Particles gather_owned(const Particles& p) const;
  /// Per-grain arrays of this rank's grains (p.size() values each), every
  /// rank's owned grains' values on every rank in ascending id (the order of
  /// gather_owned): a caller's per-grain state for a checkpoint.
  std::vector<std::vector<double>> gather_owned_arrays(const Particles& p,
                                                       std::span<const std::vector<double>> arrays) const;

 private:
  // One grain record: the double arrays of Particles that are in use, the carried arrays, then the id.
  std::size_t record_size(std::size_t carried) const;
  void pack(const Particles& p, std::span<const std::vector<double>> carried, std::size_t i,
            std::vector<double>& out) const;
  void unpack(std::span<const double> in, Particles& p, std::span<std::vector<double>> carried) const;
  // Both neighbours at once: send[0] to the lower, send[1] to the upper; returns what they sent.
  std::array<std::vector<double>, 2> swap_with_neighbours(const std::array<std::vector<double>, 2>& send,
                                                          int tag) const;

  SlabPartition slabs_;
  bool rotation_ = false;
  int rank_ = 0;
  DuplicateCommunicator comm_;
  double cutoff_ = 0.0;
  bool distributed_ = false;
  bool balancing_ = true;
  std::vector<std::uint8_t> ghost_;
  std::size_t owned_count_ = 0;
  // Ghost updates: local indices sent to [lower, upper] and where their ghosts are on this rank.
  std::array<std::vector<std::size_t>, 2> sent_index_, ghost_index_;
  mutable ExchangeCounters counters_;
};

}  // namespace fdem

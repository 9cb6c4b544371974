#pragma once
// The pairs that can touch (DemEngine's half-list pair pass, without
// tangential contact): of the neighbour list's pairs, indexed once a list
// build as the half list (i, j > i) in row order, the pair pass tests only
// the near set, the half pairs whose surface gap |x_i - x_j| - r_i - r_j
// was below a margin at the positions of its filtering. A pair left out is
// still apart while the grains came closer by less than the margin since.
// Two bounds on that, the set kept while either holds:
//  * the displacements since the list build (B): the move since the
//    filtering is d(t) - d(t_f), so no pair came closer than B(t) + B(t_f).
//    Free (the rebuild test's extremes); it keeps a block that falls as one
//    (scene P) on its set all along, but a deforming cloud (the plume) soon
//    outgrows it;
//  * the drift velocities' spread, summed over the steps since the
//    filtering (`approach`): survives deformation, but costs the fused
//    kick-drift six min/max a grain (scene P 348k -> 440k instructions a
//    step, callgrind), so it is only tracked (tracks_drift()) from the
//    first time the displacement bound ran out after a list build; a step
//    without it (approach infinite) leaves the sum infinite until the next
//    filtering.
// The set is refiltered from the half list when both run out; the margin
// is at least 1/1024 of the skin and 16 steps' drift approach (tracked) or
// 4 B (not yet), so a filtering (one distance test a half pair) serves
// many steps. Past half the skin, or unknown (decomposed: the ghosts'),
// the whole half list. Leaving out pairs that cannot touch leaves the
// touching pairs, their order and so every bit unchanged.
#include <cstddef>
#include <limits>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "dem/neighbour_list.hpp"
#include "dem/pair_shares.hpp"

namespace fdem {

class NearPairs {
 public:
  /// A list build or a load: the half pairs are indexed anew at the next select().
  void invalidate() { stale_ = true; }

  /// What select() did, for the engine's counters.
  struct Selection {
    PairSet pairs;
    bool filtered = false;  // a new near set was filtered
    bool threaded = false;  // in shares on more than one thread
  };
  /// The pairs of `list` that can touch now (header comment). approach:
  /// how much closer any two grains came in this step's drift (infinite:
  /// unknown); moved: the displacement bound B now (infinite: unknown).
  /// Filters in shares on threads above `parallel_min` half pairs.
  Selection select(const NeighbourList& list, const Particles& p, double approach, double moved,
                   std::ptrdiff_t parallel_min);

  /// Whether the fused kick-drift should take the drift velocities' extremes.
  bool tracks_drift() const { return track_drift_; }
  /// One more at every indexing and filtering: a new pair set.
  std::size_t generation() const { return generation_; }
  /// The largest coordinate or diameter at the list build [m].
  double build_scale() const { return build_scale_; }

 private:
  // After a list build: the half pairs of `list` in row order, the
  // rounding allowance from its build's positions and the diameters; no
  // near set yet, and the drift not tracked.
  void index(const NeighbourList& list, const Particles& p);
  PairSet all() const { return {half_i_.data(), half_j_.data(), half_start_.data(), half_j_.size()}; }
  PairSet near() const { return {near_i_.data(), near_j_.data(), near_start_.data(), near_count_}; }
  bool filter(double margin, const Particles& p, std::ptrdiff_t parallel_min);
  std::size_t filter_in_shares(double margin, const Particles& p, std::ptrdiff_t parallel_min, bool& threaded);

  bool stale_ = true;  // the half pairs are of an older list (invalidate)
  std::vector<Index> half_i_, half_j_, half_start_;
  double build_scale_ = 0.0;   // largest coordinate or diameter at the list build [m]
  double gap_rounding_ = 0.0;  // margin for the rounding of gaps and displacements [m]
  // The half pairs within near_margin_ of touching at their filtering
  // (near_count_ of them); near_approach_: how much closer any two grains
  // can have come since.
  std::vector<Index> near_i_, near_j_, near_start_;
  std::size_t near_count_ = 0;
  double near_margin_ = 0.0;
  double near_approach_ = 0.0;
  bool near_valid_ = false;
  double near_moved_ = 0.0;  // the displacement bound B at the filtering (infinite: unknown)
  bool track_drift_ = false;
  std::size_t generation_ = 0;
  // One thread's near pairs in a filtering in shares, on its own cache lines.
  struct alignas(64) Share {
    std::vector<Index> i, j;
    std::size_t count = 0;
  };
  std::vector<Share> shares_;
};

}  // namespace fdem

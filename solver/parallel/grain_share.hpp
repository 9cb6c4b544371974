#pragma once
// Which of a rank's grains it counts when it sums over grains into a field
// of the mesh (porosity, source term, exchange coefficients, total drag),
// and how the ranks' partial fields become the whole one. Decomposed over
// MPI ranks (parallel/grain_exchange.hpp) a rank counts the grains it owns,
// not its ghosts, and the per-element or per-node sums are then added over
// the ranks with one MPI_Allreduce over the whole array: every rank holds
// the whole (replicated) mesh, so a reduce costs O(elements) per call on
// every rank whatever the grains, below the fluid solve's O(elements) per
// rank but not shrinking with the rank count (ghost elements of the slab
// would). Each grain is counted once over the ranks; an element touched by
// two ranks' grains gets their two partial sums added, so its value differs
// from one process's ascending sum by rounding (a few ulp).
//
// Default (no exchange, or one not yet distributed: before the first list
// rebuild every rank still holds the whole set): every grain counts and
// nothing is added, one process's sums bit for bit.
#include <cstddef>
#include <cstdint>
#include <span>

#include "parallel/grain_exchange.hpp"

namespace fdem {

struct GrainShare {
  const GrainExchange* exchange = nullptr;

  bool decomposed() const { return exchange != nullptr && exchange->distributed(); }
  /// Whether grain i of this rank's arrays counts in this rank's sums.
  bool counts(std::size_t i) const {
    if (!decomposed()) return true;
    const std::span<const std::uint8_t> ghost = exchange->ghost_mask();
    return i >= ghost.size() || ghost[i] == 0;
  }
  /// The ranks' partial sums added, in place on every rank (a collective when decomposed).
  void sum_over_ranks(std::span<double> values) const {
    if (decomposed()) exchange->sum_over_ranks(values);
  }
  double sum_over_ranks(double value) const {
    sum_over_ranks(std::span<double>(&value, 1));
    return value;
  }
};

}  // namespace fdem

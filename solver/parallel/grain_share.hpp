#pragma once
// Which of a rank's grains it counts when it sums over grains into a field
// of the mesh (porosity, source term, exchange coefficients, total drag),
// and how the ranks' partial fields become the whole one. Decomposed over
// MPI ranks (parallel/grain_exchange.hpp) a rank counts the grains it owns,
// not its ghosts. A per-element field (sum_over_elements) is then completed
// by messages between the ranks that touch and need each element
// (parallel/element_sums.hpp): each rank holds the sums where its grains and
// its fluid rows read them, 0 elsewhere, and each element's diagnostics are
// counted by its one owner (owns_element) and added over the ranks
// (sum_over_element_owners). A per-node field (sum_over_nodes: the
// shape-function and diffused porosity's nodal solid) is completed the same
// way on the corners of the elements a rank needs, or (the diffused
// scheme's smoothing solve over the whole mesh) on every node, its touched
// nodes' records then going to every rank: O(grains) bytes either way.
// Without an ElementSums (no mesh exchange built) the fields are added whole
// with one MPI_Allreduce, O(elements) a call whatever the grains.
// Each grain is counted once over the ranks; an element touched by two
// ranks' grains gets their two partial sums added, so its value differs
// from one process's ascending sum by rounding (a few ulp).
//
// Default (no exchange, or one not yet distributed: before the first list
// rebuild every rank still holds the whole set): every grain counts and
// nothing is added, one process's sums bit for bit.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>

#include "parallel/element_sums.hpp"
#include "parallel/grain_exchange.hpp"

namespace fdem {

struct GrainShare {
  const GrainExchange* exchange = nullptr;
  const ElementSums* elements = nullptr;  // per-element fields completed by neighbours (else Allreduce)

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
  /// Per-element fields (`components` values an element each) completed
  /// where this rank needs them (ElementSums), or added whole over the ranks.
  /// `touched`: every element the counted grains summed into (repeats and
  /// -1 allowed, e.g. ParticleMapping::element); the fields are 0 elsewhere.
  void sum_over_elements(std::span<const Index> touched, std::initializer_list<ElementSums::Field> fields) const {
    if (!decomposed()) return;
    if (elements != nullptr) {
      elements->sum_over_ranks(std::span<const ElementSums::Field>(fields.begin(), fields.size()), touched);
      return;
    }
    for (const ElementSums::Field& f : fields) exchange->sum_over_ranks(f.values);
  }
  /// Per-node fields completed where this rank needs them (the corners of
  /// the elements it needs; `everywhere`: every node, for a solve over the
  /// whole mesh), or added whole over the ranks. `touched`: every node the
  /// counted grains summed into (repeats allowed); the fields are 0 elsewhere.
  void sum_over_nodes(std::span<const Index> touched, bool everywhere,
                      std::initializer_list<ElementSums::Field> fields) const {
    if (!decomposed()) return;
    if (elements != nullptr) {
      elements->sum_nodes_over_ranks(std::span<const ElementSums::Field>(fields.begin(), fields.size()), touched,
                                     everywhere);
      return;
    }
    for (const ElementSums::Field& f : fields) exchange->sum_over_ranks(f.values);
  }
  /// Whether this rank counts element e in a sum or extreme over elements
  /// (each element on one rank; every element in one process).
  bool owns_element(std::size_t e) const {
    return elements == nullptr || elements->owns_element(static_cast<Index>(e));
  }
  /// Sums over the elements' owners added over the ranks (a collective with
  /// ElementSums, which exists only with the grains' exchange).
  void sum_over_element_owners(std::span<double> values) const {
    if (elements != nullptr) exchange->sum_over_ranks(values);
  }
  double max_over_element_owners(double value) const {
    if (elements != nullptr) exchange->max_over_ranks(std::span<double>(&value, 1));
    return value;
  }
};

}  // namespace fdem

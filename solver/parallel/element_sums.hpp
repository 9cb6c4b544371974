#pragma once
// The coupling's sums over grains into the box mesh's elements (porosity's
// solid volume, the source term's drag and solid, the semi-implicit
// exchange's coefficients), completed on MPI ranks by messages between the
// ranks that need them instead of one MPI_Allreduce over the whole mesh.
//
// Each rank sums its own grains (parallel/grain_share.hpp), so its partial
// sums are non-zero only in the elements its grains touch: the contribution
// band C_r, the cells within cutoff + 1 cell of its grain slab along the cut
// axis (an owned grain's centre is inside its slab up to half the Verlet
// skin, and the element-overlap porosity reaches a radius further: both
// below the ghost cutoff d_max + skin). A rank needs the complete sum in
//   - the read band R_r: the cells within 2 cutoff + 2 cells of its slab
//     and its neighbours' slabs, where its owned and ghost grains read the
//     porosity (drag, fluid stress; a ghost lies within the cutoff of the
//     slab and drifts up to half the skin), the neighbour cells of their
//     elements, and where a rebalance in the middle of a fluid step may
//     move its faces (GrainExchange::rebalance keeps each new face a cutoff
//     inside the old neighbours' slabs; the drag maps grains that arrive
//     again with the step start's porosity when grains were lost);
//   - the fluid layers F_r: the z-layers of cells its fluid rows assemble
//     (PetscLinearSolver::owned_node_range, node levels l0..l1: layers
//     l0-1..l1) and one more on each side, whose element values the nodal
//     averages of those rows take in (the P1 porosity, the nodal source).
// Rank r sends rank s the elements of C_r in N_s = R_s + F_s where one of
// its fields is non-zero, as (element, values) records: every rank knows
// every rank's slabs, cutoff and fluid rows, so sender and receiver agree on
// who sends whom without asking, and the bytes a step are the elements that
// both hold grains of r and are needed by s: at most the elements r's grains
// touch, O(grains a rank) (the plume on 2 ranks: about 40 records an
// exchange, where the Allreduce moved all 12500 elements). With slabs
// along z the fluid's and the grains' bands are both z intervals, so a rank
// talks to the few ranks whose intervals meet its own; cut along x or y
// every rank's grains meet every rank's fluid layers (a rank sends its
// touched elements to each rank whose layers hold them). The exchange walks
// only the elements the caller says its grains touched (the mapping's
// elements, the overlaps' elements) and the records it receives: its work is
// O(grains a rank) too, never O(elements).
//
// The complete value of an element is the ranks' partial sums added in
// rank order from +0 (a partial sum that starts at +0 is never -0, so
// skipping a zero partial changes no bit): every rank that holds an element
// holds the same bits, and on 2 ranks they are MPI_SUM's p0 + p1. Outside
// N_r a rank's fields are set to 0 (no solid, no drag: a porosity of 1), the
// same whatever its grains, so they are deterministic and never read.
//
// Each element layer (and each node) has one owner, the rank whose fluid
// rows hold the layer's first node (the node): its diagnostics (the
// least porosity, the floored count, the total force on the fluid) are
// counted there and summed over the ranks, and the output gathers each
// layer from its owner.
//
// Collective: every rank calls sum_over_ranks (and the gathers) at the same
// point. Built only for a run whose grains are decomposed on several ranks.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "parallel/duplicate_communicator.hpp"
#include "parallel/grain_exchange.hpp"

namespace fdem {

/// The box mesh's cells as the exchange needs them (mesh/box_mesh.hpp's
/// numbering: cell = i + nx (j + ny k), element = 5 cell + local, node =
/// I + (nx+1) (J + (ny+1) K)).
struct MeshCells {
  std::array<int, 3> cells{1, 1, 1};
  Vec3 lower = Vec3::Zero();
  Vec3 cell_size = Vec3::Ones();  // [m]

  Index nodes_per_level() const { return static_cast<Index>(cells[0] + 1) * (cells[1] + 1); }
  Index nodes() const { return nodes_per_level() * (cells[2] + 1); }
  Index elements_per_layer() const { return 5 * static_cast<Index>(cells[0]) * cells[1]; }
  Index elements() const { return elements_per_layer() * cells[2]; }
};

class ElementSums {
 public:
  /// One field of the sums: `components` values per element, element-major.
  struct Field {
    std::span<double> values;
    int components = 1;
  };

  /// `fluid_nodes[r]`: the nodes [first, end) whose rows rank r's fluid
  /// assembles (one range per rank, ascending, covering every node once).
  /// `grains`: the grains' slabs and cutoff, read at every call (they move at
  /// list rebuilds). Throws std::invalid_argument when the ranges do not
  /// match the rank count or the mesh.
  ElementSums(const MeshCells& mesh, std::vector<std::pair<Index, Index>> fluid_nodes, const GrainExchange& grains);
  ~ElementSums();
  ElementSums(const ElementSums&) = delete;
  ElementSums& operator=(const ElementSums&) = delete;

  int rank() const { return grains_->rank(); }
  int ranks() const { return grains_->ranks(); }

  /// The fields completed in N of this rank (the header comment), 0 outside;
  /// every field has one record of its components per element. `touched`:
  /// the elements this rank's grains summed into (repeats and -1, a grain
  /// outside the mesh, allowed; more is harmless); every other element
  /// must be 0 in every field. The work is O(touched + records received),
  /// not O(elements): the fields are read and written only there.
  void sum_over_ranks(std::span<const Field> fields, std::span<const Index> touched) const;

  /// Per-node fields (`components` values a node, node-major), completed
  /// as sum_over_ranks completes elements: on the nodes of the elements
  /// this rank needs (needs_node), 0 elsewhere; `everywhere`: on every node
  /// on every rank (a field a solve over the whole mesh reads: the diffused
  /// porosity's), the records then going to every rank. `touched`: the
  /// nodes this rank's grains summed into (repeats allowed); the fields are
  /// 0 elsewhere. Bitwise the ranks' partial sums added in rank order from +0.
  void sum_nodes_over_ranks(std::span<const Field> fields, std::span<const Index> touched, bool everywhere) const;

  /// Whether this rank holds element e's complete sums after sum_over_ranks.
  bool needs_element(Index e) const;
  /// Whether this rank holds node n's complete sums after sum_nodes_over_ranks
  /// (the corners of the elements it needs: needs_element(e) implies it for e's nodes).
  bool needs_node(Index n) const;
  /// Whether this rank owns element e (counts its diagnostics, writes it).
  bool owns_element(Index e) const { return e >= owned_elements_.first && e < owned_elements_.second; }
  /// This rank's owned elements and nodes, [first, end) each (contiguous).
  std::pair<Index, Index> owned_elements() const { return owned_elements_; }
  std::pair<Index, Index> owned_nodes() const { return owned_nodes_; }

  /// Every rank's owned block of `per_item` (`components` values per element,
  /// or per node for gather_nodes) in rank order, on rank 0: the whole field
  /// as one process holds it; empty on the other ranks. A collective.
  std::vector<double> gather_elements(std::span<const double> per_item, int components) const;
  std::vector<double> gather_nodes(std::span<const double> per_item, int components) const;

  /// Payload bytes this rank sent in sum_over_ranks since construction, and the calls.
  std::size_t bytes_sent() const { return bytes_sent_; }
  std::size_t exchanges() const { return exchanges_; }

 private:
  struct Interval {  // cells [first, last] along an axis; empty when last < first
    int first = 0, last = -1;
    bool contains(int c) const { return c >= first && c <= last; }
    bool meets(const Interval& o) const { return first <= o.last && o.first <= last && first <= last; }
  };
  // Slabs first_rank..last_rank widened by pad_m and pad_cells, in cells along the cut axis.
  Interval band(int first_rank, int last_rank, double pad_m, int pad_cells) const;
  Interval contribution(int rank) const;
  Interval reading(int rank) const;
  int along_axis(Index cell) const;
  int layer(Index cell) const { return static_cast<int>(cell / (static_cast<Index>(mesh_.cells[0]) * mesh_.cells[1])); }
  // What the sums are over: elements, nodes where a rank needs them, or nodes everywhere.
  enum class Items { elements, nodes, nodes_everywhere };
  // The cells along the cut axis, and the z-layers, an item belongs to (a node: the two each side of it).
  Interval cells_along(Index item, Items kind) const;
  Interval layers_of(Index item, Items kind) const;
  bool needs(const Interval& reading_band, const Interval& fluid, Index item, Items kind) const;
  // Whether rank `from` may hold non-zero partial sums that rank `to` needs.
  bool linked(int from, int to, Items kind) const;
  void complete(std::span<const Field> fields, std::span<const Index> touched, Items kind) const;
  std::vector<double> gather_block(std::span<const double> per_item, int components, std::pair<Index, Index> mine,
                                   Index items) const;

  MeshCells mesh_;
  std::vector<Interval> fluid_layers_;  // F_r per rank
  // The sums' scratch: a mark per element or node (all 0 between calls) and the touched ones, each once.
  mutable std::vector<std::uint8_t> marked_;
  mutable std::vector<Index> touched_;
  std::pair<Index, Index> owned_elements_{0, 0}, owned_nodes_{0, 0};
  const GrainExchange* grains_;
  DuplicateCommunicator comm_;
  mutable std::size_t bytes_sent_ = 0, exchanges_ = 0;
};

}  // namespace fdem

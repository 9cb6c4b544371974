#pragma once
// Counts of a box mesh in 64 bits, from the cell counts alone (no mesh is
// built): the size checks that refuse a mesh too large to index or to hold
// run before anything is allocated.
#include <array>
#include <cstdint>

namespace fdem {

struct BoxMeshSize {
  std::int64_t cells = 0, nodes = 0, elements = 0;
  // Edges of the 5-tetrahedron split: the axis-parallel cell edges plus one
  // diagonal per cell face (neighbouring cells share their face diagonals; the
  // central tetrahedron adds none through the body).
  std::int64_t edges = 0;
  /// Ordered node pairs that share an element, a node with itself included:
  /// the block pattern of a P1 system, nodes + 2 edges.
  std::int64_t coupled_node_pairs() const { return nodes + 2 * edges; }
};

BoxMeshSize box_mesh_size(const std::array<int, 3>& cells);

}  // namespace fdem

#include "mesh/box_mesh_size.hpp"

namespace fdem {

BoxMeshSize box_mesh_size(const std::array<int, 3>& cells) {
  const std::int64_t x = cells[0], y = cells[1], z = cells[2];
  BoxMeshSize s;
  s.cells = x * y * z;
  s.nodes = (x + 1) * (y + 1) * (z + 1);
  s.elements = 5 * s.cells;
  const std::int64_t axis_edges = x * (y + 1) * (z + 1) + (x + 1) * y * (z + 1) + (x + 1) * (y + 1) * z;
  const std::int64_t faces = x * y * (z + 1) + x * (y + 1) * z + (x + 1) * y * z;
  s.edges = axis_edges + faces;
  return s;
}

}  // namespace fdem

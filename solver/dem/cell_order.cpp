// Grains in the cell order of a CellGrid (see cell_order.hpp).
#include "dem/cell_order.hpp"

#include <utility>

#include "dem/cell_grid.hpp"

namespace fdem {

std::vector<Index> cell_order(const Particles& p, double cell_size_m) {
  CellGrid grid;
  grid.build(p, cell_size_m);
  return std::move(grid.slots);
}

}  // namespace fdem

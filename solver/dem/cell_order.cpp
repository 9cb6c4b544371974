// Counting sort of particles into grid cells (see cell_order.hpp).
#include "dem/cell_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace fdem {

std::vector<Index> cell_order(const Particles& p, double cell_size_m) {
  const std::size_t n = p.size();
  std::vector<Index> order(n);
  if (n == 0) return order;
  double lo[3] = {p.x[0], p.y[0], p.z[0]}, hi[3] = {p.x[0], p.y[0], p.z[0]};
  for (std::size_t i = 0; i < n; ++i) {
    lo[0] = std::min(lo[0], p.x[i]); hi[0] = std::max(hi[0], p.x[i]);
    lo[1] = std::min(lo[1], p.y[i]); hi[1] = std::max(hi[1], p.y[i]);
    lo[2] = std::min(lo[2], p.z[i]); hi[2] = std::max(hi[2], p.z[i]);
  }
  double h = cell_size_m;
  const double max_cells = 4.0 * static_cast<double>(n) + 64.0;  // as NeighbourList::build
  auto cells_for = [&](double size) {
    double c = 1.0;
    for (int a = 0; a < 3; ++a) c *= std::floor((hi[a] - lo[a]) / size) + 1.0;
    return c;
  };
  while (cells_for(h) > max_cells) h *= 1.5;
  int dim[3];
  for (int a = 0; a < 3; ++a) dim[a] = static_cast<int>(std::floor((hi[a] - lo[a]) / h)) + 1;
  const std::size_t n_cells =
      static_cast<std::size_t>(dim[0]) * static_cast<std::size_t>(dim[1]) * static_cast<std::size_t>(dim[2]);
  const double inv_h = 1.0 / h;
  auto coord = [&](double v, int a) { return std::min(dim[a] - 1, static_cast<int>((v - lo[a]) * inv_h)); };
  std::vector<Index> cell_of(n), start(n_cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int c = (coord(p.z[i], 2) * dim[1] + coord(p.y[i], 1)) * dim[0] + coord(p.x[i], 0);
    cell_of[i] = c;
    ++start[static_cast<std::size_t>(c) + 1];
  }
  for (std::size_t c = 0; c < n_cells; ++c) start[c + 1] += start[c];
  for (std::size_t i = 0; i < n; ++i)
    order[static_cast<std::size_t>(start[static_cast<std::size_t>(cell_of[i])]++)] = static_cast<Index>(i);
  return order;
}

}  // namespace fdem

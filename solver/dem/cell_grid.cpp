// Counting sort of particles into a compact cell grid (see cell_grid.hpp).
#include "dem/cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace fdem {

void CellGrid::build(const Particles& p, double cell_size_m, double cells_per_particle) {
  const std::size_t n = p.size();
  cell_of.resize(n);
  slots.resize(n);
  if (n == 0) {
    dims[0] = dims[1] = dims[2] = 0;
    cell_start.assign(1, 0);
    return;
  }
  double lo[3] = {p.x[0], p.y[0], p.z[0]}, hi[3] = {p.x[0], p.y[0], p.z[0]};
  for (std::size_t i = 0; i < n; ++i) {
    lo[0] = std::min(lo[0], p.x[i]); hi[0] = std::max(hi[0], p.x[i]);
    lo[1] = std::min(lo[1], p.y[i]); hi[1] = std::max(hi[1], p.y[i]);
    lo[2] = std::min(lo[2], p.z[i]); hi[2] = std::max(hi[2], p.z[i]);
  }
  double h = cell_size_m;
  const double max_cells = cells_per_particle * static_cast<double>(n) + 64.0;
  auto cells_for = [&](double size) {
    double c = 1.0;
    for (int a = 0; a < 3; ++a) c *= std::floor((hi[a] - lo[a]) / size) + 1.0;
    return c;
  };
  while (cells_for(h) > max_cells) h *= 1.5;
  for (int a = 0; a < 3; ++a) dims[a] = static_cast<int>(std::floor((hi[a] - lo[a]) / h)) + 1;
  const double inv_h = 1.0 / h;
  auto coord = [&](double v, int a) { return std::min(dims[a] - 1, static_cast<int>((v - lo[a]) * inv_h)); };
  cell_start.assign(cells() + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int c = (coord(p.z[i], 2) * dims[1] + coord(p.y[i], 1)) * dims[0] + coord(p.x[i], 0);
    cell_of[i] = c;
    ++cell_start[static_cast<std::size_t>(c) + 1];
  }
  for (std::size_t c = 0; c + 1 < cell_start.size(); ++c) cell_start[c + 1] += cell_start[c];
  std::vector<Index> fill(cell_start.begin(), cell_start.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    slots[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[i])]++)] = static_cast<Index>(i);
}

}  // namespace fdem

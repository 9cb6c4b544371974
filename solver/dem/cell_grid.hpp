#pragma once
// A compact grid of cubic cells over the particles' bounding box (not the
// whole domain: a 20x20x40 mm block in a 100x100x250 mm box costs cells
// only where the grains are), with the particles counting-sorted into it.
// The neighbour list (neighbour_list.hpp) searches it; the grain sort
// (cell_order.hpp) takes its order.
//
// Cells are numbered z-major, then y, then x; within a cell the particles
// are in ascending index (a stable counting sort), so the grid is a
// function of the positions alone. A sparse set (a few particles far
// apart) would need very many cells: the edge is coarsened (x1.5 at a
// time) until there are at most ~4 cells per particle (correct for a
// search, only slower).
#include <cstddef>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"

namespace fdem {

struct CellGrid {
  int dims[3] = {0, 0, 0};
  std::vector<Index> cell_of;     // particle -> its cell
  std::vector<Index> cell_start;  // cell c holds slots[cell_start[c] .. cell_start[c + 1]) (cells + 1 values)
  std::vector<Index> slots;       // particle indices, by cell

  /// Bins p's particles into cells of edge at least `cell_size_m`, with at
  /// most ~`cells_per_particle` cells a particle (the edge coarsened beyond).
  void build(const Particles& p, double cell_size_m, double cells_per_particle = 4.0);
  std::size_t cells() const {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(dims[2]);
  }
};

}  // namespace fdem

#pragma once
// Grains in the order of the cells they lie in. A grain's neighbours then
// lie near it in memory, so the pair pass and the coupling's per-grain
// passes read them from the nearest cache instead of gathering them from
// all over the arrays. A cloud that starts in lattice order loses that
// order as it deforms (the plume's list entries (i, j) are 784 indices
// apart in the median at 0.2 s, 3918 at 0.9 s: benchmarks/README.md), so
// the DEM engine sorts its grains again every so often (dem_engine.hpp,
// DemEngine::sort_in_cell_order), as LAMMPS and LIGGGHTS do by default
// (atom_modify sort: every 1000 steps).
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"

namespace fdem {

/// The permutation (new position -> old index) that orders the particles by
/// the cell of a CellGrid of edge `cell_size_m` (cell_grid.hpp, the grid
/// the neighbour list searches): z-major, then y, then x, and by index
/// within a cell, so the order is a function of the positions alone.
std::vector<Index> cell_order(const Particles& p, double cell_size_m);

}  // namespace fdem

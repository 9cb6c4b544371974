#include "fluid/fluid_system_size.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/box_mesh_size.hpp"

namespace fdem {

FluidSystemSize fluid_system_size(const std::array<int, 3>& cells, int ilut_fill_factor) {
  const BoxMeshSize mesh = box_mesh_size(cells);
  FluidSystemSize s;
  s.rows = 4 * mesh.nodes;
  s.nonzeros = 16 * mesh.coupled_node_pairs();
  s.factor_nonzeros = std::max(1, ilut_fill_factor) * s.nonzeros;
  return s;
}

void require_indexable_fluid_system(const std::array<int, 3>& cells, int ilut_fill_factor, const std::string& file) {
  const FluidSystemSize s = fluid_system_size(cells, ilut_fill_factor);
  if (s.factor_nonzeros <= kMaxSparseEntries) return;
  throw InputError(
      file, "mesh.cells", fmt::format("[{}, {}, {}]", cells[0], cells[1], cells[2]),
      fmt::format("the fluid system would have {} rows and {} non-zeros, its ILUT factors up to {} (fill factor {}): "
                  "above the {} entries a 32-bit sparse index can address; use fewer cells (at most about {:.3g} "
                  "cells in all)",
                  s.rows, s.nonzeros, s.factor_nonzeros, std::max(1, ilut_fill_factor), kMaxSparseEntries,
                  static_cast<double>(box_mesh_size(cells).cells) * static_cast<double>(kMaxSparseEntries) /
                      static_cast<double>(s.factor_nonzeros)));
}

}  // namespace fdem

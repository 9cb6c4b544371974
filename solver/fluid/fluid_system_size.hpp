#pragma once
// Size of the fluid's linear system from the mesh's cell counts, in 64 bits,
// and the refusal of a mesh whose system the sparse matrices cannot index.
// FluidSolver stores the system (4 unknowns u, v, w, p per node, 4 x 4 blocks
// per coupled node pair) in Eigen sparse matrices with a 32-bit StorageIndex,
// so the row offsets, and the ILUT factors (up to fill_factor times the
// system's non-zeros), must stay below 2^31.
#include <array>
#include <cstdint>
#include <string>

namespace fdem {

struct FluidSystemSize {
  std::int64_t rows = 0;       // 4 per node
  std::int64_t nonzeros = 0;   // 16 per coupled node pair
  std::int64_t factor_nonzeros = 0;  // bound on the ILUT factors: fill_factor x nonzeros
};

/// `ilut_fill_factor` as in FluidSolverOptions (at least 1 is counted).
FluidSystemSize fluid_system_size(const std::array<int, 3>& cells, int ilut_fill_factor);

/// The largest count a 32-bit sparse index can address.
inline constexpr std::int64_t kMaxSparseEntries = 2147483647;

/// Throws InputError (file, key `mesh.cells`, the counts) when the system or
/// its factors exceed kMaxSparseEntries. Call it before building anything.
void require_indexable_fluid_system(const std::array<int, 3>& cells, int ilut_fill_factor, const std::string& file);

}  // namespace fdem

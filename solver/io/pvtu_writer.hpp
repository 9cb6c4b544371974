#pragma once
// VTK XML parallel unstructured grids (.pvtu): one snapshot written as
// pieces, one .vtu per MPI rank, and the small index file naming them that
// ParaView opens as one dataset (a .pvd lists the .pvtu like any .vtu). The
// index declares the pieces' arrays (VTK's PUnstructuredGrid: PPointData,
// PPoints), so every piece must hold the same ones (vtu_writer.hpp,
// ParticleArrays). Written atomically (io/atomic_file.hpp), and only after
// every piece is complete, so it never names a missing or partial piece.
#include <span>
#include <string>

#include "io/vtu_writer.hpp"

namespace fdem {

/// The piece of snapshot `base` (e.g. "particles_000003") that rank `rank`
/// writes: "particles_000003_rank0001.vtu".
std::string piece_file_name(const std::string& base, int rank);

/// The .pvtu of a particles snapshot whose pieces (names relative to the
/// .pvtu's folder) each hold `arrays`.
std::string particles_pvtu(ParticleArrays arrays, std::span<const std::string> piece_files);
void write_particles_pvtu(const std::string& path, ParticleArrays arrays, std::span<const std::string> piece_files);

}  // namespace fdem

#pragma once
// The grains one MPI rank writes to its VTU piece and counts in the probes.
// While every rank holds and steps every grain (the replicated state), a
// rank owns those whose centre lies in its slab (parallel/slab_partition.hpp,
// the partition the DEM decomposition uses): over the ranks every grain is
// then written and counted exactly once. A run whose ranks hold only their
// own grains owns them all.
#include <cstddef>
#include <span>
#include <vector>

#include "core/particles.hpp"
#include "parallel/slab_partition.hpp"

namespace fdem {

/// Indices of the grains of `particles` whose centre `slabs` gives to `rank`, ascending.
std::vector<std::size_t> owned_indices(const Particles& particles, const SlabPartition& slabs, int rank);

/// The grains at `indices`, every array that is filled for all of `particles`
/// (rotation, id, forces) copied with them.
Particles particle_subset(const Particles& particles, std::span<const std::size_t> indices);

}  // namespace fdem

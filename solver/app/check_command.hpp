#pragma once
// `fdem check SCENE`: load and validate a scene, then print the numbers a user
// needs before a long run (mesh and particle counts, contact times and the
// stable DEM step, step ratios, cell-to-particle ratio, memory estimate).
#include <cstdio>
#include <string>

#include "dem/particles.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// Prints the derived numbers of `scene` (with its generated `particles`) to
/// `out`; throws InputError when the DEM step is unstable and the scene does
/// not set contact.allow_unstable_step (after printing the table).
void print_scene_check(const Scene& scene, const Particles& particles, std::FILE* out);

/// Rough peak memory of a run [bytes]: particle arrays, neighbour lists,
/// mesh, fluid unknowns and the sparse system (pattern from the mesh's edges).
struct MemoryEstimate {
  double particles_bytes = 0.0;
  double fluid_bytes = 0.0;
  double total() const { return particles_bytes + fluid_bytes; }
};
MemoryEstimate estimate_memory(const Scene& scene, std::size_t particle_count);

/// Refuses (InputError) a scene too large to index (fluid/fluid_system_size.hpp),
/// from its counts alone: `check` and `run` call it before building anything.
void require_runnable_size(const Scene& scene);

/// The whole command: exit code 0 (errors are thrown to main).
int run_check_command(const std::string& scene_path, std::FILE* out);

}  // namespace fdem

#pragma once
// `fdem check SCENE`: load and validate a scene, then print the numbers a user
// needs before a long run (mesh and particle counts, contact times and the
// stable DEM step, step ratios, cell-to-particle ratio, memory estimate).
#include <cstdio>
#include <string>

#include "core/particles.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// Prints the derived numbers of `scene` (with its generated `particles`) to
/// `out`; throws InputError when the DEM step is unstable and the scene does
/// not set contact.allow_unstable_step (after printing the table).
void print_scene_check(const Scene& scene, const Particles& particles, std::FILE* out);
/// The same when `particles` holds fewer than the scene's `particle_count`
/// (not drawn, see kMostParticlesDrawnByCheck): the distributions' bounds are printed.
void print_scene_check(const Scene& scene, const Particles& particles, std::size_t particle_count, std::FILE* out);

/// `check` draws the grains (for their statistics) only up to this many.
inline constexpr std::size_t kMostParticlesDrawnByCheck = 2000000;

/// The scene's particle count from its sets alone (lattice product, random
/// count, CSV rows), without drawing any.
std::size_t count_particles(const ParticleSet& set);
std::size_t count_particles(const Scene& scene);

/// Peak resident memory of `fdem run` [bytes]: particle arrays and
/// neighbour lists, the fluid system with its ILUT factors, mesh and fields,
/// the largest output buffer (VTU or checkpoint), the process itself.
struct MemoryEstimate {
  double particles_bytes = 0.0;
  double fluid_bytes = 0.0;
  double output_bytes = 0.0;
  double process_bytes = 0.0;
  double total() const { return particles_bytes + fluid_bytes + output_bytes + process_bytes; }
};
MemoryEstimate estimate_memory(const Scene& scene, std::size_t particle_count);

/// Memory this process may still take [bytes]: MemAvailable, or less under a
/// cgroup (v2) limit or the environment's FDEM_MEMORY_LIMIT_MIB.
double available_memory_bytes();

/// Refuses (InputError) a scene whose estimate exceeds available_memory_bytes(),
/// unless `ignore_limit`; counts only, nothing is allocated.
void require_memory_fits(const Scene& scene, bool ignore_limit);

/// Refuses (InputError) a scene too large to index (fluid/fluid_system_size.hpp),
/// from its counts alone: `check` and `run` call it before building anything.
void require_runnable_size(const Scene& scene);

/// The whole command: exit code 0 (errors are thrown to main).
int run_check_command(const std::string& scene_path, std::FILE* out, bool ignore_memory_limit = false);

}  // namespace fdem

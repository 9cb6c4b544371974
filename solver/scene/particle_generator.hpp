#pragma once
// Initial particles from a scene's particle sets, in the order the sets are
// listed. Deterministic: each set draws from its own std::mt19937_64 seeded
// with the set's `seed`, so the same scene gives the same particles, bit for
// bit, on every run and thread count.
#include <cstdint>
#include <random>

#include "core/particles.hpp"
#include "scene/scene.hpp"

namespace fdem {

/// Fills x, y, z, vx, vy, vz, diameter, mass (from the set's density, or the
/// csv's rho) and zero forces. Rotation arrays stay empty: the DEM engine
/// sizes them when the rotation effect is on.
///   single   one particle at `position`
///   lattice  n_x x n_y x n_z sites at the centres of equal sub-boxes of the
///            region, x fastest then y then z (the anchors' gen_scenes.py
///            scene P order); one diameter drawn per site in that order
///   random   `count` non-overlapping spheres, centres uniform in the region
///            shrunk by the radius; each particle draws its diameter, then
///            positions until one does not overlap (InputError if the region
///            cannot hold them after a bounded number of tries)
///   csv      the rows of the file, in file order
Particles generate_particles(const Scene& scene);

/// Appends one set's particles (used by generate_particles).
void append_particle_set(const Scene& scene, std::size_t set_index, Particles& particles);

/// Uniform double in [0, 1) from the top 53 bits (the same on every platform,
/// unlike std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng);

/// One diameter from the distribution. Normal: Box-Muller, redrawn until it
/// lies in [minimum, maximum] (truncation by rejection; the loader refuses
/// bounds that accept less than 1e-3 of the distribution).
double draw_diameter(const SizeDistribution& size, std::mt19937_64& rng);

}  // namespace fdem

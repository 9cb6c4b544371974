#include "scene/particle_generator.hpp"

#include <cmath>
#include <unordered_map>

#include <fmt/format.h>

#include "core/error.hpp"
#include "scene/particle_csv.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {

namespace {

void push(Particles& p, const Vec3& position, const Vec3& velocity, double diameter, double density) {
  p.x.push_back(position.x());
  p.y.push_back(position.y());
  p.z.push_back(position.z());
  p.vx.push_back(velocity.x());
  p.vy.push_back(velocity.y());
  p.vz.push_back(velocity.z());
  p.fx.push_back(0.0);
  p.fy.push_back(0.0);
  p.fz.push_back(0.0);
  p.diameter.push_back(diameter);
  p.mass.push_back(density * sphere_volume(diameter));
}

// Hash grid of placed spheres for the overlap test of random placement. Cells
// are at least the largest diameter wide, so any overlapping pair sits in
// neighbouring cells.
class PlacementGrid {
 public:
  PlacementGrid(const Box& region, double cell) : lower_(region.lower), cell_(cell) {}

  bool overlaps(const Vec3& c, double d, const Particles& p) const {
    const auto [i, j, k] = cell_of(c);
    for (long long a = i - 1; a <= i + 1; ++a) {
      for (long long b = j - 1; b <= j + 1; ++b) {
        for (long long e = k - 1; e <= k + 1; ++e) {
          const auto it = cells_.find(key(a, b, e));
          if (it == cells_.end()) continue;
          for (std::size_t n : it->second) {
            const Vec3 other(p.x[n], p.y[n], p.z[n]);
            const double contact = 0.5 * (d + p.diameter[n]);
            if ((c - other).squaredNorm() < contact * contact) return true;
          }
        }
      }
    }
    return false;
  }
  void insert(const Vec3& c, std::size_t n) {
    const auto [i, j, k] = cell_of(c);
    cells_[key(i, j, k)].push_back(n);
  }

 private:
  std::array<long long, 3> cell_of(const Vec3& c) const {
    return {static_cast<long long>(std::floor((c.x() - lower_.x()) / cell_)),
            static_cast<long long>(std::floor((c.y() - lower_.y()) / cell_)),
            static_cast<long long>(std::floor((c.z() - lower_.z()) / cell_))};
  }
  static std::uint64_t key(long long i, long long j, long long k) {
    // 21 bits per axis (offset so -1 stays positive): regions up to 2e6 cells a side.
    const auto u = [](long long v) { return static_cast<std::uint64_t>(v + 1) & 0x1FFFFFu; };
    return u(i) | (u(j) << 21) | (u(k) << 42);
  }
  Vec3 lower_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

void append_lattice(const ParticleSet& set, std::mt19937_64& rng, Particles& p) {
  const Vec3 extent = set.region.upper - set.region.lower;
  const Vec3 spacing(extent.x() / set.lattice[0], extent.y() / set.lattice[1], extent.z() / set.lattice[2]);
  // gen_scenes.py scene P: k outer, j, i inner; site = lower + (i + 0.5) * spacing.
  for (int k = 0; k < set.lattice[2]; ++k) {
    for (int j = 0; j < set.lattice[1]; ++j) {
      for (int i = 0; i < set.lattice[0]; ++i) {
        const double d = draw_diameter(set.size, rng);
        const Vec3 site(set.region.lower.x() + (i + 0.5) * spacing.x(), set.region.lower.y() + (j + 0.5) * spacing.y(),
                        set.region.lower.z() + (k + 0.5) * spacing.z());
        push(p, site, set.velocity, d, set.density);
      }
    }
  }
}

void append_random(const Scene& scene, std::size_t set_index, std::mt19937_64& rng, Particles& p) {
  const ParticleSet& set = scene.particles[set_index];
  const double d_max = largest_diameter(set.size);
  const Vec3 extent = set.region.upper - set.region.lower;
  // Cells no finer than d_max (overlap test) and no more than ~8 per particle (memory).
  const double cell = std::max(d_max, std::cbrt(extent.prod() / (8.0 * set.count)));
  PlacementGrid grid(set.region, cell);
  // Bounded: on average 1000 tries per particle before the region is called full.
  const long long max_tries = 1000LL * set.count + 10000;
  long long tries = 0;
  for (int n = 0; n < set.count; ++n) {
    const double d = draw_diameter(set.size, rng);
    const double r = 0.5 * d;
    while (true) {
      if (++tries > max_tries) {
        throw InputError(scene.source_file, fmt::format("particles[{}].count", set_index), std::to_string(set.count),
                         fmt::format("random placement found room for only {} non-overlapping particles in the region; "
                                     "enlarge the region or lower the count",
                                     n));
      }
      Vec3 c;
      for (int a = 0; a < 3; ++a) c[a] = set.region.lower[a] + r + uniform01(rng) * (extent[a] - d);
      if (grid.overlaps(c, d, p)) continue;
      grid.insert(c, p.size());
      push(p, c, set.velocity, d, set.density);
      break;
    }
  }
}

}  // namespace

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double draw_diameter(const SizeDistribution& size, std::mt19937_64& rng) {
  switch (size.kind) {
    case SizeKind::fixed:
      return size.diameter;
    case SizeKind::uniform:
      return size.minimum + (size.maximum - size.minimum) * uniform01(rng);
    case SizeKind::normal:
      while (true) {
        // Box-Muller (cosine branch only, as the anchors' gen_scenes.py), then rejection.
        const double u1 = uniform01(rng);
        const double u2 = uniform01(rng);
        if (u1 <= 0.0) continue;
        const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * pi * u2);
        const double d = size.mean + size.sd * z;
        if (d >= size.minimum && d <= size.maximum) return d;
      }
  }
  return size.diameter;
}

void append_particle_set(const Scene& scene, std::size_t set_index, Particles& p) {
  const ParticleSet& set = scene.particles.at(set_index);
  std::mt19937_64 rng(set.seed);
  switch (set.placement) {
    case PlacementKind::single:
      push(p, set.position, set.velocity, draw_diameter(set.size, rng), set.density);
      break;
    case PlacementKind::lattice:
      append_lattice(set, rng, p);
      break;
    case PlacementKind::random:
      append_random(scene, set_index, rng, p);
      break;
    case PlacementKind::csv:
      for (const auto& r : read_particle_csv(set.csv_file)) {
        push(p, r.position, r.has_velocity ? r.velocity : set.velocity, r.diameter, r.density);
      }
      break;
  }
}

Particles generate_particles(const Scene& scene) {
  Particles p;
  for (std::size_t s = 0; s < scene.particles.size(); ++s) append_particle_set(scene, s, p);
  return p;
}

}  // namespace fdem
